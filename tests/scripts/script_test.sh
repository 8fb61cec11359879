# predvs — sourced by the shell tests of tests/scripts (the shell twin of script_test.py).
#
#   refuses_a_missing_binary SCRIPT OUT
#
# Runs SCRIPT with -o OUT/bad on /nonexistent/predvs and fails the test (exit 1, a FAIL line) unless it
# exits with status 2 and its error names the path.
refuses_a_missing_binary() {
  local script=$1 out=$2 status
  set +e
  bash "$script" -o "$out/bad" /nonexistent/predvs 2>"$out/bad.err"
  status=$?
  set -e
  [ "$status" -eq 2 ] || { echo "FAIL: a missing binary exits with $status, not 2" >&2; exit 1; }
  grep -q "/nonexistent/predvs is not an executable" "$out/bad.err" || { echo "FAIL: the error does not name the path" >&2; exit 1; }
}
