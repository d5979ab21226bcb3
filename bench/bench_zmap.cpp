// Z-map virtual machining: a 100 × 100 mm gently curved surface at 0.02 mm cells (25 M cells),
// machined by a Ø2 ball raster at 0.2 mm stepover (501 passes, ≈ 50 m of path), the tip following
// the surface's ball-offset height, points every `seg` mm along each pass (arg 0, in µm).
// Counters: cell evaluations per second ("cells × moves"), moves, path length; the wall time of
// one machining is the benchmark's real time. Goal (issue 9): ≤ 5 s on 2 cores.
#include "millnet/simulate/zmap.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

using namespace millnet;
using namespace millnet::simulate;

namespace {

double surface(double x, double y) {
  return 2.0 * std::sin(x / 30.0) * std::cos(y / 40.0) + 0.002 * (x - 50) * (y - 50) / 10;
}

// Tip height of a Ø2 ball resting on the surface (exact on planes, first order in the curvature).
double tip(double x, double y) {
  const double gx = 2.0 / 30 * std::cos(x / 30.0) * std::cos(y / 40.0) + 0.0002 * (y - 50);
  const double gy = -2.0 / 40 * std::sin(x / 30.0) * std::sin(y / 40.0) + 0.0002 * (x - 50);
  return surface(x, y) + std::sqrt(1 + gx * gx + gy * gy) - 1;
}

gcode::Program raster(double seg) {
  gcode::Program p;
  auto add = [&](gcode::Motion m, double x, double y, double z) {
    gcode::Move v;
    v.motion = m;
    v.to = {x, y, z};
    v.feed = m == gcode::Motion::Rapid ? 0 : 1900;
    p.items.emplace_back(v);
  };
  const int passes = 501;
  const auto nseg = static_cast<int>(std::ceil(100.0 / seg));
  add(gcode::Motion::Rapid, 0, 0, 10);
  for (int k = 0; k < passes; ++k) {
    const double y = 0.2 * k;
    const bool fwd = k % 2 == 0;
    if (k == 0) add(gcode::Motion::Line, 0, y, tip(0, y));
    for (int i = 1; i <= nseg; ++i) {
      const double t = std::min(100.0, seg * i);
      const double x = fwd ? t : 100 - t;
      add(gcode::Motion::Line, x, y, tip(x, y));
    }
    if (k + 1 < passes) {  // stepover along the boundary
      const double x = fwd ? 100 : 0, y2 = 0.2 * (k + 1);
      add(gcode::Motion::Line, x, y2, tip(x, y2));
    }
  }
  add(gcode::Motion::Rapid, 100, 100, 10);
  return p;
}

void BM_ZMapBallRaster(benchmark::State& st) {
  const double seg = static_cast<double>(st.range(0)) / 1000.0;
  const gcode::Program prog = raster(seg);
  const GridSpec g{0, 0, 0.02, 5000, 5000};
  ZMap zm = ZMap::flat(g, 5);
  std::uint64_t cells = 0;
  double feed_len = 0;
  for (auto _ : st) {
    st.PauseTiming();
    zm = ZMap::flat(g, 5);
    st.ResumeTiming();
    const auto r = machine(zm, prog, tooling::Cutter::ball(2));
    cells += r.cells_visited;
    feed_len = r.feed_length_mm;
    benchmark::DoNotOptimize(zm.heights().data());
  }
  st.counters["cell_moves_per_s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  st.counters["moves"] = static_cast<double>(prog.items.size());
  st.counters["path_m"] = feed_len / 1000;
  st.counters["cells"] = static_cast<double>(g.cells());
}

// The metrics of the machined surface (deviation, gouge, scallop, Ra map over 25 M cells,
// histogram) after the 1 mm-chord raster, on the interior [5, 95]² (the design is NaN outside, so
// the walls the tool leaves at the raster's edges do not count as scallop); only surface_metrics
// is timed. Theory for the scallop on a plane: 1 − √(1 − 0.1²) mm = 5.01 µm.
void BM_ZMapMetrics(benchmark::State& st) {
  const GridSpec g{0, 0, 0.02, 5000, 5000};
  ZMap zm = ZMap::flat(g, 5);
  (void)machine(zm, raster(1.0), tooling::Cutter::ball(2));
  std::vector<double> design(g.cells());
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const bool in = g.x(ix) > 5 && g.x(ix) < 95 && g.y(iy) > 5 && g.y(iy) < 95;
      design[iy * g.nx + ix] = in ? surface(g.x(ix), g.y(iy)) : std::nan("");
    }
  SurfaceMetrics m;
  for (auto _ : st) {
    m = surface_metrics(zm, design);
    benchmark::DoNotOptimize(m.ra_um.data());
  }
  st.counters["ra_median_um"] = m.ra_median_um;
  st.counters["ra_p90_um"] = m.ra_p90_um;
  st.counters["scallop_max_um"] = 1000 * m.scallop_max_mm;
  st.counters["max_gouge_um"] = 1000 * m.max_gouge_mm;
  st.counters["cells_per_s"] =
      benchmark::Counter(static_cast<double>(g.cells()), benchmark::Counter::kIsIterationInvariantRate);
}

// The rough → finish chain: a Ø10 flat end mill clears the stock in 1 mm levels (zigzag along X at
// 5 mm stepover, each level 0.3 mm above the surface's highest point under the tool, simplified to
// the level's own height), then the Ø2 ball raster (1 mm chords) finishes on the same z-map.
// Reports the largest depth of cut the finishing tool meets.
void BM_ZMapRoughThenFinish(benchmark::State& st) {
  const GridSpec g{0, 0, 0.02, 5000, 5000};
  gcode::Program rough;
  auto add = [&](gcode::Motion m, double x, double y, double z) {
    gcode::Move v;
    v.motion = m;
    v.to = {x, y, z};
    v.feed = m == gcode::Motion::Rapid ? 0 : 3000;
    rough.items.emplace_back(v);
  };
  for (double level = 3; level >= -3; level -= 1) {
    add(gcode::Motion::Rapid, -6, -6, 10);
    add(gcode::Motion::Rapid, -6, -6, level);
    for (int k = 0; k <= 22; ++k) {  // passes at y = −5 … 105
      const double y = -5 + 5.0 * k;
      const bool fwd = k % 2 == 0;
      // Stay 0.3 mm above the surface under the whole Ø10 footprint (sampled coarsely).
      const int n = 111;
      for (int i = 0; i <= n; ++i) {
        const double x = fwd ? -5 + i : 105 - i;
        double top = -1e9;
        for (double u = -5; u <= 5; u += 1)
          for (double v = -5; v <= 5; v += 1) top = std::max(top, surface(x + u, y + v));
        add(gcode::Motion::Line, x, y, std::max(level, top + 0.3));
      }
    }
    add(gcode::Motion::Rapid, -6, 105, 10);
  }
  const gcode::Program fin = raster(1.0);
  double meet = 0, rough_s = 0;
  for (auto _ : st) {
    st.PauseTiming();
    ZMap zm = ZMap::flat(g, 5);
    st.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    (void)machine(zm, rough, tooling::Cutter::flat(10));
    rough_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto r = machine(zm, fin, tooling::Cutter::ball(2));
    meet = r.max_cut_mm[kLineKind];
  }
  st.counters["rough_s"] = rough_s;
  st.counters["rough_moves"] = static_cast<double>(rough.items.size());
  st.counters["finish_max_depth_of_cut_mm"] = meet;
}

}  // namespace

BENCHMARK(BM_ZMapRoughThenFinish)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_ZMapMetrics)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_ZMapBallRaster)->Arg(1000)->Arg(250)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
