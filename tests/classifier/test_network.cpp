// Grabec network, normalizer and leave-one-out α selection (issue 2 §4).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "millnet/classifier/network.hpp"
#include "millnet/classifier/normalizer.hpp"
#include "millnet/core/error.hpp"

using namespace millnet::classifier;
using Eigen::Index;
using Eigen::MatrixXd;

namespace {

// Brute-force reference: full N×N (or M×N) distances by explicit loops, std::exp, no blocks.
// mode: 0 = part-out, 1 = vector-out, 2 = filtration.
MatrixXd reference_outputs(const MatrixXd& X, const MatrixXd& Y, const std::vector<std::string>& g, double alpha,
                           int mode) {
  const Index n = X.rows();
  MatrixXd out = MatrixXd::Zero(n, Y.cols());
  for (Index i = 0; i < n; ++i) {
    std::vector<double> d(static_cast<std::size_t>(n));
    std::vector<bool> use(static_cast<std::size_t>(n), true);
    double m = INFINITY;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      d[uj] = (X.row(i) - X.row(j)).squaredNorm();
      if (mode == 0 && g[uj] == g[static_cast<std::size_t>(i)]) use[uj] = false;
      if (mode == 1 && j == i) use[uj] = false;
      if (use[uj]) m = std::min(m, d[uj]);
    }
    double tot = 0;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      if (!use[uj]) continue;
      const double s = std::exp(-(d[uj] - m) / alpha);
      tot += s;
      out.row(i) += s * Y.row(j);
    }
    out.row(i) /= tot;
  }
  return out;
}

// Clustered synthetic set: `classes` centres in D dims (spread `sep`), parts of `per_part` vectors
// around a part centre (spread `part_noise` around its class centre, `vec_noise` within the part).
struct Synthetic {
  MatrixXd X, Y;
  std::vector<std::string> groups;
};
Synthetic make_clusters(unsigned seed, int classes, int parts_per_class, int per_part, Index D, double sep,
                        double part_noise, double vec_noise, bool random_labels = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N01(0.0, 1.0);
  std::uniform_int_distribution<int> cls(0, classes - 1);
  MatrixXd centres(classes, D);
  for (Index i = 0; i < centres.size(); ++i) centres.data()[i] = sep * N01(rng);
  Synthetic s;
  const int n = classes * parts_per_class * per_part;
  s.X.resize(n, D);
  s.Y = MatrixXd::Zero(n, classes);
  int row = 0;
  for (int c = 0; c < classes; ++c)
    for (int p = 0; p < parts_per_class; ++p) {
      Eigen::RowVectorXd pc(D);
      for (Index k = 0; k < D; ++k) pc(k) = centres(c, k) + part_noise * N01(rng);
      const int label = random_labels ? cls(rng) : c;
      for (int v = 0; v < per_part; ++v, ++row) {
        for (Index k = 0; k < D; ++k) s.X(row, k) = pc(k) + vec_noise * N01(rng);
        s.Y(row, label) = 1.0;
        s.groups.push_back("part" + std::to_string(c) + "_" + std::to_string(p));
      }
    }
  return s;
}

bool bitwise_equal(const MatrixXd& a, const MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// The same search with and without a pre-scan (or any other route to the same figures): every
// reported α, figure and output bit for bit.
void expect_same_bits(const LooReport& a, const LooReport& b) {
  EXPECT_EQ(std::memcmp(&a.alpha, &b.alpha, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.part.alpha, &b.part.alpha, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.part.rms, &b.part.rms, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.vector.alpha, &b.vector.alpha, sizeof(double)), 0);
  EXPECT_TRUE(bitwise_equal(a.verification, b.verification));
  EXPECT_TRUE(bitwise_equal(a.filtration, b.filtration));
}

// Each mode's refined optimum: its figure is the reference's at its α, and no scan point is better.
void expect_optima_match_reference(const LooReport& rep, const MatrixXd& Xn, const Synthetic& s) {
  for (const ModeOptimum* o : {&rep.part, &rep.vector}) {
    const int om = o == &rep.part ? 0 : 1;
    const double ro = rms_error(reference_outputs(Xn, s.Y, s.groups, o->alpha, om), s.Y);
    EXPECT_NEAR(o->rms, ro, 1e-12 * std::max(1.0, ro)) << "mode " << om;
    for (const auto& p : rep.curve) EXPECT_LE(o->rms, (om == 0 ? p.rms_part : p.rms_vector) + 1e-12);
  }
}

}  // namespace

