#!/usr/bin/env bash
# CTest predvs_front_executable: `predvs` (app/main.cpp) links none of ViSP's image, robot, detection
# or visual-servoing libraries nor OpenCV's codecs or video I/O (ldd: neither directly nor through
# another library), runs the track commands itself, and hands every other command line to predvs-all
# beside it unchanged (its help, its errors and their exit status, a servo run); without predvs-all
# it says so in one line and exits with 2.
#   front_test.sh PREDVS WORK_DIR
set -euo pipefail
predvs=$1
work=$2
fail() { echo "front_test: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"

libs=$(ldd "$predvs")
for lib in libvisp_core libvisp_io libvisp_vs libvisp_robot libvisp_detection libvisp_blob libopencv_imgcodecs \
           libopencv_videoio libopencv_core libgdal libavcodec libgstreamer; do
  if grep -q "$lib" <<<"$libs"; then fail "$predvs loads $lib: $(grep "$lib" <<<"$libs" | head -1)"; fi
done

# Its own commands.
"$predvs" make-track --kind zigzag --rate-hz 30 --duration-s 4 --out "$work/t.csv" > /dev/null
"$predvs" predict --input "$work/t.csv" --predictor hold,kf-cv,imm --delay-frames 2 --no-plots --out "$work/p" > "$work/p.txt"
grep -q "^imm " "$work/p.txt" || fail "predvs predict printed no imm row: $(cat "$work/p.txt")"
"$predvs" predict --help > "$work/phelp.txt"
grep -q -- "--fit-split" "$work/phelp.txt" || fail "predvs predict --help lacks --fit-split"
set +e
"$predvs" predict --input "$work/missing.csv" --predictor kf-cv --delay-frames 2 --out "$work/q" 2> "$work/err.txt"
status=$?
set -e
[ $status -eq 2 ] || fail "predict on a missing file: exit status $status, expected 2"
grep -q "^predvs: error: .*missing.csv" "$work/err.txt" || fail "predict on a missing file: $(cat "$work/err.txt")"
[ ! -e "$work/q" ] || fail "predict on a missing file left $work/q"

# Handed to predvs-all.
"$predvs" --help > "$work/help.txt"
for sub in predict servo compare calibrate track-study; do
  grep -q "^  $sub " "$work/help.txt" || fail "predvs --help does not list $sub"
done
"$predvs" list > "$work/list.txt"
grep -q "ibvs-moving-target" "$work/list.txt" || fail "predvs list shows no ibvs-moving-target"
"$predvs" servo --set duration_s=1 --predictors hold --no-plots --out "$work/s" > /dev/null
[ -s "$work/s/summary.json" ] || fail "predvs servo wrote no summary.json"
set +e
"$predvs" bogus 2> "$work/err.txt"
status=$?
set -e
[ $status -eq 2 ] || fail "predvs bogus: exit status $status, expected 2"
grep -q "^predvs: error: unknown subcommand 'bogus'" "$work/err.txt" || fail "predvs bogus: $(cat "$work/err.txt")"

# Without predvs-all beside it.
mkdir -p "$work/alone"
cp "$predvs" "$work/alone/predvs"
set +e
"$work/alone/predvs" servo 2> "$work/err.txt"
status=$?
set -e
[ $status -eq 2 ] || fail "predvs servo without predvs-all: exit status $status, expected 2"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "predvs servo without predvs-all: not one line: $(cat "$work/err.txt")"
grep -q "^predvs: error: cannot run $work/alone/predvs-all" "$work/err.txt" || fail "without predvs-all: $(cat "$work/err.txt")"
"$work/alone/predvs" make-track --duration-s 2 --out "$work/alone/t.csv" > /dev/null || fail "predvs alone cannot run make-track"
rm -rf "$work"
echo "front_test: ok"
