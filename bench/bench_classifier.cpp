// Leave-one-out α selection (issue 2 §4 benchmark): N = 120, 2,400, 24,000 stored vectors,
// D = 225 inputs, 40 α candidates (6 decades, 2 per octave), synthetic clustered data: 5 classes,
// parts of 22 near-duplicate variants (like rotated variants of one mould) around class centres.
// Run: bench_classifier --benchmark_counters_tabular=true (OMP_NUM_THREADS sets the threads).
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "millnet/classifier/network.hpp"

namespace {

using Eigen::Index;
using Eigen::MatrixXd;

struct Data {
  MatrixXd Xn, Y;
  std::vector<std::string> groups;
};

Data make(Index n, Index d, unsigned seed, double centre_spread = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N01;
  const int classes = 5, per_part = 22;
  MatrixXd centres(classes, d);
  for (Index i = 0; i < centres.size(); ++i) centres.data()[i] = centre_spread * N01(rng);
  Data s;
  s.Xn.resize(n, d);
  s.Y = MatrixXd::Zero(n, 8);  // 8 strategy slots, 5 used
  Eigen::RowVectorXd part(d);
  int cls = 0;
  for (Index i = 0; i < n; ++i) {
    if (i % per_part == 0) {
      cls = static_cast<int>((i / per_part) % classes);
      for (Index k = 0; k < d; ++k) part(k) = centres(cls, k) + 0.8 * N01(rng);
    }
    for (Index k = 0; k < d; ++k) s.Xn(i, k) = part(k) + 0.15 * N01(rng);
    s.Y(i, cls) = 1.0;
    s.groups.push_back("part" + std::to_string(i / per_part));
  }
  s.Xn = millnet::classifier::Normalizer::fit(s.Xn).apply(s.Xn);
  return s;
}

void BM_SelectAlpha(benchmark::State& state) {
  const Index n = state.range(0);
  // range(1) = class-centre spread in % (100: well separated, the optimum at the scan's low edge;
  // 15: overlapping classes, an interior optimum that both modes refine on grids)
  const Data s = make(n, 225, 2024, static_cast<double>(state.range(1)) / 100.0);
  millnet::classifier::LooReport rep;
  for (auto _ : state) {
    rep = millnet::classifier::select_alpha(s.Xn, s.Y, s.groups, {});
    benchmark::DoNotOptimize(rep.alpha);
  }
  state.counters["N"] = static_cast<double>(n);
  state.counters["candidates"] = static_cast<double>(rep.curve.size());
  state.counters["alpha"] = rep.alpha;
  state.counters["rms_part"] = rep.rms_part_at_alpha;
  state.counters["rms_vector"] = rep.rms_vector_at_alpha;
  state.counters["acc_part"] = rep.accuracy_part_at_alpha;
  state.counters["full_passes"] = rep.full_passes;
  state.counters["refine_evals"] = rep.part.refine_evaluations + rep.vector.refine_evaluations;
  state.counters["edge_part"] = rep.part.edge == millnet::classifier::Edge::None ? 0 : 1;
}

}  // namespace

BENCHMARK(BM_SelectAlpha)->Args({120, 100})->Args({2400, 100})->Args({2400, 15})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelectAlpha)->Args({24000, 100})->Args({24000, 15})->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
