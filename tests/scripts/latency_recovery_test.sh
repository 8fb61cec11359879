#!/bin/bash
# scripts/latency-recovery.sh (docs/CALIBRATION.md "Recovery on simulated logs"): its ten rows, each
# with a true delay read from the log's stamps and both fits within one base period of it (the
# criterion tests/calibration/latency_estimation_test.cpp checks on its own runs). A path that is not
# an executable is an error with exit status 2.
#   latency_recovery_test.sh PREDVS OUT
set -euo pipefail
. "$(dirname "$0")/script_test.sh"
predvs=$1
out=$2
script=$(dirname "$0")/../../scripts/latency-recovery.sh
rm -rf "$out"
table=$(bash "$script" -o "$out/logs" "$predvs")
echo "$table"
# | 40 ms | 1 | 80 ms | hold, 0.5 | 69.8 +- 3.5 ms | 80.3 +- 6.5 ms |
echo "$table" | awk -F'|' 'NR > 2 {
    rows++; base = $2 + 0; truth = $4 + 0; split($6, p, " "); split($7, s, " ")
    if (p[1] == "" || s[1] == "" || (p[1] - truth) ^ 2 > base ^ 2 || (s[1] - truth) ^ 2 > base ^ 2) bad++
  } END { exit !(rows == 10 && bad == 0) }' ||
  { echo "FAIL: not ten rows each within one base period" >&2; exit 1; }
refuses_a_missing_binary "$script" "$out"
echo "latency_recovery_test: OK"
