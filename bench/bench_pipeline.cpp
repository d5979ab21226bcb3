// Issue 5 roughing throughput: a 1,000,000-triangle closed part (wavy top over 200 × 200 mm) roughed
// in 10 Z levels, split into slicing (the stock height field + material_contours per level) and
// planning + machining (regions → planner → feed maps → G-code), with SOM and with zigzag.
//   bench_pipeline --benchmark_filter=Rough
// The time per stage of `millnet run` comes from run_report.json ("timing"), see test_scenario.
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/zlevels.hpp"
#include "millnet/rough/rough.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

using namespace millnet;

namespace {

constexpr int kCells = 706;    // top grid cells per side: 2·706² = 996,872 top triangles
constexpr double kSide = 200;  // mm
constexpr double kFloor = 6;   // the wavy top stays above z = 6, so every level cuts it
constexpr int kLevels = 10;

// Closed height-field solid: wavy top (z 7..33 mm), vertical walls, flat bottom at z = 0;
// 996,872 + 4·2·706 + 2 = 1,002,522 triangles. O(kCells²).
const ingest::Mesh& wavy_part() {
  static const ingest::Mesh m = [] {
    const int n = kCells + 1;
    ingest::Mesh w;
    const auto top = [](double x, double y) {
      return 20 + 9 * std::sin(x / 13) * std::cos(y / 17) + 4 * std::sin((x + 2 * y) / 29);
    };
    w.V.resize(static_cast<Eigen::Index>(2 * n * n), 3);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = kSide * j / kCells, y = kSide * i / kCells;
        w.V.row(i * n + j) << x, y, top(x, y);
        w.V.row(n * n + i * n + j) << x, y, 0;  // bottom grid (only its border and corners are used)
      }
    std::vector<std::array<int, 3>> f;
    f.reserve(static_cast<std::size_t>(2 * kCells * kCells + 8 * kCells + 2));
    for (int i = 0; i < kCells; ++i)
      for (int j = 0; j < kCells; ++j) {
        const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
        f.push_back({a, b, d});
        f.push_back({a, d, c});
      }
    // Walls: for each border edge (p → q, counter-clockwise seen from above) the quad p q q' p'.
    const int B = n * n;
    auto wall = [&](int p, int q) {
      f.push_back({p, B + p, B + q});
      f.push_back({p, B + q, q});
    };
    for (int k = 0; k < kCells; ++k) {
      wall(k, k + 1);                              // y = 0, x increasing
      wall(k * n + kCells, (k + 1) * n + kCells);  // x = side, y increasing
      wall(kCells * n + k + 1, kCells * n + k);    // y = side, x decreasing
      wall((k + 1) * n, k * n);                    // x = 0, y decreasing
    }
    const int c00 = B, c10 = B + kCells, c01 = B + kCells * n, c11 = B + kCells * n + kCells;
    f.push_back({c00, c11, c10});  // bottom faces −z
    f.push_back({c00, c01, c11});
    w.F.resize(static_cast<Eigen::Index>(f.size()), 3);
    for (std::size_t t = 0; t < f.size(); ++t) w.F.row(static_cast<Eigen::Index>(t)) << f[t][0], f[t][1], f[t][2];
    return w;
  }();
  return m;
}

/// The default config's roughing (schema defaults, seed 7, zigzag: I-partition, angle searched), with
/// 10 equal levels down to kFloor.
rough::Params params(bool som) {
  rough::Params p;
  if (som) {
    pocket::SomSpec s;
    s.frame.spacing = p.cut.stepover;
    s.som.seed = 7;
    p.planner = s;
  } else {
    pocket::ZigzagSpec z;
    z.zigzag.angle_deg = std::nullopt;
    z.zigzag.partition = pocket::PartitionKind::I;
    p.planner = z;
  }
  const ingest::Mesh& m = wavy_part();
  const double top = m.V.col(2).maxCoeff();
  // Stock top = top + 1; 10 equal levels down to kFloor.
  p.cut.step_down = (top + 1 - kFloor) / kLevels;
  p.floor_allowance_mm = kFloor;
  return p;
}

// The slicing alone, as rough_mesh does it: the stock height field, then one material_contours per level.
void BM_RoughSlicing(benchmark::State& state) {
  const ingest::Mesh& m = wavy_part();
  const rough::Params p = params(true);
  const double x0 = -p.stock.margin_mm, x1 = kSide + p.stock.margin_mm,
               top = m.V.col(2).maxCoeff() + p.top_allowance_mm;
  const int nx = static_cast<int>(std::ceil((x1 - x0) / p.raster_mm)) + 1;
  double raster_s = 0;
  std::size_t loops = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const ingest::HeightField f = ingest::rasterize_top(m, x0, x0, p.raster_mm, nx, nx);
    raster_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    loops = 0;
    const double dz = (top - kFloor) / kLevels;
    for (int k = 1; k <= kLevels; ++k)
      loops += ingest::material_contours(f, top - k * dz, p.contour_tolerance_mm).size();
    benchmark::DoNotOptimize(loops);
  }
  state.counters["triangles"] = static_cast<double>(m.F.rows());
  state.counters["raster_s"] = raster_s;
  state.counters["loops"] = static_cast<double>(loops);
}
BENCHMARK(BM_RoughSlicing)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// The whole roughing (slicing + planning + machining); arg 0 = SOM, 1 = zigzag.
void BM_RoughMesh(benchmark::State& state) {
  const ingest::Mesh& m = wavy_part();
  const rough::Params p = params(state.range(0) == 0);
  rough::Result r;
  for (auto _ : state) {
    r = rough::rough_mesh(m, p);
    benchmark::DoNotOptimize(gcode::write(r.machining.program, gcode::linuxcnc()).data());
  }
  if (r.machining.status != pocket::PlanStatus::Ok || static_cast<int>(r.levels.size()) != kLevels) {
    state.SkipWithError("roughing failed or wrong level count");
    return;
  }
  std::size_t islands = 0;
  for (const auto& lv : r.levels) islands += lv.islands;
  state.SetLabel(std::string(pocket::planner_name(p.planner)));
  state.counters["triangles"] = static_cast<double>(m.F.rows());
  state.counters["levels"] = static_cast<double>(r.levels.size());
  state.counters["islands"] = static_cast<double>(islands);
  state.counters["tool_points"] = static_cast<double>(r.tool_points);
  state.counters["cut_m"] = r.machining.metrics.cut_length_mm / 1000;
  state.counters["gcode_MB"] = static_cast<double>(gcode::write(r.machining.program, gcode::linuxcnc()).size()) / 1e6;
}
BENCHMARK(BM_RoughMesh)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
