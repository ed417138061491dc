# Assertions of the command-line tests, sourced by cli_test.sh and gltf_cli_test.sh. Each
# counts a failure in $failures (set by the caller) and goes on.

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_ok NAME REGEX CMD...: exit 0 and stdout+stderr matching REGEX (extended grep).
expect_ok() {
  local name=$1 regex=$2; shift 2
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "$name: exit $rc: $out"; return; fi
  if ! grep -Eq -- "$regex" <<<"$out"; then fail "$name: output does not match /$regex/:"$'\n'"$out"; fi
}

# expect_fail CODE NAME REGEX CMD...: exit status CODE and one line "isoforge: error: ...REGEX".
expect_fail() {
  local code=$1 name=$2 regex=$3; shift 3
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ $rc -ne "$code" ]; then fail "$name: expected exit $code, got $rc: $out"; return; fi
  if [ "$(wc -l <<<"$out")" -ne 1 ]; then fail "$name: error is not one line:"$'\n'"$out"; fi
  if ! grep -Eq -- "^isoforge: error: .*$regex" <<<"$out"; then fail "$name: message does not match /$regex/: $out"; fi
}
# expect_error NAME REGEX CMD...: the work failed (exit 1), one line naming the problem.
expect_error() { expect_fail 1 "$@"; }
# expect_usage NAME REGEX CMD...: the command line is wrong (exit 2), one line naming the problem.
expect_usage() { expect_fail 2 "$@"; }
