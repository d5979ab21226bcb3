#!/usr/bin/env bash
# README command 1: set up, build, and run the default pipeline (configs/default.json) into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/app/millnet run configs/default.json --out out "$@"
echo "outputs: $(pwd)/out (summary: out/summary.md)"
