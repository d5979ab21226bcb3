#!/usr/bin/env bash
# README command 2: set up, build, and run every test (GoogleTest through ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
cd "${BUILD_DIR:-build}"
# ctest starts the tests that took longest last time first; on a first run it has no such record
# and would start the ten-minute pipeline scenario last, on one core, after everything else. A
# first record names it (ctest rewrites the file after every run).
if [ ! -s Testing/Temporary/CTestCostData.txt ]; then
  mkdir -p Testing/Temporary
  printf 'Scenario.DefaultPipelineRunsEndToEndAndMeetsItsFigures 1 600\n---\n' > Testing/Temporary/CTestCostData.txt
fi
ctest --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
