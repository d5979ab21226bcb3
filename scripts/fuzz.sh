#!/usr/bin/env bash
# Runs millnet's libFuzzer targets (fuzz/README.md) under ASan + UBSan:
#   scripts/fuzz.sh TARGET|all [SECONDS per target, default 60]
#   FUZZ_RUNS=N scripts/fuzz.sh TARGET|all   N inputs per target from seed 1 instead of a time
#                                            budget: the same inputs on every machine (CI uses it,
#                                            so that CI checks exactly what was run before landing)
# Builds build-fuzz/ with clang first (FUZZ_BUILD_DIR=DIR: a build already configured with
# -DMILLNET_FUZZ=ON instead, e.g. CI's sanitizer build, which carries the targets beside the tests).
# Seeds: fuzz/seeds/<target>/ and the test corpus; the corpus grown by a run stays in
# <build>/corpus/<target> (not in git) and seeds the next run there.
# Exits non-zero on the first finding (crash, leak, timeout > 10 s, RSS > 2 GB, an exception other
# than millnet::Error); the input is kept in <build>/findings/.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh TARGET|all [SECONDS]}
seconds=${2:-60}
scripts/setup.sh
B=${FUZZ_BUILD_DIR:-build-fuzz}
if [ -z "${FUZZ_BUILD_DIR:-}" ]; then
  # -O1 with line tables: libFuzzer's recommended optimisation, and half the sanitizers' compile time
  # of -O2 -g; findings still name file and line.
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DMILLNET_FUZZ=ON -DMILLNET_TESTS=OFF -DMILLNET_BENCH=OFF -DMILLNET_NATIVE=OFF >/dev/null
fi
cmake --build "$B" -j "${JOBS:-$(nproc)}" --target fuzz_all
if [ "$target" = all ]; then
  # The two slowest readers first (Open CASCADE's STEP/IGES and the tool library: 52 s and 40 s of
  # the 184 s of 20,000 inputs each), so that the parallel lanes below end together.
  targets="cad tool_library $(cd fuzz && ls fuzz_*.cpp | sed 's/^fuzz_//; s/\.cpp$//' | grep -v -x -e cad -e tool_library)"
else
  targets=$target
fi
# Seeds from the regression corpus and the shipped data, by reader.
seed_dirs() {
  case $1 in
    pocket_json) echo tests/corpus/pocket ../shared/bench/pockets ;;
    pocket_dxf) echo tests/corpus/pocket ;;
    mesh_stl|mesh_ply|mesh_off|points|cad) echo tests/corpus/mesh ;;
    config) echo tests/corpus/config configs ;;
    tool_library) echo configs ;;
    model) echo tests/corpus/model ;;
    vectors) echo tests/corpus/vectors ;;
    manifest) echo tests/corpus/manifest ;;
    gcode) echo tests/corpus/gcode ;;
    zmap) echo ;;
  esac
}
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p "$B"/findings
# One target: its inputs from its seeds, its log in <build>/fuzz_<target>.log; non-zero on a finding.
fuzz_one() {
  local t=$1
  local corpus=$B/corpus/$t
  mkdir -p "$corpus"
  local seeds=()
  [ -d "fuzz/seeds/$t" ] && seeds+=("fuzz/seeds/$t")
  for d in $(seed_dirs "$t"); do [ -d "$d" ] && seeds+=("$d"); done
  local budget
  if [ -n "${FUZZ_RUNS:-}" ]; then
    budget=(-runs="$FUZZ_RUNS" -seed=1)
    echo "== fuzz_$t: $FUZZ_RUNS inputs from seed 1" >&2
  else
    budget=(-max_total_time="$seconds")
    echo "== fuzz_$t: ${seconds} s" >&2
  fi
  local log=$B/fuzz_$t.log
  if ! "$B/fuzz/fuzz_$t" "$corpus" "${seeds[@]}" "${budget[@]}" -timeout=10 \
       -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
       -artifact_prefix="$B"/findings/"$t"- >"$log" 2>&1; then
    tail -40 "$log" >&2
    echo "fuzz: fuzz_$t found a problem; the input is in $B/findings/" >&2
    return 1
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$log" | sed "s/^/fuzz_$t /" >&2
}
for t in $targets; do
  [ -x "$B/fuzz/fuzz_$t" ] || { echo "fuzz: no target '$t' (see fuzz/)" >&2; exit 2; }
done
# Targets run FUZZ_JOBS at a time (default: the cores; each libFuzzer run is one thread, and each
# target's inputs are its own, from seed 1, whatever runs beside it). The first finding stops the
# targets not yet started; those running finish.
jobs_max=${FUZZ_JOBS:-$(nproc)}
status=0
running=0
for t in $targets; do
  if [ "$running" -ge "$jobs_max" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  [ "$status" -eq 0 ] || break
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done
exit $status
