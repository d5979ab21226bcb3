#!/usr/bin/env bash
# README command 2: set up, build, and run every test (GoogleTest through ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
ROOT=$PWD
cd "${BUILD_DIR:-build}"
# On a fresh build, ctest knows no test's duration and starts them in declaration order: the
# end-to-end scenario (~9 min) came last and ran alone. tests/ctest_costs.txt holds the measured
# seconds of the long tests (names without spaces: CMake 3.25 reads no other), so that they start
# first; ctest replaces the file with its own measurements after the run.
if [ ! -s Testing/Temporary/CTestCostData.txt ]; then
  mkdir -p Testing/Temporary
  cp "$ROOT/tests/ctest_costs.txt" Testing/Temporary/CTestCostData.txt
fi
ctest --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
