// Z-map virtual machining: a 100 × 100 mm gently curved surface at 0.02 mm cells (25 M cells),
// machined by a Ø2 ball raster at 0.2 mm stepover (501 passes, ≈ 50 m of path), the tip following
// the surface's ball-offset height, points every `seg` mm along each pass (arg 0, in µm).
// Counters: cell evaluations per second ("cells × moves"), moves, path length; the wall time of
// one machining is the benchmark's real time. Goal (issue 9): ≤ 5 s on 2 cores.
#include "millnet/simulate/zmap.hpp"

#include <benchmark/benchmark.h>

#include <cmath>

using namespace millnet;
using namespace millnet::simulate;

namespace {

double surface(double x, double y) { return 2.0 * std::sin(x / 30.0) * std::cos(y / 40.0) + 0.002 * (x - 50) * (y - 50) / 10; }

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
    if (k == 0) add(gcode::Motion::Line, 0, y, surface(0, y));
    for (int i = 1; i <= nseg; ++i) {
      const double t = std::min(100.0, seg * i);
      const double x = fwd ? t : 100 - t;
      add(gcode::Motion::Line, x, y, surface(x, y));
    }
    if (k + 1 < passes) {  // stepover along the boundary
      const double x = fwd ? 100 : 0, y2 = 0.2 * (k + 1);
      add(gcode::Motion::Line, x, y2, surface(x, y2));
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
    const auto r = machine(zm, prog, finish::Cutter::ball(2));
    cells += r.cells_visited;
    feed_len = r.feed_length_mm;
    benchmark::DoNotOptimize(zm.heights().data());
  }
  st.counters["cell_moves_per_s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  st.counters["moves"] = static_cast<double>(prog.items.size());
  st.counters["path_m"] = feed_len / 1000;
  st.counters["cells"] = static_cast<double>(g.cells());
}

}  // namespace

BENCHMARK(BM_ZMapBallRaster)->Arg(1000)->Arg(250)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
