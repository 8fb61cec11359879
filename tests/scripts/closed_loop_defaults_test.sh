#!/bin/bash
# scripts/closed-loop-defaults.sh (docs/PERFORMANCE.md "The feed-forward's velocity"): one seed of
# e5-line with every predictor at its defaults, by the same binary twice. Every predictor has a row
# with two equal figures, and every predictor but hold feeds the leader's velocity forward (more
# than 3x closer than hold; 7.1x (stkf) to 8.4x at this seed, 1.3-7.8x before the whitening and the
# unweighted feed-forward velocity); -p runs the list given (without hold, the rmse and '-' for the
# ratio). A path that is not an executable is an error
# with exit status 2.
#   closed_loop_defaults_test.sh PREDVS OUT
set -euo pipefail
. "$(dirname "$0")/script_test.sh"
predvs=$1
out=$2
script=$(dirname "$0")/../../scripts/closed-loop-defaults.sh
rm -rf "$out"
table=$(bash "$script" -r 1 -s e5-line -o "$out" "$predvs" "$predvs" 2>/dev/null)
echo "$table"
for p in hold kf-cv kf-ca cs-akf cs-akf-adaptive stkf st-akf st-akf-pm fakf-classic fakf imm; do
  row=$(echo "$table" | awk -v p="$p" '$1 == "e5-line" && $2 == p')
  [ -n "$row" ] || { echo "FAIL: no row for $p" >&2; exit 1; }
  echo "$row" | awk '{ if ($3 != $5) exit 1 }' || { echo "FAIL: $p differs between two runs of one binary: $row" >&2; exit 1; }
done
for p in kf-cv kf-ca cs-akf cs-akf-adaptive stkf st-akf st-akf-pm fakf-classic fakf imm; do
  echo "$table" | awk -v p="$p" '$1 == "e5-line" && $2 == p { r = $4; sub("x", "", r); exit !(r + 0 > 3) }' ||
    { echo "FAIL: $p is not 3x closer than hold on e5-line" >&2; exit 1; }
done
# -p: the list given instead of every predictor
rows=$(bash "$script" -r 1 -s e5-line -o "$out/p" -p "hold, {name: cv-auto, type: kf-cv, params: {q: auto}}" "$predvs" 2>/dev/null |
  awk '$1 == "e5-line" { print $2 }' | sort | paste -sd' ')
[ "$rows" = "cv-auto hold" ] || { echo "FAIL: -p gave the rows '$rows'" >&2; exit 1; }
# -p without hold: the rmse alone, '-' for the ratio to hold
row=$(bash "$script" -r 1 -s e5-line -o "$out/nohold" -p "kf-cv" "$predvs" 2>/dev/null | awk '$1 == "e5-line"')
echo "$row" | awk '{ exit !($2 == "kf-cv" && $3 + 0 > 0 && $4 == "-") }' || { echo "FAIL: -p kf-cv gave '$row'" >&2; exit 1; }
refuses_a_missing_binary "$script" "$out"
echo "closed_loop_defaults_test: OK"
