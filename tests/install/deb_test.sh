#!/usr/bin/env bash
# CTest deb_package: `cpack -G DEB` of the already built tree (no second build) into WORK_DIR, then
#  - the predvs .deb declares the shared libraries it links (dpkg-shlibdeps: ViSP, OpenCV,
#    yaml-cpp, libstdc++) and gnuplot-nox; predvs-dev depends on predvs (= same version),
#    libvisp-dev and libeigen3-dev;
#  - predvs holds usr/bin/predvs, usr/bin/predvs-all and usr/share/predvs/{scenarios,textures,params}, and no headers;
#    predvs-dev holds the headers, the static libraries and the CMake package;
#  - the predvs .deb unpacked (dpkg-deb -x) into a temporary root runs the default scenario from
#    another folder with its data found beside the binary (PREDVS_DATA_DIR unset), and converges:
#    every predictor settles and kf-cv and cs-akf-adaptive bring the steady rmse 4x below hold;
#  - with predvs-dev unpacked into the same root, find_package(predvs COMPONENTS calibration)
#    against <root>/usr gives the four targets, their libraries and <root>/usr/share/predvs.
# The install into a fresh Debian 12 (apt resolving these Depends) is scripts/check-deb-fresh.sh.
# Usage: deb_test.sh CPACK CMAKE BUILD_DIR WORK_DIR VERSION
set -euo pipefail
cpack_cmd=$1 cmake_cmd=$2 build=$3 work=$4 version=$5
fail() { echo "deb_test: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$cpack_cmd" --config "$build/CPackConfig.cmake" -G DEB -B "$work" > "$work/cpack.log" 2>&1 \
  || { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
arch=$(dpkg --print-architecture)
deb="$work/predvs_${version}_${arch}.deb"
dev="$work/predvs-dev_${version}_${arch}.deb"
[ -f "$deb" ] || fail "cpack wrote no $deb: $(ls "$work")"
[ -f "$dev" ] || fail "cpack wrote no $dev: $(ls "$work")"

# Control fields: name, version, the declared Depends.
[ "$(dpkg-deb -f "$deb" Package)" = predvs ] || fail "$deb: Package is not predvs"
[ "$(dpkg-deb -f "$deb" Version)" = "$version" ] || fail "$deb: Version is not $version"
depends=$(dpkg-deb -f "$deb" Depends)
echo "predvs Depends: $depends"
# The package names, one a line (alternatives "a | b" split, version constraints dropped).
echo "$depends" | tr ',|' '\n\n' | sed 's/^ *//; s/ .*//' > "$work/depends.txt"
for lib in libvisp-core3.5 libvisp-vs3.5 libvisp-robot3.5 libvisp-detection3.5 libopencv-core406 \
           libyaml-cpp0.7 libstdc++6 libc6 gnuplot-nox; do
  grep -Fxq "$lib" "$work/depends.txt" || fail "$deb: Depends lacks $lib: $depends"
done
dev_depends=$(dpkg-deb -f "$dev" Depends)
echo "predvs-dev Depends: $dev_depends"
for d in "predvs (= $version)" libvisp-dev libeigen3-dev; do
  echo "$dev_depends" | grep -Fq "$d" || fail "$dev: Depends lacks $d: $dev_depends"
done

# Contents.
dpkg-deb -c "$deb" | awk '{print $6}' > "$work/runtime.txt"
dpkg-deb -c "$dev" | awk '{print $6}' > "$work/dev.txt"
for f in ./usr/bin/predvs ./usr/bin/predvs-all ./usr/share/predvs/scenarios/ibvs-moving-target.yaml \
         ./usr/share/predvs/textures/tag36h11_id0.pgm ./usr/share/predvs/params/pre-issue-11.yaml; do
  grep -qx "$f" "$work/runtime.txt" || fail "$deb does not hold $f"
done
if grep -q '^./usr/include/' "$work/runtime.txt"; then fail "$deb holds headers (they belong to predvs-dev)"; fi
for f in '/usr/include/predvs/servo/data_dir\.h' '/usr/include/predvs/calibration/calibrated_camera\.h' \
         '/usr/lib/.*libpredvs_servo\.a' '/usr/lib/.*libpredvs_calibration\.a' \
         '/usr/lib/.*cmake/predvs/predvsConfig\.cmake' '/usr/lib/.*cmake/predvs/predvsCalibrationTargets\.cmake'; do
  grep -q "^\.$f$" "$work/dev.txt" || fail "$dev does not hold $f"
done
if grep -q '^./usr/bin/' "$work/dev.txt"; then fail "$dev holds programs (they belong to predvs)"; fi

# Unpacked: runs from elsewhere, data found at <root>/usr/bin/../share/predvs.
dpkg-deb -x "$deb" "$work/root"
predvs="$work/root/usr/bin/predvs"
run=$(mktemp -d)
trap 'rm -rf "$run"' EXIT
cd "$run"
unset PREDVS_DATA_DIR
"$predvs" list > list.txt 2>&1 || { cat list.txt; fail "unpacked predvs list failed"; }
grep -q "in $work/root/usr/share/predvs/scenarios:" list.txt \
  || fail "unpacked predvs list does not read $work/root/usr/share/predvs: $(grep -i scenarios list.txt)"
"$predvs" servo --no-plots --out "$run/run" > servo.txt 2>&1 || { cat servo.txt; fail "unpacked predvs servo failed"; }
cat servo.txt
summary="$run/run/summary.json"
[ -s "$summary" ] || fail "predvs servo wrote no $summary"
# summary.json: one key per line; within a predictor, its metrics come before its name.
awk '/"rmse":/ {gsub(/,/, "", $2); r = $2} /"settling_s":/ {gsub(/,/, "", $2); s = $2}
     /"name":/ {gsub(/[",]/, "", $2); print $2, r, s}' "$summary" > figures.txt
grep -q '^hold ' figures.txt || fail "$summary has no hold run"
awk '$3 == "null" || $3 == "" {print "deb_test: " $1 " never settled"; bad = 1}
     $1 == "hold" {hold = $2} $1 == "kf-cv" {cv = $2} $1 == "cs-akf-adaptive" {cs = $2}
     END {if (!(cv > 0 && cs > 0 && 4 * cv < hold && 4 * cs < hold)) {
            print "deb_test: rmse hold " hold ", kf-cv " cv ", cs-akf-adaptive " cs ": not 4x below hold"; bad = 1}
          exit bad}' figures.txt >&2 || fail "the default scenario did not converge (see above)"

# predvs-dev over predvs: the CMake package under <root>/usr resolves (configure only: the same
# files, installed by the same rules, are compiled and linked against by example_against_install
# and install_prefix; scripts/check-deb-fresh.sh --dev builds the example against /usr).
dpkg-deb -x "$dev" "$work/root"
mkdir -p "$work/user"
cat > "$work/user/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(predvs_dev_user LANGUAGES CXX)
find_package(predvs REQUIRED COMPONENTS calibration)
foreach(t predictors tasks servo calibration)
  if(NOT TARGET predvs::${t})
    message(FATAL_ERROR "predvs::${t} missing")
  endif()
  get_target_property(loc predvs::${t} IMPORTED_LOCATION_RELEASE)
  if(NOT EXISTS "${loc}")
    message(FATAL_ERROR "predvs::${t}: ${loc} missing")
  endif()
endforeach()
message(STATUS "PREDVS_DATA_DIR=${PREDVS_DATA_DIR}")
CMAKE
"$cmake_cmd" -S "$work/user" -B "$work/user/build" -DCMAKE_PREFIX_PATH="$work/root/usr" > dev.txt 2>&1 \
  || { cat dev.txt; fail "find_package(predvs COMPONENTS calibration) failed on the unpacked predvs-dev"; }
grep -q "PREDVS_DATA_DIR=$work/root/usr/share/predvs$" dev.txt \
  || fail "predvs-dev's PREDVS_DATA_DIR is not $work/root/usr/share/predvs: $(grep PREDVS_DATA_DIR dev.txt)"

# python3-predvs, when the module was built: its Depends, and `import predvs` from the unpacked
# root (the Debian interpreter, which has python3-numpy), reading a parameter file of predvs.
py="$work/python3-predvs_${version}_${arch}.deb"
if [ -f "$py" ]; then
  py_depends=$(dpkg-deb -f "$py" Depends)
  echo "python3-predvs Depends: $py_depends"
  for d in "predvs (= $version)" python3-numpy "python3 (>= "; do
    echo "$py_depends" | grep -Fq "$d" || fail "$py: Depends lacks $d: $py_depends"
  done
  dpkg-deb -x "$py" "$work/root"
  PYTHONPATH="$work/root/usr/lib/python3/dist-packages" /usr/bin/python3 -c "
import predvs, sys
p = predvs.make('kf-cv', 2)
p.update(0.0, [1.0, 2.0])
specs = predvs.read_params(sys.argv[1])
assert any(s['name'] == 'kf-ca' for s in specs), specs
print('python3-predvs: import predvs from', predvs.__file__)
" "$work/root/usr/share/predvs/params/pre-issue-11.yaml" > py.txt 2>&1 \
    || { cat py.txt; fail "import predvs from the unpacked python3-predvs failed"; }
  grep -q "from $work/root/usr/lib/python3/dist-packages/predvs/" py.txt || fail "imported predvs from elsewhere: $(cat py.txt)"
fi
echo "deb_test: OK ($deb, $(du -k "$deb" | cut -f1) KiB; $dev${py:+; $py})"
