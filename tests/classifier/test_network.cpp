// Grabec network, normalizer and the trained model (issue 2 §4); leave-one-out selection of α in
// test_loo.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
      if (d < b1) {
        b2 = b1;
        b1 = d;
        best = j;
      } else if (d < b2)
        b2 = d;
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
  EXPECT_EQ(Index{0}, [&] {
    Index k;
    p.probabilities.row(0).maxCoeff(&k);
    Index l;
    s.Y.row(7).maxCoeff(&l);
    return k - l;
  }());
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

// Issue 12 §1: the leave-one-out's N² pairs are counted before any is computed.
TEST(Model, LeaveOneOutPairsAreRefusedOverTheLimitAndRunAtIt) {
  Synthetic s = make_clusters(3, 4, 4, 6, 9, 5.0, 0.5, 0.1);
  const Index n = s.X.rows();
  TrainingSet set{s.X, s.Y, s.groups, {"s1", "s2", "s3", "s4"}};
  const millnet::WorkEstimate e = estimate_loo_work(n, 9);
  EXPECT_DOUBLE_EQ(e.count, static_cast<double>(n * n));
  EXPECT_DOUBLE_EQ(e.bytes, 8.0 * n * 9 + 12.0 * 256 * n);
  TrainParams p;
  p.limits.max_pairs = static_cast<double>(n * n) - 1;
  try {
    (void)train(set, p);
    FAIL() << "N² − 1 pairs allowed, N² asked: must be refused";
  } catch (const millnet::Error& err) {
    const std::string msg = err.what();
    EXPECT_NE(msg.find("leave-one-out over " + std::to_string(n) + " stored vectors makes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(--max-pairs, /limits/max_pairs)"), std::string::npos) << msg;
  }
  p.limits.max_pairs = static_cast<double>(n * n);  // exactly the estimate: runs
  EXPECT_NO_THROW((void)train(set, p));
  p.fixed_alpha = 0.5;  // no search, but still N² pairs for the LOO figures
  p.limits.max_pairs = 1;
  EXPECT_THROW((void)train(set, p), millnet::Error);
}

// Fig. 6's series: the output of each labelled vector's own strategy, unlabelled rows skipped.
TEST(LooReport, TrueLabelOutputsPickEachRowsOwnStrategy) {
  millnet::classifier::LooReport loo;
  loo.filtration = Eigen::MatrixXd{{0.9, 0.1}, {0.2, 0.8}, {0.5, 0.5}};
  loo.verification = Eigen::MatrixXd{{0.7, 0.3}, {0.4, 0.6}, {0.1, 0.9}};
  const auto t = millnet::classifier::true_label_outputs(loo, {1, 2, 0});
  EXPECT_EQ(t.filtration, (std::vector<double>{0.9, 0.8}));
  EXPECT_EQ(t.verification, (std::vector<double>{0.7, 0.6}));
}
