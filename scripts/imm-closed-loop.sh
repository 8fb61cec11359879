#!/bin/bash
# imm in a closed loop, at its defaults against imm with other parameters PARAMS (default
# `ff_weight_tau_s: 1`, the feed-forward weights' low-pass before; predictors/.../imm.h;
# docs/PERFORMANCE.md "imm's feed-forward weights over two seconds" and "imm's raise on its CA mode's
# own innovation"), beside kf-cv and kf-ca, in one `predvs compare` run per grid, so on the same
# seeds. Grids: the 24 closed-loop scenario cells and 12 held-out variants of
# closed-loop-white-target.sh; 18 variants of the two loops without vision delay (e8-ibvs and e8-vtc
# over 1 / 2 / 5 px and 30 / 20 / 10 Hz; 5 px at 10 Hz are the scenarios themselves); and the
# occlusion grids of closed-loop-coasting.sh (ibvs-moving-target with one occlusion of 0.5 and 2 s,
# 8 cells each; the rendered twin; e8-vtc-occlusion). Prints per grid the geometric mean (min-max)
# of rmse(imm) / rmse(imm with PARAMS), and for both the item-4 criterion: the cells where imm is
# over 1.1 times the better of kf-cv and kf-ca.
#
#   scripts/imm-closed-loop.sh [-r RUNS] [-o OUT] [-p 'KEY: VALUE, ...'] BIN
#
# RUNS: runs per cell (default 10); OUT: where the leaderboards go (default /tmp/imm-closed-loop).
set -euo pipefail

runs=10
out=/tmp/imm-closed-loop
params="ff_weight_tau_s: 1"
usage() { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "r:o:p:h" opt; do
  case $opt in
    r) runs=$OPTARG ;;
    o) out=$OPTARG ;;
    p) params=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -eq 1 ] || usage
bin=$1
[ -x "$bin" ] || { echo "imm-closed-loop: error: $bin is not an executable" >&2; exit 2; }

list="kf-cv, kf-ca, imm, {name: imm-other, type: imm, params: {$params}}"
mkdir -p "$out"
script=imm-closed-loop
. "$(dirname "$0")/lib/compare-grid.sh"
closed_loop_grids
compare_grid e8-variants --scenarios e8-ibvs,e8-vtc --sweep noise.sigma=1,2,5 --sweep timing.base_period_s=0.0333,0.05,0.1
occlusion_grids 0.5 2

python3 - "$out" "$params" <<'PY'
import csv, math, os, sys
out, params = sys.argv[1], sys.argv[2]
grids = ["scenarios", "held-out", "e8-variants", "occlusion-0.5", "occlusion-2", "rendered-twin", "e8-vtc-occlusion"]
gm = lambda xs: math.exp(sum(map(math.log, xs)) / len(xs))
print(f"{'grid':17s} {'cells':>5s} {'imm / imm-other: gmean (min-max)':>33s} | imm over 1.1 x min(kf-cv, kf-ca): default; {{{params}}}")
for g in grids:
    t = {}
    with open(os.path.join(out, g, "leaderboard.csv")) as f:
        for row in csv.DictReader(f):
            if row["metric"] == "rmse":
                t[(row["variant"], row["predictor"])] = float(row["mean"])
    cells = sorted({v for (v, p) in t})
    r = [t[(v, "imm")] / t[(v, "imm-other")] for v in cells]
    over = lambda p: [f"{v} {t[(v, p)] / min(t[(v, 'kf-cv')], t[(v, 'kf-ca')]):.2f}" for v in cells
                      if t[(v, p)] > 1.1 * min(t[(v, "kf-cv")], t[(v, "kf-ca")])]
    a, b = over("imm"), over("imm-other")
    print(f"{g:17s} {len(cells):5d} {gm(r):15.3f} ({min(r):.3f}-{max(r):.3f}) | {len(a)}{': ' + ', '.join(a) if a else ''}; "
          f"{len(b)}{': ' + ', '.join(b) if b else ''}")
PY