TEST(Normalizer, HandComputedMeanStdAndConstantColumn) {
  MatrixXd X(3, 2);
  X << 0, 5, 1, 5, 3, 5;
  const Normalizer n = Normalizer::fit(X);
  EXPECT_DOUBLE_EQ(n.mean(0), 4.0 / 3.0);
  EXPECT_NEAR(n.std(0), 1.247219128924647, 1e-15);  // sqrt(14/9): population std of {0,1,3}
  EXPECT_EQ(n.mean(1), 5.0);
  EXPECT_EQ(n.std(1), 1.0);  // constant column: std stored as 1
  const MatrixXd Z = n.apply(X);
  EXPECT_NEAR(Z(2, 0), (3.0 - 4.0 / 3.0) / 1.247219128924647, 1e-15);
  EXPECT_EQ(Z(0, 1), 0.0);
  EXPECT_NEAR(Z.col(0).mean(), 0.0, 1e-15);
  EXPECT_THROW((void)n.apply(MatrixXd::Zero(1, 3)), millnet::Error);
}

TEST(Network, ThreeVectorExampleByHand) {
  // stored x = 0, 1, 3 (already normalized), classes A, A, B; query 0.5, α = 1:
  // d² = 0.25, 0.25, 6.25 → s = 1, 1, e^-6 → outputs (2, e^-6)/(2 + e^-6).
  MatrixXd X(3, 1), Y(3, 2), Q(1, 1);
  X << 0, 1, 3;
  Y << 1, 0, 1, 0, 0, 1;
  Q << 0.5;
  const NetworkOutputs r = evaluate_network(X, Y, Q, 1.0);
  EXPECT_NEAR(r.outputs(0, 0), 0.9987621580633643, 1e-15);
  EXPECT_NEAR(r.outputs(0, 1), 0.001237841936635777, 1e-15);
  EXPECT_DOUBLE_EQ(r.d2_min(0), 0.25);
  EXPECT_EQ(r.nearest(0), 0);
  // per-vector leave-one-out at α = 1, by hand:
  //  x=0: others d² 1, 9 → (1, e^-8)/(1+e^-8); x=1: d² 1, 4 → (1, e^-3)/(1+e^-3);
  //  x=3: d² 9, 4 → all weight on class A although it is B: squared error 2.
  const std::vector<std::string> g{"a", "b", "c"};
  const MatrixXd v = verification_outputs(X, Y, g, 1.0, LooMode::VectorOut, 2);
  EXPECT_NEAR(v(0, 1), 0.00033535013046647816, 1e-15);
  EXPECT_NEAR(v(1, 1), 0.04742587317756679, 1e-15);
  EXPECT_NEAR(v(2, 0), 1.0, 1e-15);
  EXPECT_NEAR(rms_error(v, Y), 0.5779992289228896, 1e-15);
  EXPECT_NEAR(argmax_accuracy(v, Y), 2.0 / 3.0, 1e-15);
}

