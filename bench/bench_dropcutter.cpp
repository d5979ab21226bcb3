// Drop-cutter throughput (issue 9, Benchmarks): CL points per second for a Ø2 ball over a 0.1 mm
// grid, with 1 and 2 threads, on a small generated mould part (~4k triangles, datasets::make_part;
// no real mesh ships with the repo) and on a generated 1,000,000-triangle terrain (200 × 200 mm),
// plus the index set-up time. Counters: items_per_second = CL points/s; setup_s; triangles.
#include "millnet/datasets/generator.hpp"
#include "millnet/finish/dropcutter.hpp"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <chrono>
#include <memory>

using namespace millnet;
using namespace millnet::finish;
using millnet::tooling::Cutter;
using millnet::tooling::CutterType;

namespace {

/// Open height-field terrain over [0, size]² with n×n vertices (2·(n−1)² triangles).
ingest::Mesh terrain(int n, double size) {
  ingest::Mesh m;
  const auto nn = static_cast<Eigen::Index>(n);
  m.V.resize(nn * nn, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = size * j / (n - 1), y = size * i / (n - 1);
      const double z = 10 + 6 * std::sin(x / 17) * std::cos(y / 23) + 2 * std::sin(x / 5 + y / 7) +
                       0.4 * std::sin(1.3 * x) * std::cos(1.1 * y);
      m.V.row(static_cast<Eigen::Index>(i) * nn + j) << x, y, z;
    }
  m.F.resize(2 * (nn - 1) * (nn - 1), 3);
  Eigen::Index t = 0;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      m.F.row(t++) << a, b, d;
      m.F.row(t++) << a, d, c;
    }
  return m;
}

const ingest::Mesh& small_part() {
  // Deep cavity family (steep walls, flat floors): 2·(res−1)² top + bottom + walls ≈ 4k triangles.
  static const ingest::Mesh m = datasets::make_part(datasets::Family::DeepCavity, 0, 7, 43).mesh;
  return m;
}
const ingest::Mesh& big_terrain() {
  static const ingest::Mesh m = terrain(709, 200);  // 2·708² = 1,002,528 triangles
  return m;
}

void BM_Setup(benchmark::State& st, const ingest::Mesh& (*mesh)()) {
  const ingest::Mesh& m = mesh();
  omp_set_num_threads(static_cast<int>(st.range(0)));
  for (auto _ : st) {
    DropCutter dc(m, Cutter::ball(2));
    benchmark::DoNotOptimize(dc);
  }
  st.counters["triangles"] = static_cast<double>(m.F.rows());
}

/// The 0.1 mm grid: over a w × w mm window centred on the footprint, or (w = 0) over the whole
/// footprint grown by the cutter radius.
struct Window {
  double x0, y0;
  int nx, ny;
};
Window window(const ingest::Mesh& m, double w) {
  const auto b = ingest::bounds(m);
  if (w <= 0) {
    const double x0 = b.min.x() - 1, y0 = b.min.y() - 1;
    return {x0, y0, static_cast<int>(std::lround((b.max.x() + 1 - x0) / 0.1)) + 1,
            static_cast<int>(std::lround((b.max.y() + 1 - y0) / 0.1)) + 1};
  }
  const double cx = 0.5 * (b.min.x() + b.max.x()), cy = 0.5 * (b.min.y() + b.max.y());
  const int n = static_cast<int>(std::lround(w / 0.1));
  return {cx - w / 2, cy - w / 2, n, n};
}

void BM_Grid(benchmark::State& st, const ingest::Mesh& (*mesh)(), double w, Cutter cutter = Cutter::ball(2)) {
  const ingest::Mesh& m = mesh();
  omp_set_num_threads(static_cast<int>(st.range(0)));
  const Window win = window(m, w);
  const auto t0 = std::chrono::steady_clock::now();
  const DropCutter dc(m, cutter);
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t contacts = 0;
  for (auto _ : st) {
    const std::vector<double> z = dc.drop_grid(win.x0, win.y0, 0.1, win.nx, win.ny);
    contacts = 0;
    for (const double v : z) contacts += std::isfinite(v) ? 1u : 0u;
    benchmark::DoNotOptimize(z.data());
  }
  const double points = static_cast<double>(win.nx) * win.ny;
  st.SetItemsProcessed(static_cast<std::int64_t>(static_cast<double>(st.iterations()) * points));
  st.counters["triangles"] = static_cast<double>(m.F.rows());
  st.counters["setup_s"] = setup;
  st.counters["points"] = points;
  st.counters["contacts"] = static_cast<double>(contacts);
}

/// The same through drop(vector<Vector2d>) (full CLPoints).
void BM_Points(benchmark::State& st, const ingest::Mesh& (*mesh)(), double w) {
  const ingest::Mesh& m = mesh();
  omp_set_num_threads(static_cast<int>(st.range(0)));
  const Window win = window(m, w);
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < win.ny; ++i)
    for (int j = 0; j < win.nx; ++j) pts.emplace_back(win.x0 + 0.1 * j, win.y0 + 0.1 * i);
  const DropCutter dc(m, Cutter::ball(2));
  for (auto _ : st) {
    const std::vector<CLPoint> cl = dc.drop(pts);
    benchmark::DoNotOptimize(cl.data());
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(pts.size()));
}

}  // namespace

BENCHMARK_CAPTURE(BM_Setup, small_part, &small_part)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Setup, terrain_1M, &big_terrain)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
// Small part: the 0.1 mm grid over the whole footprint + 1 mm (walls, floors, rims, outside).
BENCHMARK_CAPTURE(BM_Grid, small_part, &small_part, 0.0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Points, small_part, &small_part, 0.0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Terrain: a 30 × 30 mm window (90,000 points) of the 200 × 200 mm, 1M-triangle terrain.
BENCHMARK_CAPTURE(BM_Grid, terrain_1M, &big_terrain, 30.0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Points, terrain_1M, &big_terrain, 30.0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Other cutters, for comparison (not goals): flat Ø2 and bull Ø2 r0.5 on the terrain window.
BENCHMARK_CAPTURE(BM_Grid, terrain_1M_flat, &big_terrain, 30.0, Cutter::flat(2))
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Grid, terrain_1M_bull, &big_terrain, 30.0, Cutter::bull(2, 0.5))
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
