#!/usr/bin/env bash
# Issue 10's benchmark: labelling N parts by simulation (five finishing strategies planned and
# simulated per part) with 1 rank × 2 threads, then 2 ranks × 1 thread; prints wall times and the
# bytes rank 0 gathered. Figures go into docs/scaling.md, not into tests.
#   [ORDER=mpi-first] [EXTRA=--no-preview] bench/mpi_labelling.sh [BUILD_DIR] [N]     (default build, 20 parts)
# Settings (coarse, so the whole run takes minutes on 2 cores): stepover 1 mm, step-down 1 mm,
# z-map cell 0.1 mm, raster 0.5 mm, 2 variants per part; parts are 10–30 mm height fields.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
N=${2:-20}
EXE=$PWD/$BUILD_DIR/app/millnet
W=$(mktemp -d /tmp/millnet-mpi-bench.XXXXXX)
trap 'rm -rf "$W"' EXIT
python3 - "$W" "$N" <<'PY'
import math, sys, json, os
w, n = sys.argv[1], int(sys.argv[2])
os.makedirs(f"{w}/parts")
parts = []
for k in range(n):
    # a cosine bump or a ridge on a block, sizes 10..30 mm: costs differ by part
    W, D = 10 + (k * 7) % 21, 8 + (k * 5) % 15
    def f(x, y, k=k, W=W, D=D):
        if k % 2 == 0:
            r = math.hypot((x - W / 2) / (W / 2.5), (y - D / 2) / (D / 2.5))
            return 1 + (2 + k % 5) * max(0.0, math.cos(min(r, 1) * math.pi / 2))
        return 1 + (1 + k % 4) * max(0.0, 1 - abs(x - W * 0.4) / (W * 0.3))
    nx, ny = 24, 18
    V = [(W * i / nx, D * j / ny) for j in range(ny + 1) for i in range(nx + 1)]
    tri = []
    def vid(i, j): return j * (nx + 1) + i
    top = [(x, y, f(x, y)) for x, y in V]
    bot = [(x, y, 0.0) for x, y in V]
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            tri += [(top[a], top[b], top[c]), (top[a], top[c], top[d])]
            tri += [(bot[a], bot[c], bot[b]), (bot[a], bot[d], bot[c])]
    ring = [vid(i, 0) for i in range(nx)] + [vid(nx, j) for j in range(ny)] + \
           [vid(i, ny) for i in range(nx, 0, -1)] + [vid(0, j) for j in range(ny, 0, -1)]
    for m in range(len(ring)):
        a, b = ring[m], ring[(m + 1) % len(ring)]
        tri += [(bot[a], bot[b], top[b]), (bot[a], top[b], top[a])]
    name = f"p{k:02d}"
    with open(f"{w}/parts/{name}.stl", "w") as out:
        out.write(f"solid {name}\n")
        for t in tri:
            out.write(" facet normal 0 0 0\n  outer loop\n")
            for v in t: out.write("   vertex %.6f %.6f %.6f\n" % v)
            out.write("  endloop\n endfacet\n")
        out.write(f"endsolid {name}\n")
    parts.append({"file": f"parts/{name}.stl", "label": "simulate"})
cfg = {"dataset": {"parts": parts, "raster_mm": 0.5,
                   "augment": {"angles_deg": [0, 10], "axes": ["x"], "flip": False}},
       "finish": {"stepover_mm": 1.0, "step_down_mm": 1.0}, "simulate": {"cell_mm": 0.1}}
json.dump(cfg, open(f"{w}/cfg.json", "w"))
PY
cd "$W"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN="mpirun --oversubscribe --bind-to none --mca btl self,vader --mca btl_vader_single_copy_mechanism none"
# EXTRA: more flags for both runs, e.g. EXTRA=--no-preview (no 3D pages: 1.2–1.5 MB each, 5 per part).
one_rank() { "$EXE" dataset --quiet --threads 2 --config cfg.json --out one ${EXTRA:-}; }
two_ranks() { $MPIRUN -np 2 "$EXE" dataset --threads 1 --config cfg.json --out two ${EXTRA:-} 2>&1 | grep "work units" || true; }
if [ "${ORDER:-}" = mpi-first ]; then  # the other order, to see the load's drift
  t0=$(date +%s.%N); two_ranks; t1=$(date +%s.%N); one_rank; t2=$(date +%s.%N)
  T1=$(echo "$t2 - $t1" | bc); T2=$(echo "$t1 - $t0" | bc)
else
  t0=$(date +%s.%N); one_rank; t1=$(date +%s.%N); two_ranks; t2=$(date +%s.%N)
  T1=$(echo "$t1 - $t0" | bc); T2=$(echo "$t2 - $t1" | bc)
fi
cmp one/vectors.csv two/vectors.csv && cmp one/manifest.json two/manifest.json && echo "outputs identical"
echo "labelling $N parts: 1 rank x 2 threads $T1 s; 2 ranks x 1 thread $T2 s"
du -sb one/labelling | awk '{print "labelling files: " $1 " bytes"}'
