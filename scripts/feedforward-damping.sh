#!/bin/bash
# The damping of ibvs's feed-forward (task.feedforward_damping, tasks/include/predvs/tasks/ibvs_task.h;
# docs/PERFORMANCE.md "The feed-forward through a damped inverse"): every predictor with its defaults
# in the closed-loop scenarios that run the `ibvs` law on a moving target, once per damping, on the
# same seeds. Prints, per scenario cell and damping, over the predictors but hold: the geometric mean
# of rmse(damping) / rmse(0), the largest of that ratio, and the geometric mean of the control
# effort's ratio.
#
#   scripts/feedforward-damping.sh [-r RUNS] [-o OUT] [-s SCENARIOS] [-k DAMPINGS] BIN
#
# RUNS: runs per cell (default 10); OUT: where the leaderboards go (default
# /tmp/feedforward-damping, one folder per damping); SCENARIOS: comma-separated (default
# ibvs-moving-target,delay-study,e8-ibvs,e9-ibvs; e8-ibvs and e9-ibvs pin 0 in their files, the
# papers' law, which --set overrides here); DAMPINGS: comma-separated, 0 first (default
# 0,0.01,0.02,0.03,0.05).
set -euo pipefail

runs=10
out=/tmp/feedforward-damping
scenarios=ibvs-moving-target,delay-study,e8-ibvs,e9-ibvs
dampings=0,0.01,0.02,0.03,0.05
predictors="hold, kf-cv, kf-ca, cs-akf, cs-akf-adaptive, stkf, st-akf, st-akf-pm, fakf-classic, fakf, imm"
usage() { sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "r:o:s:k:h" opt; do
  case $opt in
    r) runs=$OPTARG ;;
    o) out=$OPTARG ;;
    s) scenarios=$OPTARG ;;
    k) dampings=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -eq 1 ] || usage
bin=$1
[ -x "$bin" ] || { echo "feedforward-damping: error: $bin is not an executable" >&2; exit 2; }
[ "${dampings%%,*}" = 0 ] || { echo "feedforward-damping: error: the first damping of -k must be 0 (the reference)" >&2; exit 2; }

mkdir -p "$out"
script=feedforward-damping
list=$predictors
. "$(dirname "$0")/lib/compare-grid.sh"
for k in ${dampings//,/ }; do compare_grid "$k" --scenarios "$scenarios" --set "task.feedforward_damping=$k"; done

python3 - "$out" "$dampings" <<'EOF'
import csv, math, sys
out, dampings = sys.argv[1], sys.argv[2].split(",")
tables = {}
for k in dampings:
    t = {}
    with open(f"{out}/{k}/leaderboard.csv") as f:
        for row in csv.DictReader(f):
            if row["metric"] in ("rmse", "effort"):
                t[(row["variant"], row["predictor"], row["metric"])] = float(row["mean"])
    tables[k] = t
ref = tables[dampings[0]]
gmean = lambda xs: math.exp(sum(map(math.log, xs)) / len(xs)) if xs else float("nan")
print("cell                          " + "".join(f" | {'damping ' + k:>26s}" for k in dampings[1:]))
print("                              " + "".join(f" | {'rmse gm':>8s} {'worst':>7s} {'effort':>8s}" for _ in dampings[1:]))
for variant in sorted({v for (v, p, m) in ref}):
    preds = sorted({p for (v, p, m) in ref if v == variant and p != "hold"})
    line = f"{variant[:30]:30s}"
    for k in dampings[1:]:
        r = [tables[k][(variant, p, "rmse")] / ref[(variant, p, "rmse")] for p in preds if ref[(variant, p, "rmse")] > 0]
        e = [tables[k][(variant, p, "effort")] / ref[(variant, p, "effort")] for p in preds if ref[(variant, p, "effort")] > 0]
        line += f" | {gmean(r):8.3f} {max(r):7.3f} {gmean(e):8.3f}"
    print(line)
EOF
