#!/usr/bin/env bash
# Every example of the documentation is run as written, so that none can rot:
# - the examples of every subcommand's --help footer (the subcommands listed by `isoforge
#   --help`), each footer in a fresh directory, in order (a later example may use an earlier
#   one's output, as a reader following the footer would);
# - every command of README.md's ```sh blocks, all in one directory, in order, except `make`
#   lines (the repository's own build targets).
# Each directory holds `data`, a link to the repository's data/, so the examples run as they do
# from the repository root. An example must exit 0 and must not warn (an example whose result is
# empty would be a bad example).
# Usage: examples_test.sh ISOFORGE DATA_DIR README.md SCRATCH_DIR
set -u
bin=$(realpath "$1") data=$(realpath "$2") readme=$(realpath "$3") tmp=$(realpath -m "$4")
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0 ran=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# The examples call `isoforge`: this build of it.
isoforge() { "$bin" "$@"; }

# run DIR LINE: runs LINE in DIR through the shell, as a reader would paste it.
run() {
  local dir=$1 line=$2 out rc
  ran=$((ran + 1))
  out=$(cd "$dir" && eval "$line" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "in $dir: $line"$'\n'"  exit $rc: $out"; return; fi
  if grep -q "isoforge: warning" <<<"$out"; then fail "in $dir: $line"$'\n'"  warns: $out"; fi
}

scratch() {
  mkdir -p "$1" && ln -s "$data" "$1/data"
}

# ---- every --help footer ----
subcommands=$("$bin" --help | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 }')
[ -n "$subcommands" ] || fail "isoforge --help lists no subcommands"
for sub in $subcommands; do
  # The lines after "Examples:" that start with "  isoforge ", joined with their continuation
  # lines (after a trailing backslash), without a trailing note "   (...)".
  examples=$("$bin" "$sub" --help | awk '
    function flush() { if (cmd != "") { sub(/  +\(.*\) *$/, "", cmd); print cmd }; cmd = "" }
    /^Examples:/ { on = 1; next }
    !on { next }
    cont { sub(/^ +/, ""); cmd = cmd " " $0; cont = sub(/ *\\$/, "", cmd); next }
    /^  isoforge / { flush(); cmd = substr($0, 3); cont = sub(/ *\\$/, "", cmd); next }
    { flush() }
    END { flush() }')
  if [ -z "$examples" ]; then fail "isoforge $sub --help has no examples"; continue; fi
  dir="$tmp/help_$sub"
  scratch "$dir"
  while IFS= read -r line; do run "$dir" "$line"; done <<<"$examples"
done

# ---- every command of README.md's sh blocks ----
dir="$tmp/readme"
scratch "$dir"
commands=$(awk '/^```sh *$/ { on = 1; next } /^```/ { on = 0 } on && NF' "$readme" | grep -v '^make ')
[ -n "$commands" ] || fail "README.md has no sh commands"
while IFS= read -r line; do run "$dir" "$line"; done <<<"$commands"

if [ $failures -ne 0 ]; then echo "$failures of $ran examples failed"; exit 1; fi
rm -rf "$tmp"  # the outputs are big; keep them only to look into a failure
echo "all $ran examples ran"
