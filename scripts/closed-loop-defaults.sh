#!/bin/bash
# Every predictor with its defaults in the closed-loop scenarios, as a user adds them on the command
# line (the scenarios' own lists pin parameters; this replaces the list), run by one or more predvs
# binaries on the same seeds. Prints, per scenario and predictor, the mean rmse over the runs of each
# binary and hold's rmse over it (docs/PERFORMANCE.md "The feed-forward's velocity").
#
#   scripts/closed-loop-defaults.sh [-r RUNS] [-o OUT] [-s SCENARIOS] [-p PREDICTORS] BIN [BIN ...]
#
# RUNS: runs per predictor and scenario (default 5, seeds = each scenario's seed + r); OUT: where
# the leaderboards go (default /tmp/closed-loop-defaults, OUT/1, OUT/2, ... one per binary);
# SCENARIOS: comma-separated (default: the closed-loop scenarios with a moving target);
# PREDICTORS: the YAML list's elements instead of every predictor, e.g.
#   -p 'hold, kf-cv, {name: kf-cv-auto, type: kf-cv, params: {q: auto}}'
set -euo pipefail

runs=5
out=/tmp/closed-loop-defaults
scenarios=ibvs-moving-target,e5-line,e5-circle,e5-line-ibvs,e5-circle-ibvs,e8-ibvs,e8-vtc
predictors="hold, kf-cv, kf-ca, cs-akf, cs-akf-adaptive, stkf, st-akf, st-akf-pm, fakf-classic, fakf, imm"
usage() { sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "r:o:s:p:h" opt; do
  case $opt in
    r) runs=$OPTARG ;;
    o) out=$OPTARG ;;
    s) scenarios=$OPTARG ;;
    p) predictors=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || usage
for bin in "$@"; do
  [ -x "$bin" ] || { echo "closed-loop-defaults: error: $bin is not an executable" >&2; exit 2; }
done

mkdir -p "$out"
i=0
for bin in "$@"; do
  i=$((i + 1))
  echo "closed-loop-defaults: binary $i: $bin" >&2
  "$bin" compare --scenarios "$scenarios" --runs "$runs" --set "predictors=[$predictors]" \
    --out "$out/$i" --no-plots >"$out/$i.log" 2>&1 || { echo "closed-loop-defaults: error: $bin compare failed, see $out/$i.log" >&2; exit 1; }
done

python3 - "$out" "$#" <<'EOF'
import csv, sys
out, n = sys.argv[1], int(sys.argv[2])
tables = []
for i in range(1, n + 1):
    t = {}
    with open(f"{out}/{i}/leaderboard.csv") as f:
        for row in csv.DictReader(f):
            if row["metric"] == "rmse":
                t[(row["variant"], row["predictor"])] = float(row["mean"])
    tables.append(t)
head = "scenario            predictor        " + "".join(f"   rmse[{i}]  vs hold" for i in range(1, n + 1))
print(head)
for (variant, predictor) in sorted(tables[0], key=lambda k: (k[0], k[1] != "hold", k[1])):
    line = f"{variant:19s} {predictor:16s}"
    for t in tables:
        r, h = t.get((variant, predictor)), t.get((variant, "hold"))
        line += f" {r:10.3f}" if r else f" {'-':>10s}"
        line += f" {h / r:7.1f}x" if r and h else f" {'-':>8s}"
    print(line)
EOF
