#!/usr/bin/env bash
# Installs the predvs .deb into a fresh, minimal Debian 12 and runs the default scenario there:
#   1. debootstrap --variant=minbase bookworm into a temporary folder (from the Debian archive;
#      sources: bookworm, bookworm-updates, bookworm-security, main only, as a fresh install);
#   2. copies the .deb in and runs, in a chroot, `apt-get install -y --no-install-recommends
#      ./predvs_<version>_<arch>.deb`: apt resolves the Depends the package declares from the
#      archive, and nothing else (no Recommends, so nothing the Depends forgot can slip in);
#   3. runs `predvs list` and `predvs servo` (with its plots: gnuplot-nox is a Depends) from /root
#      in the chroot and checks the run converged: every predictor settles and kf-cv and
#      cs-akf-adaptive bring the steady rmse 4x below hold; the plots exist;
#   4. with --dev, also installs predvs-dev (the .deb beside DEB) with cmake, make and g++, and
#      builds and runs examples/predictor_ahead_of_vpservo against /usr (find_package(predvs),
#      no CMAKE_PREFIX_PATH): kf-cv must lower the steady-state image error 4-fold;
#   5. with --python, also installs python3-predvs (beside DEB) and, in the chroot's python3,
#      imports predvs, runs kf-cv on a few frames and reads a parameter file of /usr/share/predvs;
#   6. prints the time of each step and the number of packages installed.
# /proc is mounted inside the chroot (predvs finds its data through /proc/self/exe) and unmounted
# on exit, and the folder is removed (unless --keep). Runs as root; needs debootstrap and network.
# Usage: scripts/check-deb-fresh.sh [DEB] [--dev] [--python] [--keep]   (DEB: default build/predvs_*_<arch>.deb)
#        PREDVS_DEBIAN_MIRROR=http://... to use another Debian mirror.
set -euo pipefail
fail() { echo "check-deb-fresh: $*" >&2; exit 1; }

deb="" keep=0 with_dev=0 with_python=0
for a in "$@"; do
  case "$a" in
    --keep) keep=1 ;;
    --dev) with_dev=1 ;;
    --python) with_python=1 ;;
    -*) fail "unknown option $a (usage: check-deb-fresh.sh [DEB] [--dev] [--python] [--keep])" ;;
    *) deb=$a ;;
  esac
done
arch=$(dpkg --print-architecture)
if [ -z "$deb" ]; then
  set -- build/predvs_*_"$arch".deb
  [ -f "$1" ] || fail "no build/predvs_*_$arch.deb: run make deb first, or pass the .deb"
  deb=$1
fi
[ -f "$deb" ] || fail "$deb: no such file"
[ "$(dpkg-deb -f "$deb" Package 2>/dev/null)" = predvs ] || fail "$deb: not the predvs package"
dev_deb="$(dirname "$deb")/$(basename "$deb" | sed 's/^predvs_/predvs-dev_/')"
if [ "$with_dev" = 1 ]; then [ -f "$dev_deb" ] || fail "--dev: no $dev_deb beside $deb"; fi
py_deb="$(dirname "$deb")/$(basename "$deb" | sed 's/^predvs_/python3-predvs_/')"
if [ "$with_python" = 1 ]; then [ -f "$py_deb" ] || fail "--python: no $py_deb beside $deb"; fi
src=$(cd "$(dirname "$0")/.." && pwd)
[ "$(id -u)" -eq 0 ] || fail "must run as root (debootstrap, chroot, mount)"
command -v debootstrap >/dev/null || fail "debootstrap not found (apt-get install debootstrap)"
mirror=${PREDVS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

work=$(mktemp -d /tmp/predvs-deb-fresh.XXXXXX)
root="$work/root"
cleanup() {
  if mountpoint -q "$root/proc" 2>/dev/null; then umount "$root/proc" || umount -l "$root/proc"; fi
  if [ "$keep" = 1 ]; then echo "check-deb-fresh: kept $root"; else rm -rf "$work"; fi
}
trap cleanup EXIT
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
                   DEBIAN_FRONTEND=noninteractive "$@"; }
now() { date +%s; }

t0=$(now)
echo "check-deb-fresh: debootstrap --variant=minbase bookworm $root ($mirror)"
debootstrap --variant=minbase bookworm "$root" "$mirror" > "$work/debootstrap.log" 2>&1 \
  || { tail -20 "$work/debootstrap.log"; fail "debootstrap failed (log above)"; }
t1=$(now)
cat > "$root/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
deb http://security.debian.org/debian-security bookworm-security main
EOF
cp /etc/resolv.conf "$root/etc/resolv.conf"
mount -t proc proc "$root/proc"
base_count=$(in_root dpkg-query -W -f='${Status}\n' | grep -c 'install ok installed')
cp "$deb" "$root/tmp/"
name=$(basename "$deb")

echo "check-deb-fresh: apt-get install -y --no-install-recommends ./$name (in the chroot)"
in_root apt-get update -qq > "$work/apt.log" 2>&1 || { tail -20 "$work/apt.log"; fail "apt-get update failed"; }
in_root sh -c "cd /tmp && apt-get install -y --no-install-recommends ./$name" >> "$work/apt.log" 2>&1 \
  || { tail -30 "$work/apt.log"; fail "apt-get install ./$name failed (log above)"; }
t2=$(now)
count=$(in_root dpkg-query -W -f='${Status}\n' | grep -c 'install ok installed')
download=$(grep -E '^Need to get' "$work/apt.log" | tail -1 || true)
in_root sh -c 'command -v predvs' | grep -qx /usr/bin/predvs || fail "predvs is not /usr/bin/predvs in the chroot"

