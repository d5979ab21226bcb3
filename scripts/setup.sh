#!/usr/bin/env bash
# Installs millnet's build dependencies from Debian 12 packages. Idempotent: does nothing when
# everything is already there. Needs root (or sudo) only when something is missing.
set -euo pipefail
PKGS=(build-essential cmake ninja-build pkg-config
      libeigen3-dev libassimp-dev libopencv-dev nlohmann-json3-dev
      libgtest-dev libgmock-dev libcli11-dev libbenchmark-dev libpolyclipping-dev libnanoflann-dev
      libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev  # STEP/IGES (MILLNET_CAD)
      libopenmpi-dev openmpi-bin   # MPI: mpirun -np K millnet dataset|predict|finish (issue 10)
      linuxcnc-uspace   # LinuxCNC's rs274 interpreter: tests check that every program millnet writes is accepted
      zlib1g-dev   # the preview pages pack their data (gzip + base64)
      libjs-three libjs-chart.js   # three.js r111 + OrbitControls and Chart.js, inlined into the HTML preview pages
      chromium fonts-dejavu-core   # headless Chromium: the preview pages are opened and screenshot by tests/app/test_preview_browser.cpp
      clang libclang-rt-14-dev libomp-14-dev  # libFuzzer and clang's OpenMP: scripts/fuzz.sh
      clang-format)  # clang-format 14: scripts/format.sh --check in .ci/run
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PKGS[@]} packages present" >&2
  exit 0
fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "setup: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
