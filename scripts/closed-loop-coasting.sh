#!/bin/bash
# Coasting in a closed loop (coast_tau_s; predictors/.../channel_predictor.h coastTauParam;
# docs/PERFORMANCE.md "Coasting in a closed loop"): every predictor that coasts, at its defaults
# (told closed_loop: 1 by compare, so coast_tau_s 0.5 s) and with coast_tau_s TAU (default 0.2, the
# open loop's), in one `predvs compare` run per grid, so on the same seeds. Grids: ibvs-moving-target
# with one occlusion of 0.2, 0.5, 1 and 2 s at 12 s over 60 / 25 Hz, 0.5 / 2 px and a target 1x / 3x
# as fast (8 cells each); ibvs-rendered-dots through its geometric twin (0.038 and 0.5 px; a 0.5 s
# occlusion); e8-vtc-occlusion (3 s, the loop told to extrapolate). Prints per grid and predictor the
# geometric mean (min-max) of rmse(default) / rmse(TAU), and the cells over 5 % worse.
#
#   scripts/closed-loop-coasting.sh [-r RUNS] [-o OUT] [-t TAU] BIN
#
# RUNS: runs per cell (default 5); OUT: where the leaderboards go (default /tmp/closed-loop-coasting).
set -euo pipefail

runs=5
out=/tmp/closed-loop-coasting
tau=0.2
usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "r:o:t:h" opt; do
  case $opt in
    r) runs=$OPTARG ;;
    o) out=$OPTARG ;;
    t) tau=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -eq 1 ] || usage
bin=$1
[ -x "$bin" ] || { echo "closed-loop-coasting: error: $bin is not an executable" >&2; exit 2; }

filters="kf-cv kf-ca cs-akf-adaptive stkf st-akf fakf-classic fakf imm"
list="hold"
for f in $filters; do list="$list, $f, {name: $f-tau, type: $f, params: {coast_tau_s: $tau}}"; done
mkdir -p "$out"
script=closed-loop-coasting
. "$(dirname "$0")/lib/compare-grid.sh"
occlusion_grids 0.2 0.5 1 2

python3 - "$out" "$filters" <<'PY'
import csv, math, os, sys
out, filters = sys.argv[1], sys.argv[2].split()
grids = ["occlusion-0.2", "occlusion-0.5", "occlusion-1", "occlusion-2", "rendered-twin", "e8-vtc-occlusion"]
gm = lambda xs: math.exp(sum(map(math.log, xs)) / len(xs))
print(f"{'grid':17s} {'all: gmean':>10s} {'max':>6s} {'worse':>7s} | per predictor: gmean (min-max)")
for g in grids:
    t = {}
    with open(os.path.join(out, g, "leaderboard.csv")) as f:
        for row in csv.DictReader(f):
            if row["metric"] == "rmse":
                t[(row["variant"], row["predictor"])] = float(row["mean"])
    cells = sorted({v for (v, p) in t})
    every, parts = [], []
    for p in filters:
        r = [t[(v, p)] / t[(v, p + "-tau")] for v in cells]
        every += r
        parts.append(f"{p} {gm(r):.2f} ({min(r):.2f}-{max(r):.2f})")
    worse = sum(1 for x in every if x > 1.05)
    print(f"{g:17s} {gm(every):10.3f} {max(every):6.3f} {f'{worse}/{len(every)}':>7s} | " + ", ".join(parts))
PY
