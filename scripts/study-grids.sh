#!/bin/bash
# predvs — the ten make-track grids of docs/PERFORMANCE.md ("Defaults that hold" and after), run by
# `predvs track-study` with the same further arguments, into OUT/<grid>/study.csv (and
# OUT/<grid>.log); summarise them with scripts/study-summary.py OUT.
#
#   scripts/study-grids.sh BIN OUT [track-study arguments, e.g. --delay-frames 5 --param kf-cv.q=50]
#
# The arguments may be any but those the grids set themselves (--seed, --seeds, --duration-s, --drop,
# --rates, --noise, --jobs, --out).
#
# g1-g3: the tuning grids (20 s, 15 s, other rates and noise); g4 and v8: 30 seeds each with the
# generator's 2 % dropped frames; g5-g7, v9, v10: 30 seeds each with 5-10 % (v8-v10 held out: never
# tuned on). About 25 s on 2 cores at --delay-frames 2.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 BIN OUT [track-study arguments]" >&2
  exit 2
fi
bin=$1 out=$2
shift 2
[ -x "$bin" ] || { echo "$0: $bin: not an executable" >&2; exit 2; }
mkdir -p "$out"
grid() {  # NAME, then the grid's own arguments
  local name=$1
  shift
  "$bin" track-study --jobs 2 "$@" --out "$out/$name" >"$out/$name.log" 2>&1 || { echo "$0: $name failed: see $out/$name.log" >&2; exit 1; }
}
grid g1 "$@" --seed 1
grid g2 "$@" --seed 101 --duration-s 15
grid g3 "$@" --rates 12,20,45 --noise 1,2.5 --seed 201 --seeds 3 --duration-s 10
grid g4 "$@" --seed 401 --seeds 30 --duration-s 15
grid g5 "$@" --seed 501 --seeds 30 --duration-s 10 --drop 0.05
grid g6 "$@" --seed 601 --seeds 30 --duration-s 12 --drop 0.08
grid g7 "$@" --seed 701 --seeds 30 --duration-s 12 --drop 0.1
grid v8 "$@" --seed 801 --seeds 30 --duration-s 15
grid v9 "$@" --seed 901 --seeds 30 --duration-s 10 --drop 0.06
grid v10 "$@" --seed 1001 --seeds 30 --duration-s 12 --drop 0.08
