# bash completion for bead (installed as PREFIX/share/bash-completion/completions/bead).
# The subcommands and their options are read from bead's own --help, so
# completion never drifts from the tool: `bead <TAB>` gives the
# subcommands, `bead measure --<TAB>` its options, `bead calibrate <TAB>`
# what it calibrates; anything else completes file names.
_bead_words_after() {
  # The first column of the lines under the heading "$2" of help text "$1".
  printf '%s\n' "$1" | awk -v head="$2" '
    $0 == head { on = 1; next }
    on && /^  [a-z]/ { print $1; next }
    on && !/^  / { on = 0 }'
}

_bead() {
  local cur=${COMP_WORDS[COMP_CWORD]} cmd=() i
  for ((i = 1; i < COMP_CWORD; i++)); do
    case ${COMP_WORDS[i]} in -*) ;; *) cmd+=("${COMP_WORDS[i]}") ;; esac
  done
  local help
  help=$("${COMP_WORDS[0]}" "${cmd[@]:0:2}" --help 2>/dev/null) || return 0
  local subs
  subs=$(_bead_words_after "$help" "Subcommands:")
  if [[ $cur == -* ]]; then
    local opts
    opts=$(printf '%s\n' "$help" | grep -oE '(^|[ ,])--?[A-Za-z][A-Za-z0-9-]*' | tr -d ' ,' | sort -u)
    COMPREPLY=($(compgen -W "$opts" -- "$cur"))
  elif [ -n "$subs" ] && [ ${#cmd[@]} -lt 2 ]; then
    COMPREPLY=($(compgen -W "$subs" -- "$cur"))
  else
    COMPREPLY=($(compgen -f -- "$cur"))
  fi
}
complete -o filenames -F _bead bead
