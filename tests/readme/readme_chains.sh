#!/usr/bin/env bash
# Runs every chain of README.md, so that the README cannot drift from what
# ships: each ```sh block whose first line is "# chain: NAME" runs whole
# (bash -e: every command must succeed) in a fresh folder that holds links
# to the source's testdata/ and examples/, with the build's bead on PATH,
# libbead.so as BEAD_LIBRARY and the Python module on PYTHONPATH, as an
# installed tree gives them.
#   readme_chains.sh SOURCE_DIR BEAD_CLI BEAD_LIBRARY PYTHON_MODULE_DIR WORK_DIR
set -euo pipefail
src=$(realpath "$1") cli=$(realpath "$2") lib=$(realpath "$3") pydir=$(realpath "$4") work=$5
rm -rf "$work"
mkdir -p "$work/bin"
ln -s "$cli" "$work/bin/bead"
# The Python the module is built for (Debian's, with NumPy).
ln -s /usr/bin/python3 "$work/bin/python3"
export PATH="$work/bin:$PATH" BEAD_LIBRARY="$lib" PYTHONPATH="$pydir"

# Each chain into chain-K.sh, its name in chain-K.name.
awk -v dir="$work" '
  /^```sh$/ { inblock = 1; first = 1; next }
  /^```$/ && inblock { inblock = 0; if (file != "") close(file); file = ""; next }
  inblock && first {
    first = 0
    if ($0 ~ /^# chain: /) {
      k++; file = dir "/chain-" k ".sh"
      name = substr($0, 10); print name > (dir "/chain-" k ".name"); close(dir "/chain-" k ".name")
    }
  }
  inblock && file != "" { print > file }
' "$src/README.md"

failed=0 count=0
for chain in "$work"/chain-*.sh; do
  [ -e "$chain" ] || break
  count=$((count + 1))
  k=$(basename "$chain" .sh)
  name=$(cat "$work/$k.name")
  run="$work/$k"
  mkdir -p "$run"
  ln -s "$src/testdata" "$run/testdata"
  ln -s "$src/examples" "$run/examples"
  start=$SECONDS
  if (cd "$run" && bash -e -o pipefail "$chain") >"$run.log" 2>&1; then
    echo "ok     $name ($((SECONDS - start)) s)"
  else
    echo "FAILED $name: the README's commands, as run:"
    sed 's/^/  | /' "$chain"
    echo "  output:"
    tail -n 30 "$run.log" | sed 's/^/  > /'
    failed=1
  fi
done
if [ "$count" -eq 0 ]; then
  echo "no '# chain:' block found in $src/README.md" >&2
  exit 1
fi
exit "$failed"
