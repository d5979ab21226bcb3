// Leave-one-out α selection (issue 2 §4): blocked passes against the brute-force reference,
// the scan, refinement and output routes bit for bit, thread-count independence.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "classifier/synthetic.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/normalizer.hpp"
#include "millnet/core/error.hpp"

using namespace millnet::classifier;
using namespace millnet::classifier::test;
using Eigen::Index;
using Eigen::MatrixXd;

namespace {

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
  prm.block_rows = 16;  // 144 = 9 blocks: exercises the block combination
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
