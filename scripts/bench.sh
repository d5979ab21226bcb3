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
# End to end: the five finishing strategies planned and simulated on one default test part
# (issue 9's figure: total wall time on this machine).
if [ -z "${1:-}" ] || [[ "finish" =~ ${1} ]]; then
  echo "== millnet finish --strategy all --simulate (s2_gentle_freeform_01)" >&2
  rm -rf build/bench_finish
  TIMEFORMAT="finish all --simulate: %R s wall"
  time build/app/millnet finish --quiet --mesh datasets/test_parts/s2_gentle_freeform_01.stl --strategy all --simulate \
    --out build/bench_finish
  cat build/bench_finish/s2_gentle_freeform_01.strategies.md
fi
