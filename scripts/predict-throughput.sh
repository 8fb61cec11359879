#!/bin/bash
# predvs — wall and CPU time of `predvs predict --predictor all` on a 2-million-row track
# (docs/PERFORMANCE.md, "`predvs predict` throughput"), for one binary or two interleaved.
#
#   scripts/predict-throughput.sh [-n RUNS] [-t TRACK] [-o DIR] BIN [BIN2]
#
# TRACK (default DIR/big.csv) is made with BIN's make-track when it does not exist (the command of
# the section: turns, 30 Hz, 1.5 px, 66,667 s, 2 % drops, seed 1). For each of RUNS rounds (default 3),
# with predictions.png and then with --no-plots, each binary runs once; before each run the output
# is removed and `sync`ed. Prints one line per run: mode, binary, wall s, user s, system s.
set -euo pipefail
runs=3
track=""
dir=/tmp/predvs-throughput
while getopts "n:t:o:" opt; do
  case $opt in
    n) runs=$OPTARG ;;
    t) track=$OPTARG ;;
    o) dir=$OPTARG ;;
    *) echo "usage: $0 [-n RUNS] [-t TRACK] [-o DIR] BIN [BIN2]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 [-n RUNS] [-t TRACK] [-o DIR] BIN [BIN2]" >&2
  exit 2
fi
for bin in "$@"; do
  [ -x "$bin" ] || { echo "$0: $bin: not an executable" >&2; exit 2; }
done
mkdir -p "$dir"
[ -n "$track" ] || track=$dir/big.csv
if [ ! -f "$track" ]; then
  "$1" make-track --kind turns --rate-hz 30 --noise-px 1.5 --duration-s 66667 --drop 0.02 --seed 1 --out "$track"
fi
for mode in plot no-plots; do
  extra=()
  [ $mode = no-plots ] && extra=(--no-plots)
  for _ in $(seq 1 "$runs"); do
    for bin in "$@"; do
      rm -rf "$dir/out"
      sync
      /usr/bin/time -f "%e %U %S" -o "$dir/time" "$bin" predict --input "$track" --predictor all --delay-frames 2 \
        --out "$dir/out" "${extra[@]}" >/dev/null
      echo "$mode $bin $(cat "$dir/time")"
    done
  done
done
rm -rf "$dir/out" "$dir/time"
