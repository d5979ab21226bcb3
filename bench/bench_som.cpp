// SOM tour timing on 1k / 10k / 100k random and grid points (one core), and plan_som on the three bench
// pockets (tool Ø10, stepover 5, grid anchored at (0, 0)) with the figures as counters:
// N, cut length, rapid length, retractions, cut / ((N − 1)·stepover).
#include "millnet/pocket/planner_som.hpp"

#include <benchmark/benchmark.h>

#include "millnet/pocket/io/pocket_io.hpp"

#include <cmath>

namespace mp = millnet::pocket;

namespace {

std::vector<mp::Vec2> random_points(std::size_t n) {
  mp::Rng rng(20240601);
  std::vector<mp::Vec2> p(n);
  const double side = 5.0 * std::sqrt(static_cast<double>(n));  // density of a 5 mm grid
  for (auto& q : p) q = mp::Vec2(side * rng.uniform(), side * rng.uniform());
  return p;
}

std::vector<mp::Vec2> grid_points(std::size_t n) {
  const auto s = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  std::vector<mp::Vec2> p;
  for (int i = 0; i < s; ++i)
    for (int j = 0; j < s; ++j) p.emplace_back(5.0 * j, 5.0 * i);
  return p;
}

void run_som(benchmark::State& state, const std::vector<mp::Vec2>& pts, double bound) {
  mp::SomResult r;
  for (auto _ : state) {
    r = mp::som_tour(pts, {});
    benchmark::DoNotOptimize(r.order.data());
  }
  const double len = mp::tour_length(pts, r.order, true);
  state.counters["N"] = static_cast<double>(pts.size());
  state.counters["passes"] = r.passes;
  state.counters["tour_mm"] = len;
  // random: tour / sqrt(N·A) (≈ 0.7124 for an optimal tour, Beardwood–Halton–Hammersley); grid: tour / (N·g)
  state.counters["tour_ratio"] = len / bound;
}

void BM_SomRandom(benchmark::State& state) {
  const auto pts = random_points(static_cast<std::size_t>(state.range(0)));
  const double side = 5.0 * std::sqrt(static_cast<double>(pts.size()));
  run_som(state, pts, std::sqrt(static_cast<double>(pts.size())) * side);
}
void BM_SomGrid(benchmark::State& state) {
  const auto pts = grid_points(static_cast<std::size_t>(state.range(0)));
  run_som(state, pts, 5.0 * static_cast<double>(pts.size()));
}
BENCHMARK(BM_SomRandom)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SomGrid)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(1);

mp::Region load_pocket(const std::string& name) {
  return mp::read_pocket(std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json").region;
}

void BM_PlanSom(benchmark::State& state, const char* name, bool linking) {
  const mp::Region region = load_pocket(name);
  mp::CutParams cut;
  cut.tool.diameter = 10;
  cut.stepover = 5;
  const mp::GridFrame frame{{0, 0}, 0, cut.stepover};
  mp::SmoothingParams sp;
  if (!linking) sp = {.linking = false, .weak = true, .extra_passes = false};  // the seed's postprocessing
  mp::PlanResult r;
  for (auto _ : state) {
    r = mp::plan_som(region, cut, frame, {}, sp);
    benchmark::DoNotOptimize(r.path.chains.data());
  }
  const mp::SomStats& st = std::get<mp::SomStats>(r.stats);
  const double n = static_cast<double>(st.tool_points);
  state.counters["N"] = n;
  state.counters["cut_mm"] = r.path.cut_length();
  state.counters["rapid_mm"] = r.path.rapid_length();
  state.counters["retractions"] = static_cast<double>(r.path.retractions());
  state.counters["regions"] = st.smoothing.reachable_regions;
  state.counters["cut_over_bound"] = r.path.cut_length() / ((n - 1) * cut.stepover);
  state.counters["som_mm"] = st.smoothing.som_tour_length_mm;
  state.counters["weak_saved"] = st.smoothing.weak.saved_mm;
  state.counters["opt_saved"] = st.smoothing.two_opt_saved_mm;
  state.counters["links"] = st.smoothing.links;
  state.counters["plan_s"] = r.planning_time_s;
}
BENCHMARK_CAPTURE(BM_PlanSom, four_islands, "four_islands", true)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_PlanSom, comb, "comb", true)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_PlanSom, eight_islands, "eight_islands", true)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_PlanSom, four_islands_seed, "four_islands", false)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_PlanSom, comb_seed, "comb", false)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_PlanSom, eight_islands_seed, "eight_islands", false)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
