#!/usr/bin/env bash
# CTest install_prefix: `cmake --install` into a fresh prefix, then the installed predvs runs from
# another folder with its data found beside itself (PREDVS_DATA_DIR unset), through
# PREDVS_DATA_DIR pointing elsewhere, and fails naming PREDVS_DATA_DIR when that is not a folder;
# a small project links predvs::calibration (find_package(predvs COMPONENTS calibration)).
# Usage: install_test.sh CMAKE BUILD_DIR PREFIX SOURCE_DIR
set -euo pipefail
cmake_cmd=$1 build=$2 prefix=$3 src=$4
fail() { echo "install_test: $*" >&2; exit 1; }
rm -rf "$prefix"
"$cmake_cmd" --install "$build" --prefix "$prefix" >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
unset PREDVS_DATA_DIR
predvs="$prefix/bin/predvs"
[ -x "$predvs" ] || fail "$predvs not installed"
for f in include/predvs/predictors/predictor.h include/predvs/tasks/ibvs_task.h include/predvs/servo/data_dir.h \
         lib/libpredvs_predictors.a lib/libpredvs_tasks.a lib/libpredvs_servo.a \
         lib/cmake/predvs/predvsConfig.cmake share/predvs/scenarios/ibvs-moving-target.yaml \
         share/predvs/textures/tag36h11_id0.pgm; do
  [ -e "$prefix/$f" ] || fail "$prefix/$f not installed"
done
[ -x "$prefix/bin/predvs-all" ] || fail "$prefix/bin/predvs-all not installed (predvs hands it every command but the track ones)"
for exe in "$predvs" "$prefix/bin/predvs-all"; do
  if grep -q "$src/data" "$exe"; then fail "$exe contains the source path $src/data"; fi
done
# The commands predvs runs itself (app/track_cli.h), from the installed prefix.
"$predvs" make-track --kind turns --duration-s 5 --out "$work/t.csv" >/dev/null || fail "installed predvs make-track failed"
"$predvs" predict --input "$work/t.csv" --predictor hold,kf-cv --delay-frames 2 --no-plots --out "$work/p" >/dev/null \
  || fail "installed predvs predict failed"
[ -s "$work/p/predictions.csv" ] || fail "installed predvs predict wrote no $work/p/predictions.csv"

"$predvs" list > list.txt || fail "installed predvs list failed"
grep -q "in $prefix/share/predvs/scenarios:" list.txt || fail "predvs list does not read $prefix/share/predvs: $(grep Scenarios list.txt)"
grep -q "ibvs-moving-target" list.txt || fail "predvs list shows no ibvs-moving-target"
"$predvs" servo --no-plots --out "$work/o" > servo.txt 2>&1 || { cat servo.txt; fail "installed predvs servo failed"; }
[ -s "$work/o/summary.json" ] || fail "predvs servo wrote no $work/o/summary.json"
# The AprilTag texture (servo layer's dataDir()) through the installed layout, short run.
"$predvs" servo --scenario ibvs-rendered-apriltag --set duration_s=0.5 --no-plots --out "$work/tag" >/dev/null 2>&1 \
  || fail "installed predvs servo --scenario ibvs-rendered-apriltag failed"

# PREDVS_DATA_DIR elsewhere: a data folder with a scenario that exists only there.
mkdir -p alt/scenarios
cp "$prefix/share/predvs/scenarios/ibvs-moving-target.yaml" alt/scenarios/only-in-alt.yaml
PREDVS_DATA_DIR="$work/alt" "$predvs" list > alt.txt || fail "predvs list with PREDVS_DATA_DIR failed"
grep -q "only-in-alt" alt.txt || fail "PREDVS_DATA_DIR=$work/alt not used by predvs list"
if grep -q "e1-line" alt.txt; then fail "PREDVS_DATA_DIR did not override the installed data"; fi
PREDVS_DATA_DIR="$work/alt" "$predvs" servo --scenario only-in-alt --no-plots --out "$work/o2" >/dev/null 2>&1 \
  || fail "predvs servo --scenario only-in-alt with PREDVS_DATA_DIR failed"
if PREDVS_DATA_DIR="$work/missing" "$predvs" list > bad.txt 2>&1; then fail "PREDVS_DATA_DIR=missing accepted"; fi
grep -q "PREDVS_DATA_DIR=$work/missing" bad.txt || fail "error does not name PREDVS_DATA_DIR: $(cat bad.txt)"

# predvs::calibration from the installed package (OpenCV and Ceres found by predvsConfig.cmake).
mkdir calib
cat > calib/CMakeLists.txt <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(calib_user LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(predvs REQUIRED COMPONENTS calibration)
add_executable(calib_user main.cpp)
target_link_libraries(calib_user PRIVATE predvs::calibration)
CMAKE
cat > calib/main.cpp <<'CPP'
#include <predvs/calibration/calibrated_camera.h>
#include <iostream>
int main() {
  predvs::CalibratedCamera c;
  c.width_px = 640; c.height_px = 480; c.fx_px = c.fy_px = 800; c.cx_px = 320; c.cy_px = 240;
  c.distortion[0] = -0.2;
  std::cout << predvs::inverseRadialTerm(c) << "\n";
}
CPP
{ "$cmake_cmd" -S calib -B calib/build -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  && "$cmake_cmd" --build calib/build; } > calib.log 2>&1 || { cat calib.log; fail "a project using predvs::calibration did not build"; }
kdu=$(calib/build/calib_user) || fail "the predvs::calibration user exited non-zero"
# kdu inverts kud = k1 = -0.2 to first order: about +0.2.
awk -v k="$kdu" 'BEGIN { exit !(k > 0.1 && k < 0.4) }' || fail "inverseRadialTerm(k1 = -0.2) = $kdu, expected about +0.2"
echo "install_test: OK ($prefix)"