TEST(Network, HugeAlphaGivesClassPriors) {
  const Synthetic s = make_clusters(11, 3, 3, 4, 5, 3.0, 0.5, 0.1);
  // unbalanced: drop the last 5 vectors
  const MatrixXd X = s.X.topRows(31), Y = s.Y.topRows(31);
  const Eigen::RowVectorXd priors = Y.colwise().mean();
  const NetworkOutputs r = evaluate_network(X, Y, X, 1e14);  // filtration: self included
  for (Index i = 0; i < X.rows(); ++i) EXPECT_LT((r.outputs.row(i) - priors).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Network, TinyAlphaGivesNearestNeighbour) {
  std::mt19937_64 rng(20240521);
  std::normal_distribution<double> N01;
  MatrixXd X(40, 6), Y = MatrixXd::Zero(40, 4), Q(25, 6);
  for (Index i = 0; i < X.size(); ++i) X.data()[i] = N01(rng);
  for (Index i = 0; i < Q.size(); ++i) Q.data()[i] = N01(rng);
  for (Index i = 0; i < 40; ++i) Y(i, i % 4) = 1;
  const NetworkOutputs r = evaluate_network(X, Y, Q, 1e-9);
  for (Index q = 0; q < Q.rows(); ++q) {
    Index best = 0;
    double b1 = INFINITY, b2 = INFINITY;
    for (Index j = 0; j < X.rows(); ++j) {
      const double d = (Q.row(q) - X.row(j)).squaredNorm();
      if (d < b1) { b2 = b1; b1 = d; best = j; } else if (d < b2) b2 = d;
    }
    ASSERT_GT(b2 - b1, 1e-6) << "seed 20240521: nearest neighbour ambiguous at query " << q;
    EXPECT_EQ(r.nearest(q), best);
    EXPECT_NEAR(r.d2_min(q), b1, 1e-12);
    EXPECT_LT((r.outputs.row(q) - Y.row(best)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(Network, UnderflowGivesNoNaNAndTheNearestAnswer) {
  // Every exp(−d²/α) underflows to 0 (d² ~ 1e6, α = 1e-3): without subtracting d²_min this is 0/0.
  MatrixXd X(3, 2), Y(3, 3), Q(1, 2);
  X << 0, 0, 10, 0, 0, 10;
  Y = MatrixXd::Identity(3, 3);
  Q << 1000, 3;
  const NetworkOutputs r = evaluate_network(X, Y, Q, 1e-3);
  ASSERT_TRUE(r.outputs.allFinite());
  EXPECT_EQ(r.nearest(0), 1);
  EXPECT_NEAR(r.outputs(0, 1), 1.0, 1e-15);
  EXPECT_NEAR(r.d2_min(0), 990.0 * 990.0 + 9.0, 1e-6);
  // the same through verification: a far outlier in LOO
  const MatrixXd v = verification_outputs(X * 1e4, Y, {"a", "b", "c"}, 1e-3, LooMode::PartOut);
  EXPECT_TRUE(v.allFinite());
}

TEST(Loo, BlockedEqualsBruteForceReference) {
  const unsigned seed = 7;
  Synthetic s = make_clusters(seed, 4, 4, 9, 7, 2.0, 1.0, 0.3);  // N = 144
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  for (double alpha : {0.05, 1.0, 30.0}) {
    for (int mode : {0, 1}) {
      const MatrixXd ref = reference_outputs(Xn, s.Y, s.groups, alpha, mode);
      const MatrixXd got =
          verification_outputs(Xn, s.Y, s.groups, alpha, mode == 0 ? LooMode::PartOut : LooMode::VectorOut, 16);
      EXPECT_LT((ref - got).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " alpha " << alpha << " mode " << mode;
    }
  }
  AlphaSearchParams prm;
  prm.block_rows = 16;      // 144 = 9 blocks: exercises the block combination
  prm.cache_neighbours = 40;
  const LooReport rep = select_alpha(Xn, s.Y, s.groups, prm);
  ASSERT_GE(rep.curve.size(), 20u);
  // every scan point (squaring chains) against the reference
  for (const auto& p : rep.curve) {
    const double rp = rms_error(reference_outputs(Xn, s.Y, s.groups, p.alpha, 0), s.Y);
    const double rv = rms_error(reference_outputs(Xn, s.Y, s.groups, p.alpha, 1), s.Y);
    EXPECT_NEAR(p.rms_part, rp, 1e-9 * std::max(1.0, rp)) << "alpha " << p.alpha;
    EXPECT_NEAR(p.rms_vector, rv, 1e-9 * std::max(1.0, rv)) << "alpha " << p.alpha;
  }
  const MatrixXd ver = reference_outputs(Xn, s.Y, s.groups, rep.alpha, 0);
  const MatrixXd fil = reference_outputs(Xn, s.Y, s.groups, rep.alpha, 2);
  EXPECT_LT((ver - rep.verification).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((fil - rep.filtration).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(rep.rms_part_at_alpha, rms_error(ver, s.Y), 1e-12);
  EXPECT_NEAR(rep.rms_vector_at_alpha, rms_error(reference_outputs(Xn, s.Y, s.groups, rep.alpha, 1), s.Y), 1e-12);
  // the refined optimum is no worse than any scan point
  for (const auto& p : rep.curve) EXPECT_LE(rep.part.rms, p.rms_part + 1e-12);
}

TEST(Loo, PicksAlphaWithFullAccuracyOnSeparatedData) {
  const unsigned seed = 42;
  const Synthetic s = make_clusters(seed, 5, 4, 6, 12, 6.0, 0.4, 0.1);
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  const LooReport rep = select_alpha(Xn, s.Y, s.groups, {});
  EXPECT_EQ(rep.mode, LooMode::PartOut);
  EXPECT_EQ(rep.accuracy_part_at_alpha, 1.0) << "seed " << seed;
  EXPECT_EQ(argmax_accuracy(rep.verification, s.Y), 1.0);
  // perfectly separated: the nearest other part is always of the right class, so the RMS falls
  // towards α → 0 and the optimum may sit at the low edge; it must never be the priors' end
  EXPECT_NE(rep.part.edge, Edge::High);
  EXPECT_LT(rep.part.rms, 0.05);
  EXPECT_GE(rep.curve.size(), 20u);
  EXPECT_TRUE(rep.neighbour_cache_used);
  // probabilities: filtration and verification rows sum to 1
  for (Index i = 0; i < s.X.rows(); ++i) {
    EXPECT_NEAR(rep.filtration.row(i).sum(), 1.0, 1e-12);
    EXPECT_NEAR(rep.verification.row(i).sum(), 1.0, 1e-12);
  }
}

TEST(Loo, VectorOutIsFooledByNearDuplicateSiblingsPartOutIsNot) {
  // Parts with random labels and 8 near-identical variants each: a vector's sibling always has
  // its label, another part's label is a coin toss.
  const unsigned seed = 1234;
  const Synthetic s = make_clusters(seed, 4, 6, 8, 10, 1.0, 1.0, 1e-4, /*random_labels=*/true);
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  AlphaSearchParams prm;
  prm.mode = LooMode::VectorOut;
  const LooReport rv = select_alpha(Xn, s.Y, s.groups, prm);
  EXPECT_EQ(rv.vector.edge, Edge::Low) << "seed " << seed;
  EXPECT_LT(rv.vector.rms, 1e-6);
  EXPECT_GT(rv.part.rms, 0.2);  // the honest figure
  EXPECT_NE(rv.part.edge, Edge::Low);
  EXPECT_GT(rv.part.alpha, 100.0 * rv.vector.alpha);
  prm.mode = LooMode::PartOut;
  const LooReport rp = select_alpha(Xn, s.Y, s.groups, prm);
  EXPECT_DOUBLE_EQ(rp.alpha, rv.part.alpha);
  EXPECT_DOUBLE_EQ(rp.rms_part_at_alpha, rp.part.rms);
  EXPECT_GT(rp.rms_part_at_alpha, 0.2);
}

TEST(Loo, ThreadCountDoesNotChangeAnyBit) {
  const Synthetic s = make_clusters(99, 4, 5, 11, 15, 2.0, 0.8, 0.2);  // N = 220
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  AlphaSearchParams prm;
  prm.block_rows = 32;
  prm.cache_neighbours = 30;  // small: forces some full passes too
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const LooReport a = select_alpha(Xn, s.Y, s.groups, prm);
  const NetworkOutputs na = evaluate_network(Xn, s.Y, Xn * 0.9, a.alpha, 32);
  omp_set_num_threads(2);
  const LooReport b = select_alpha(Xn, s.Y, s.groups, prm);
  const NetworkOutputs nb = evaluate_network(Xn, s.Y, Xn * 0.9, a.alpha, 32);
  omp_set_num_threads(saved);
  ASSERT_EQ(a.curve.size(), b.curve.size());
  for (std::size_t i = 0; i < a.curve.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.curve[i].rms_part, &b.curve[i].rms_part, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&a.curve[i].rms_vector, &b.curve[i].rms_vector, sizeof(double)), 0);
  }
  EXPECT_EQ(std::memcmp(&a.alpha, &b.alpha, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.rms_part_at_alpha, &b.rms_part_at_alpha, sizeof(double)), 0);
  EXPECT_TRUE(bitwise_equal(a.verification, b.verification));
  EXPECT_TRUE(bitwise_equal(a.filtration, b.filtration));
  EXPECT_TRUE(bitwise_equal(na.outputs, nb.outputs));
}

TEST(Loo, EdgeOfScanIsReported) {
  const Synthetic s = make_clusters(5, 3, 4, 5, 8, 6.0, 0.3, 0.1);
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  AlphaSearchParams prm;
  prm.alpha_min = 1e3;  // far too large: the best is the smallest α scanned
  prm.alpha_max = 1e5;
  const LooReport rep = select_alpha(Xn, s.Y, s.groups, prm);
  EXPECT_EQ(rep.part.edge, Edge::Low);
  EXPECT_GE(rep.part.alpha, 1e3 * (1 - 1e-12));
}

TEST(Loo, BadInputIsRejectedWithAMessage) {
  MatrixXd X = MatrixXd::Random(4, 3), Y = MatrixXd::Identity(4, 2);
  Y.resize(4, 2);
  Y << 1, 0, 0, 1, 1, 0, 0, 1;
  EXPECT_THROW((void)select_alpha(X, Y, {"a", "a", "a", "a"}, {}), millnet::Error);  // one group
  EXPECT_THROW((void)select_alpha(X, Y, {"a", "b"}, {}), millnet::Error);            // group count
  X(1, 1) = NAN;
  try {
    (void)select_alpha(X, Y, {"a", "b", "c", "d"}, {});
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);
  }
}

TEST(Model, TrainPredictAndUnfamiliarFlag) {
  Synthetic s = make_clusters(3, 4, 4, 6, 9, 5.0, 0.5, 0.1);
  TrainingSet set{s.X, s.Y, s.groups, {"s1", "s2", "s3", "s4"}};
  const Model m = train(set);
  EXPECT_GT(m.alpha, 0.0);
  EXPECT_EQ(m.loo.accuracy_part_at_alpha, 1.0);
  // threshold = factor × 95th percentile (nearest rank) of the part-out nearest d²
  std::vector<double> nd(m.loo.nearest_d2.data(), m.loo.nearest_d2.data() + m.loo.nearest_d2.size());
  std::sort(nd.begin(), nd.end());
  const auto idx = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(nd.size()))) - 1;
  EXPECT_DOUBLE_EQ(m.unfamiliar_threshold, 4.0 * nd[idx]);
  MatrixXd q(2, 9);
  q.row(0) = s.X.row(7) * 1.0001;
  q.row(1) = s.X.row(7) + Eigen::RowVectorXd::Constant(9, 500.0);
  const Prediction p = predict(m, q);
  EXPECT_FALSE(p.unfamiliar[0]);
  EXPECT_TRUE(p.unfamiliar[1]);
  EXPECT_EQ(Index{0}, [&] { Index k; p.probabilities.row(0).maxCoeff(&k); Index l; s.Y.row(7).maxCoeff(&l); return k - l; }());
  for (Index i = 0; i < 2; ++i) EXPECT_NEAR(p.probabilities.row(i).sum(), 1.0, 1e-12);
  EXPECT_TRUE(p.probabilities.allFinite());
  EXPECT_THROW((void)predict(m, MatrixXd::Zero(1, 8)), millnet::Error);
}

TEST(Model, FixedAlphaMatchesReference) {
  Synthetic s = make_clusters(8, 3, 3, 4, 5, 2.0, 0.5, 0.2);
  TrainParams tp;
  tp.fixed_alpha = 0.7;
  const Model m = train({s.X, s.Y, s.groups, {"a", "b", "c"}}, tp);
  const MatrixXd Xn = m.normalizer.apply(s.X);
  EXPECT_EQ(m.alpha, 0.7);
  EXPECT_NEAR(m.loo.rms_part_at_alpha, rms_error(reference_outputs(Xn, s.Y, s.groups, 0.7, 0), s.Y), 1e-12);
  EXPECT_NEAR(m.loo.rms_vector_at_alpha, rms_error(reference_outputs(Xn, s.Y, s.groups, 0.7, 1), s.Y), 1e-12);
  EXPECT_LT((m.loo.filtration - reference_outputs(Xn, s.Y, s.groups, 0.7, 2)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Loo, GridRefinementWithoutCacheIsExactAndTakesAtMostThreePasses) {
  // cache_neighbours = 1 covers no bracket: refinement runs as one grid pass for both modes, the
  // outputs come from its kept sums (or one more pass). Every reported figure against the
  // brute-force reference, for both chosen modes.
  const unsigned seed = 31;
  const Synthetic s = make_clusters(seed, 3, 4, 7, 6, 1.5, 0.9, 0.3);  // N = 84, overlapping classes
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  for (LooMode mode : {LooMode::PartOut, LooMode::VectorOut}) {
    AlphaSearchParams prm;
    prm.mode = mode;
    prm.block_rows = 10;
    prm.cache_neighbours = 1;
    prm.prescan_stride = 0;
    const LooReport rep = select_alpha(Xn, s.Y, s.groups, prm);
    // the pre-scan (every 2nd vector) only moves the grid into the scan pass: same bits, no more passes
    prm.prescan_stride = 2;
    const LooReport pre = select_alpha(Xn, s.Y, s.groups, prm);
    EXPECT_LE(pre.full_passes, rep.full_passes);
    expect_same_bits(pre, rep);
    EXPECT_FALSE(rep.neighbour_cache_used);
    EXPECT_LE(rep.full_passes, 3);
    EXPECT_GE(rep.part.refine_evaluations, 3);
    const int m = mode == LooMode::PartOut ? 0 : 1;
    const MatrixXd ver = reference_outputs(Xn, s.Y, s.groups, rep.alpha, m);
    const MatrixXd fil = reference_outputs(Xn, s.Y, s.groups, rep.alpha, 2);
    EXPECT_LT((ver - rep.verification).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " mode " << m;
    EXPECT_LT((fil - rep.filtration).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " mode " << m;
    const double rp = rms_error(reference_outputs(Xn, s.Y, s.groups, rep.alpha, 0), s.Y);
    const double rv = rms_error(reference_outputs(Xn, s.Y, s.groups, rep.alpha, 1), s.Y);
    EXPECT_NEAR(rep.rms_part_at_alpha, rp, 1e-12 * std::max(1.0, rp));
    EXPECT_NEAR(rep.rms_vector_at_alpha, rv, 1e-12 * std::max(1.0, rv));
    expect_optima_match_reference(rep, Xn, s);
  }
}

TEST(Loo, SampledNeighbourCutAndPrescanPredictionsKeepEveryBit) {
  // N = 720 with a 40-neighbour cache: each row's cut comes from the sampled pivot (N ≥ 16·41), and
  // the pre-scan decides per mode between a grid in the scan pass and the cache. Whatever it
  // decides, the report is the one without a pre-scan, bit for bit, and matches the reference.
  const Synthetic s = make_clusters(5, 4, 10, 18, 5, 2.5, 0.7, 0.1);
  const MatrixXd Xn = Normalizer::fit(s.X).apply(s.X);
  AlphaSearchParams prm;
  prm.cache_neighbours = 40;
  prm.block_rows = 64;
  prm.prescan_stride = 0;
  const LooReport plain = select_alpha(Xn, s.Y, s.groups, prm);
  prm.prescan_stride = 4;
  const LooReport pre = select_alpha(Xn, s.Y, s.groups, prm);
  EXPECT_LE(pre.full_passes, plain.full_passes);
  expect_same_bits(pre, plain);
  const MatrixXd ver = reference_outputs(Xn, s.Y, s.groups, pre.alpha, 0);
  const MatrixXd fil = reference_outputs(Xn, s.Y, s.groups, pre.alpha, 2);
  EXPECT_LT((ver - pre.verification).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((fil - pre.filtration).cwiseAbs().maxCoeff(), 1e-12);
  expect_optima_match_reference(pre, Xn, s);
}
