#!/bin/bash
# scripts/imm-closed-loop.sh (docs/PERFORMANCE.md "imm's feed-forward weights over two seconds"): one
# seed per cell. With -p giving imm its own defaults the other imm is the same bits, so every grid's
# ratio is 1.000 (1.000-1.000) and no cell differs in the item-4 line; with the 1 s low-pass of
# before, the e8 variants (where the weights matter) differ. A path that is not an executable is an
# error with exit status 2.
#   imm_closed_loop_test.sh PREDVS OUT
set -euo pipefail
. "$(dirname "$0")/script_test.sh"
predvs=$1
out=$2
script=$(dirname "$0")/../../scripts/imm-closed-loop.sh
rm -rf "$out"
same=$(bash "$script" -r 1 -p "ff_weight_tau_s: 2" -o "$out/same" "$predvs" 2>/dev/null)
echo "$same"
for g in scenarios held-out e8-variants occlusion-0.5 occlusion-2 rendered-twin e8-vtc-occlusion; do
  echo "$same" | awk -v g="$g" '$1 == g { found = 1; ok = ($3 == "1.000" && $4 == "(1.000-1.000)") } END { exit !(found && ok) }' ||
    { echo "FAIL: imm against its own defaults is not 1.000 on $g" >&2; exit 1; }
done
other=$(bash "$script" -r 1 -p "ff_weight_tau_s: 1" -o "$out/other" "$predvs" 2>/dev/null)
echo "$other" | awk '$1 == "e8-variants" { exit ($4 == "(1.000-1.000)") }' ||
  { echo "FAIL: ff_weight_tau_s 1 changed nothing on the e8 variants" >&2; exit 1; }
refuses_a_missing_binary "$script" "$out"
echo "imm_closed_loop_test: OK"
