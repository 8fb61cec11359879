#!/bin/bash
# The vision delay recovered by `predvs calibrate latency` from simulated servo logs of known
# timing (docs/CALIBRATION.md §2, "Recovery on simulated logs"): for each row, one `predvs servo`
# run of the default scenario (8 s for the point model, 4 s for the start-of-motion fit, which uses
# the first 1.3 s), then `calibrate latency` with the camera's intrinsics (the point model) and
# without (the start-of-motion fit). The true delay is the log's own stamped delivery - acquisition
# (the release tick). Prints a markdown table.
#
#   scripts/latency-recovery.sh [-o OUT] BIN
#
# OUT: scratch directory for the logs (default /tmp/latency-recovery; replaced). About 10 s.
set -euo pipefail

out=/tmp/latency-recovery
usage() { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "o:h" opt; do
  case $opt in
    o) out=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -eq 1 ] || usage
bin=$1
[ -x "$bin" ] || { echo "latency-recovery: error: $bin is not an executable" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out"

# base period (s), frames per base period N, lag each of acquisition and processing (s), predictor, noise (px)
rows="0.04 1 0 hold 0.5
0.04 1 0 kf-cv 0.5
0.04 1 0.02 hold 0.5
0.04 1 0.02 kf-cv 0.5
0.04 1 0.04 hold 0.5
0.04 1 0.04 kf-cv 0.5
0.01 2 0.015 hold 0.5
0.01 4 0.03 hold 0.5
0.04 1 0.02 hold 1.0
0.04 1 0.04 hold 1.0"

# fit DURATION_S INTRINSICS_ARGS...: servo then calibrate latency; prints "delay +- sigma ms" and
# leaves the stamped delay in $out/truth
fit() {
  local dur=$1; shift
  local log=$out/log-$dur
  rm -rf "$log" "$out/fit"
  "$bin" servo --predictors "$pred" --set duration_s="$dur" --set timing.base_period_s="$base" \
    --set timing.frame_period_n="$n" --set 'timing.delay_frames=~' --set timing.acquisition_lag_s="$lag" \
    --set timing.processing_lag_s="$lag" --set noise.sigma="$sigma" --no-plots --out "$log" >/dev/null 2>&1
  "$bin" calibrate latency --log "$log/log.csv" "$@" --no-plots --out "$out/fit" >"$out/fit.txt"
  sed -n 's/.*stamped delivery - acquisition: median \([0-9.]*\) ms.*/\1/p' "$out/fit.txt" >"$out/truth"
  sed -n 's/^  vision delay: \([0-9.]* +- [0-9.]*\) ms.*/\1 ms/p' "$out/fit.txt"
}

echo "| base period | N | true delay (release tick) | predictor, noise (px) | point model (8 s) | start-of-motion fit (4 s) |"
echo "|---|---|---|---|---|---|"
while read -r base n lag pred sigma; do
  point=$(fit 8 --intrinsics 800,800,320,240)
  truth=$(cat "$out/truth")
  start=$(fit 4)
  printf '| %.0f ms | %s | %.0f ms | %s, %s | %s | %s |\n' "$(echo "$base * 1000" | bc)" "$n" "$truth" "$pred" "$sigma" "$point" "$start"
done <<<"$rows"
