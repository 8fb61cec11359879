#!/usr/bin/env bash
# Installs every Debian package predvs needs to build, test and plot, and only what is missing.
# Runs as root on a fresh Debian 12 (bookworm); as another user it uses sudo when available.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config   # build-essential brings dpkg-dev (dpkg-shlibdeps: make deb)
  file                 # make deb: CPack finds the ELF files to give dpkg-shlibdeps
  libeigen3-dev
  libvisp-dev          # ViSP 3.5: vpServo, vpSimulatorCamera, vpLinearKalmanFilterInstantiation
  libopencv-dev        # cv::KalmanFilter (benchmark baseline); also pulled in by ViSP
  libyaml-cpp-dev      # scenario files
  libcli11-dev         # the predvs command line
  nlohmann-json3-dev   # summary.json / leaderboard.json
  libgtest-dev libgmock-dev
  libbenchmark-dev
  gnuplot-nox          # PNG plots (pngcairo terminal)
  visp-images-data     # ViSP's image sets (mire-2, AprilTag, calibration grids): track, tests
  libceres-dev         # offline noise fitting (predvs fit-noise)
  libopenmpi-dev openmpi-bin  # optional: `mpirun -np K predvs compare` (campaigns over MPI ranks)
  chromium             # headless browser: the report.html test (tests/app/campaign_report_test)
  pybind11-dev python3-dev python3-numpy python3-pytest  # `import predvs` (python/, docs/PYTHON.md) and its tests
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root" >&2; exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
