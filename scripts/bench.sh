#!/usr/bin/env bash
# Builds and runs every benchmark (bench/bench_*.cpp); pass a filter regex as $1.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
for b in build/bench/bench_*; do
  [ -x "$b" ] || continue
  echo "== $b" >&2
  "$b" --benchmark_filter="${1:-.}"
done
