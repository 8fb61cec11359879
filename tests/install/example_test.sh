#!/usr/bin/env bash
# CTest example_against_install: configures and builds examples/predictor_ahead_of_vpservo as a
# separate project against the prefix installed by install_prefix, runs it, and checks that kf-cv
# ahead of the vpServo loop lowers the steady-state image error at least 4-fold.
# Usage: example_test.sh CMAKE PREFIX SOURCE_DIR WORK_DIR [COMPILER_LAUNCHER]
set -euo pipefail
cmake_cmd=$1 prefix=$2 src=$3 work=$4 launcher=${5:-}
fail() { echo "example_test: $*" >&2; exit 1; }
rm -rf "$work"
args=(-S "$src/examples/predictor_ahead_of_vpservo" -B "$work" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release)
[ -n "$launcher" ] && args+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$launcher")
"$cmake_cmd" "${args[@]}" > "$work.configure.log" 2>&1 || { cat "$work.configure.log"; fail "configure failed"; }
"$cmake_cmd" --build "$work" > "$work.build.log" 2>&1 || { cat "$work.build.log"; fail "build failed"; }
out=$("$work/predictor_ahead_of_vpservo" kf-cv 2>/dev/null) || fail "the example exited non-zero"
echo "$out"
without=$(echo "$out" | sed -n 's/.*without predictor: \([0-9.]*\) px/\1/p')
with=$(echo "$out" | sed -n 's/.*with kf-cv: \([0-9.]*\) px/\1/p')
[ -n "$without" ] && [ -n "$with" ] || fail "unexpected output"
awk -v a="$with" -v b="$without" 'BEGIN { exit !(a > 0 && 4 * a < b) }' || fail "kf-cv error $with px not 4x below $without px"
if "$work/predictor_ahead_of_vpservo" no-such-predictor >/dev/null 2>&1; then fail "unknown predictor accepted"; fi
if "$work/predictor_ahead_of_vpservo" kf-cv q=x >/dev/null 2>&1; then fail "a bad KEY=VALUE accepted"; fi
out=$("$work/predictor_ahead_of_vpservo" kf-cv q=400 r=0.25 2>/dev/null) || fail "kf-cv q=400 r=0.25 exited non-zero"
echo "$out" | grep -q "with kf-cv: " || fail "parameters on the command line: unexpected output: $out"
echo "example_test: OK"
