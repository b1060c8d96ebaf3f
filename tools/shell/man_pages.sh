#!/usr/bin/env bash
# One man page per command, made from the same text as its --help (so the
# two cannot differ): bead.1 from `bead --help`, bead-<name>.1 from `bead
# <name> --help` (calibrate's page holds each of its subcommands' help).
#   man_pages.sh BEAD_CLI VERSION OUT_DIR
set -euo pipefail
cli=$1 version=$2 out=$3
mkdir -p "$out"
# Text as roff: a backslash doubled, a leading dot or quote escaped, each
# line kept as it is (no fill), in a fixed-width block.
roff() { sed -e 's/\\/\\e/g' -e "s/^\\([.']\\)/\\\\\\&\\1/"; }
page() {  # NAME SUMMARY HELP_TEXT
  {
    printf '.TH %s 1 "" "bead %s" "libbead"\n' "$(echo "$1" | tr a-z A-Z)" "$version"
    printf '.SH NAME\n%s \\- %s\n' "$1" "$2"
    printf '.SH DESCRIPTION\n.nf\n'
    printf '%s\n' "$3" | roff
    printf '.fi\n.SH SEE ALSO\nbead(1); the formats: PREFIX/share/doc/bead/data-formats.md\n'
  } >"$out/$1.1"
}
top=$("$cli" --help)
page bead "laser line profiles of extruded beads: geometry, flow, models and controllers" "$top"
printf '%s\n' "$top" | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print } on && !/^  / { on = 0 }' |
  while read -r name summary; do
    text=$("$cli" "$name" --help)
    subs=$(printf '%s\n' "$text" | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && !/^  / { on = 0 }')
    for s in $subs; do text+=$'\n\n'"$("$cli" "$name" "$s" --help)"; done
    page "bead-$name" "$summary" "$text"
  done