echo "check-deb-fresh: predvs list; predvs servo (in /root of the chroot)"
in_root sh -c 'cd /root && predvs list' > "$work/list.txt" 2>&1 || { cat "$work/list.txt"; fail "predvs list failed"; }
grep -q "in /usr/share/predvs/scenarios:" "$work/list.txt" || fail "predvs list does not read /usr/share/predvs"
in_root sh -c 'cd /root && predvs servo' > "$work/servo.txt" 2>&1 || { cat "$work/servo.txt"; fail "predvs servo failed"; }
t3=$(now)
cat "$work/servo.txt"
out="$root/root/out/ibvs-moving-target"
for f in summary.json log.csv error.png trajectories.png features.png command.png; do
  [ -s "$out/$f" ] || fail "predvs servo wrote no out/ibvs-moving-target/$f"
done
awk '/"rmse":/ {gsub(/,/, "", $2); r = $2} /"settling_s":/ {gsub(/,/, "", $2); s = $2}
     /"name":/ {gsub(/[",]/, "", $2); print $2, r, s}' "$out/summary.json" > "$work/figures.txt"
awk '$3 == "null" || $3 == "" {print "check-deb-fresh: " $1 " never settled"; bad = 1}
     $1 == "hold" {hold = $2} $1 == "kf-cv" {cv = $2} $1 == "cs-akf-adaptive" {cs = $2}
     END {if (!(cv > 0 && cs > 0 && 4 * cv < hold && 4 * cs < hold)) {
            print "check-deb-fresh: rmse hold " hold ", kf-cv " cv ", cs-akf-adaptive " cs ": not 4x below hold"; bad = 1}
          exit bad}' "$work/figures.txt" >&2 || fail "the default scenario did not converge (see above)"

if [ "$with_dev" = 1 ]; then
  dev_name=$(basename "$dev_deb")
  cp "$dev_deb" "$root/tmp/"
  cp -r "$src/examples/predictor_ahead_of_vpservo" "$root/root/example"
  echo "check-deb-fresh: apt-get install -y --no-install-recommends ./$dev_name cmake make g++ (in the chroot)"
  in_root sh -c "cd /tmp && apt-get install -y --no-install-recommends ./$dev_name cmake make g++" > "$work/apt-dev.log" 2>&1 \
    || { tail -30 "$work/apt-dev.log"; fail "apt-get install ./$dev_name failed (log above)"; }
  t4=$(now)
  dev_count=$(in_root dpkg-query -W -f='${Status}\n' | grep -c 'install ok installed')
  dev_download=$(grep -E '^Need to get' "$work/apt-dev.log" | tail -1 || true)
  echo "check-deb-fresh: the example against /usr (cmake, build, run)"
  in_root sh -c 'cd /root/example && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build' \
    > "$work/example.log" 2>&1 || { tail -30 "$work/example.log"; fail "the example did not build against predvs-dev"; }
  ex=$(in_root /root/example/build/predictor_ahead_of_vpservo kf-cv) || fail "the example exited non-zero"
  t5=$(now)
  echo "$ex"
  without=$(echo "$ex" | sed -n 's/.*without predictor: \([0-9.]*\) px/\1/p')
  with=$(echo "$ex" | sed -n 's/.*with kf-cv: \([0-9.]*\) px/\1/p')
  awk -v a="$with" -v b="$without" 'BEGIN { exit !(a > 0 && 4 * a < b) }' \
    || fail "the example: kf-cv error '$with' px not 4x below '$without' px"
fi

if [ "$with_python" = 1 ]; then
  py_name=$(basename "$py_deb")
  cp "$py_deb" "$root/tmp/"
  t6=$(now)
  echo "check-deb-fresh: apt-get install -y --no-install-recommends ./$py_name (in the chroot)"
  in_root sh -c "cd /tmp && apt-get install -y --no-install-recommends ./$py_name" > "$work/apt-py.log" 2>&1 \
    || { tail -30 "$work/apt-py.log"; fail "apt-get install ./$py_name failed (log above)"; }
  py_count=$(in_root dpkg-query -W -f='${Status}\n' | grep -c 'install ok installed')
  py_out=$(in_root python3 -c "
import predvs
p = predvs.make('kf-cv', 2)
for k in range(5):
    p.update(0.1 * k, [10.0 * k, 5.0])
x, P = p.predict(0.6)
specs = predvs.read_params('/usr/share/predvs/params/pre-issue-11.yaml')
assert abs(x[0][0] - 60.0) < 5.0 and any(s['name'] == 'kf-ca' for s in specs), (x, specs)
print('import predvs from', predvs.__file__, '- kf-cv at 0.6 s:', round(float(x[0][0]), 3))
") || fail "import predvs in the chroot failed"
  t7=$(now)
  echo "$py_out"
fi

echo "check-deb-fresh: OK: $name on a fresh Debian 12 ($(. "$root/etc/os-release"; echo "$PRETTY_NAME"), \
debian_version $(cat "$root/etc/debian_version"))"
echo "  debootstrap (minbase): $((t1 - t0)) s, $base_count packages"
echo "  apt-get install ./$name: $((t2 - t1)) s, $((count - base_count)) packages added ($count in all); $download"
echo "  predvs list + servo with plots: $((t3 - t2)) s"
if [ "$with_dev" = 1 ]; then
  echo "  apt-get install ./$dev_name cmake make g++: $((t4 - t3)) s, $((dev_count - count)) packages added ($dev_count in all); $dev_download"
  echo "  the example against /usr (configure, build, run): $((t5 - t4)) s"
fi
if [ "$with_python" = 1 ]; then
  echo "  apt-get install ./$py_name + import predvs: $((t7 - t6)) s, $((py_count - ${dev_count:-$count})) packages added"
fi
