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
# End to end: one default test part labelled by simulation (issue 37 §3): times, memory, thread
# invariance, the preview page's size and render time.
if [ -z "${1:-}" ] || [[ "labelling" =~ ${1} ]]; then
  bench/labelling.sh build
fi
