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

// Issue 39: `millnet train` on a library labelled by virtual machining — outputs are each
// strategy's score (the best 1, the others best time / their time, 0 for a miss), α chosen by the
// leave-one-part-out regret over the scan (classifier::part_out_outputs), the calibration and its
// reliability table. Parts of 22 variants; range(0) parts (500: the library size; the
// target is ≤ 10 s on 2 cores).
void BM_TrainByRegret(benchmark::State& state) {
  const Index parts = state.range(0), n = parts * 22;
  Data s = make(n, 225, 2039, 0.15);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.4, 0.999);
  for (Index i = 0; i < n; i += 22) {  // one score row per part, shared by its variants
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(8);
    Index best = 0;
    s.Y.row(i).maxCoeff(&best);
    for (Index k = 0; k < 5; ++k) row(k) = k == best ? 1.0 : (U(rng) < 0.1 ? 0.0 : U(rng));
    for (Index v = i; v < std::min(n, i + 22); ++v) s.Y.row(v) = row;
  }
  millnet::classifier::TrainingSet set{s.Xn, s.Y, s.groups, {"1", "2", "3", "4", "5", "6", "7", "8"}};
  millnet::classifier::TrainParams params;
  params.criterion = millnet::classifier::Criterion::Regret;
  params.limits.max_pairs = 1e12;
  double alpha = 0;
  for (auto _ : state) {
    const millnet::classifier::Model m = millnet::classifier::train(set, params);
    alpha = m.alpha;
    benchmark::DoNotOptimize(alpha);
  }
  state.counters["N"] = static_cast<double>(n);
}

// Issue 39: predicting one part once the model is loaded: its 22 variants' vectors against a
// library of 500 parts × 22 (the network's outputs, d²_min, the expected regret per strategy).
// The part's own vectors (mesh → height field → 15×15 grid) are BM_SampleGrid15 in bench_ingest.
// Target: ≤ 50 ms.
void BM_PredictPart(benchmark::State& state) {
  static const millnet::classifier::Model model = [] {
    const Data s = make(500 * 22, 225, 2039, 0.15);
    millnet::classifier::TrainParams params;
    params.fixed_alpha = 1.0;
    params.limits.max_pairs = 1e12;
    return millnet::classifier::train({s.Xn, s.Y, s.groups, {"1", "2", "3", "4", "5", "6", "7", "8"}}, params);
  }();
  const Data q = make(22, 225, 99, 0.15);
  for (auto _ : state) {
    const millnet::classifier::Prediction p = millnet::classifier::predict(model, q.Xn);
    const Eigen::MatrixXd r = millnet::classifier::expected_regret(model, q.Xn);
    benchmark::DoNotOptimize(p.probabilities.data());
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["stored"] = static_cast<double>(model.inputs.rows());
}

BENCHMARK(BM_PredictPart)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrainByRegret)->Arg(120)->Arg(500)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_SelectAlpha)->Args({120, 100})->Args({2400, 100})->Args({2400, 15})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelectAlpha)->Args({24000, 100})->Args({24000, 15})->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
