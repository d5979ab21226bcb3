// The network judged by the regret of its picks (classifier/regret.hpp; issue 39): hand-computed
// regrets, part picks and baseline, the leave-one-part-out outputs against the brute-force
// reference, α chosen by regret, and the calibration's isotonic map.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <unistd.h>

#include "millnet/classifier/io/model_file.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/regret.hpp"
#include "millnet/classifier/tolerances.hpp"
#include "synthetic.hpp"

using namespace millnet::classifier;
using Eigen::MatrixXd;
using Eigen::RowVectorXd;

namespace {

RowVectorXd row(std::initializer_list<double> v) {
  RowVectorXd r(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) r(i++) = x;
  return r;
}

/// A set whose outputs are scores: three part kinds (by a feature), each with its own best and
/// runner-up costs; `per_kind` parts of 3 vectors each.
test::Synthetic scored_set(unsigned seed, int per_kind) {
  test::Synthetic s = test::make_clusters(seed, 3, per_kind, 3, 6, 3.0, 0.4, 0.1);
  const MatrixXd scores = (MatrixXd(3, 3) << 1.0, 0.5, 0.0,  //
                           0.8, 1.0, 0.25,                   //
                           0.0, 0.9, 1.0)
                              .finished();
  for (Eigen::Index i = 0; i < s.Y.rows(); ++i) {
    Eigen::Index c = 0;
    s.Y.row(i).maxCoeff(&c);
    s.Y.row(i) = scores.row(c);
  }
  return s;
}

}  // namespace

TEST(Regret, APickCostsItsTimeOverTheBestsAndAMissCostsASecondFinishing) {
  const RowVectorXd y = row({0.5, 1.0, 0.0, 0.8});
  EXPECT_EQ(pick_regret(y, 1), 0.0);
  EXPECT_DOUBLE_EQ(pick_regret(y, 0), 1.0);   // twice the best's time
  EXPECT_DOUBLE_EQ(pick_regret(y, 3), 0.25);  // 1 / 0.8 − 1
  EXPECT_EQ(pick_regret(y, 2), tol::kMissRegret);
  // One-hot labels: the mean regret is the error rate.
  EXPECT_EQ(pick_regret(row({0, 1, 0}), 1), 0.0);
  EXPECT_EQ(pick_regret(row({0, 1, 0}), 2), tol::kMissRegret);
  // Nothing scores: no pick is worse than another.
  EXPECT_EQ(pick_regret(row({0, 0, 0}), 1), 0.0);
}

TEST(Regret, APartsPickIsTheMeanOfItsVariantsAndTheBaselineIsTheMostFrequentBest) {
  // Parts a (2 vectors), b (2), c (1); scores per part, predictions per vector.
  const MatrixXd Y = (MatrixXd(5, 3) << 1, 0.5, 0,  //
                      1, 0.5, 0,                    //
                      0.8, 1, 0,                    //
                      0.8, 1, 0,                    //
                      1, 0, 0.4)
                         .finished();
  const MatrixXd P = (MatrixXd(5, 3) << 0.9, 0.2, 0.1,  //
                      0.1, 0.6, 0.0,                    // a: mean (0.5, 0.4, 0.05) → 1, right
                      0.9, 0.5, 0.0,                    //
                      0.7, 0.6, 0.0,                    // b: mean (0.8, 0.55, 0) → 1: regret 1/0.8 − 1
                      0.0, 0.2, 0.3)                    // c: → 3: 1/0.4 − 1 = 1.5
                         .finished();
  const std::vector<std::string> g{"a", "a", "b", "b", "c"};
  const std::vector<PartPick> picks = part_picks(P, Y, g);
  ASSERT_EQ(picks.size(), 3u);
  EXPECT_EQ(picks[0].part, "a");
  EXPECT_EQ(picks[0].pick, 0);
  EXPECT_EQ(picks[0].regret, 0.0);
  EXPECT_NEAR(picks[0].margin, 0.1, 1e-15);
  EXPECT_EQ(picks[1].best, 1);
  EXPECT_EQ(picks[1].pick, 0);
  EXPECT_DOUBLE_EQ(picks[1].regret, 0.25);
  EXPECT_EQ(picks[2].pick, 2);
  EXPECT_DOUBLE_EQ(picks[2].regret, 1.5);
  EXPECT_FALSE(picks[2].miss);
  // ρ of a's prediction (0.5, 0.4, 0.05) against its scores (1, 0.5, 0): the same order.
  EXPECT_NEAR(picks[0].spearman, 1.0, 1e-12);
  const RegretSummary s = summarize(picks);
  EXPECT_NEAR(s.top1, 1.0 / 3, 1e-15);
  EXPECT_NEAR(s.mean, (0 + 0.25 + 1.5) / 3, 1e-15);
  EXPECT_DOUBLE_EQ(s.median, 0.25);
  EXPECT_DOUBLE_EQ(s.p90, 1.5);
  // Strategy 1 is best on a and c: always 1 costs 0 + 0.25 + 0.
  const Baseline b = always_the_same(picks);
  EXPECT_EQ(b.slot, 0);
  EXPECT_NEAR(b.figures.mean, 0.25 / 3, 1e-15);
  EXPECT_NEAR(b.figures.top1, 2.0 / 3, 1e-15);
  // A part whose vectors carry different outputs is refused, naming it.
  MatrixXd bad = Y;
  bad(1, 1) = 0.6;
  try {
    (void)part_picks(P, bad, g);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'a'"), std::string::npos) << e.what();
  }
}

TEST(Regret, PartOutOutputsAtManyAlphasMatchTheBruteForceReference) {
  const test::Synthetic s = scored_set(5, 4);
  const std::vector<double> alphas{0.05, 0.7, 3.0, 40.0};
  const std::vector<MatrixXd> outs = part_out_outputs(s.X, s.Y, s.groups, alphas, 7);
  ASSERT_EQ(outs.size(), alphas.size());
  for (std::size_t a = 0; a < alphas.size(); ++a)
    EXPECT_LE((outs[a] - test::reference_outputs(s.X, s.Y, s.groups, alphas[a], 0)).cwiseAbs().maxCoeff(), 1e-12)
        << alphas[a];
}

TEST(Regret, PartOutOutputsFromSquaredWeightsMatchTheBruteForceReference) {
  // Halving α squares the weights: a chain of six halvings (restarted from an exp after four), in
  // any order of the list, with a stranger between them; outputs within 1e-12 of the reference.
  const test::Synthetic s = scored_set(6, 5);
  const std::vector<double> alphas{0.8, 0.05, 3.2, 0.1, 1.6, 0.7, 0.2, 0.4, 6.4};
  const std::vector<MatrixXd> outs = part_out_outputs(s.X, s.Y, s.groups, alphas, 5);
  ASSERT_EQ(outs.size(), alphas.size());
  for (std::size_t a = 0; a < alphas.size(); ++a)
    EXPECT_LE((outs[a] - test::reference_outputs(s.X, s.Y, s.groups, alphas[a], 0)).cwiseAbs().maxCoeff(), 1e-12)
        << alphas[a];
}

TEST(Regret, AlphaChosenByRegretIsTheCurvesLowestAndNoWorseThanTheRmsChoice) {
  test::Synthetic s = scored_set(9, 5);
  TrainParams rms_params, regret_params;
  regret_params.criterion = Criterion::Regret;
  const TrainingSet set{s.X, s.Y, s.groups, {"1", "2", "3"}};
  const Model by_rms = train(set, rms_params);
  const Model by_regret = train(set, regret_params);
  ASSERT_EQ(by_regret.regret_curve.size(), by_regret.loo.curve.size() + 1);
  double lowest = INFINITY;
  for (const auto& [a, r] : by_regret.regret_curve) lowest = std::min(lowest, r);
  const double chosen = summarize(part_picks(by_regret.loo.verification, s.Y, s.groups)).mean;
  const double at_rms = summarize(part_picks(by_rms.loo.verification, s.Y, s.groups)).mean;
  EXPECT_NEAR(chosen, lowest, 1e-12);
  EXPECT_LE(chosen, at_rms + 1e-12);
  // The report's outputs are those at the chosen α (the brute-force reference).
  EXPECT_LE((by_regret.loo.verification - test::reference_outputs(s.X, s.Y, s.groups, by_regret.alpha, 0))
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
  EXPECT_EQ(by_regret.criterion, Criterion::Regret);
}

TEST(Calibration, AnIsotonicMapOfTheMarginFallingToThePriorWhenUnfamiliar) {
  // Four parts: margins 0.1 … 0.4, right on the 2nd and 4th: PAV pools the middle two; each block
  // by the rule of succession: 0 of 1 → 1/3, 1 of 2 → 1/2, 1 of 1 → 2/3.
  std::vector<PartPick> picks(4);
  const double margins[] = {0.1, 0.2, 0.3, 0.4};
  for (int i = 0; i < 4; ++i) {
    picks[static_cast<std::size_t>(i)].margin = margins[i];
    picks[static_cast<std::size_t>(i)].best = i % 2 == 1 ? 0 : 1;
    picks[static_cast<std::size_t>(i)].pick = 0;
    picks[static_cast<std::size_t>(i)].regret = i % 2 == 1 ? 0 : 0.3;
    picks[static_cast<std::size_t>(i)].d2_min = 1.0;
  }
  const Calibration c = calibrate(picks, 2, 10.0);
  ASSERT_EQ(c.raw.size(), 3u);
  EXPECT_EQ(c.raw, (std::vector<double>{0.1, 0.3, 0.4}));
  ASSERT_EQ(c.right.size(), 3u);
  EXPECT_DOUBLE_EQ(c.right[0], 1.0 / 3);
  EXPECT_DOUBLE_EQ(c.right[1], 0.5);
  EXPECT_DOUBLE_EQ(c.right[2], 2.0 / 3);
  EXPECT_EQ(c.prior, (std::vector<double>{0.5, 0.5}));
  EXPECT_EQ(c.confidence(0, 0.25, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(c.confidence(0, 0.9, 1.0), 2.0 / 3);
  // Four times the threshold away: f = 1/4, raw margin 0.4·f = 0.1 → 1/3; then towards the prior.
  EXPECT_DOUBLE_EQ(c.confidence(0, 0.4, 40.0), 0.25 / 3 + 0.75 * 0.5);
  // Very far: the prior.
  EXPECT_NEAR(c.confidence(0, 0.4, 1e12), 0.5, 1e-9);
  // Reliability: every part's confidence from a calibration without it, binned.
  const std::vector<ReliabilityBin> bins = reliability(picks, 2, 10.0, 5);
  std::size_t n = 0;
  for (const ReliabilityBin& b : bins) n += b.parts;
  EXPECT_EQ(n, 4u);
}

TEST(Calibration, TheModelFileKeepsCriterionCurveCalibrationAndTarget) {
  test::Synthetic s = scored_set(3, 3);
  TrainParams p;
  p.criterion = Criterion::Regret;
  Model m = train({s.X, s.Y, s.groups, {"1", "2", "3"}}, p);
  m.target_json = R"({"aim":"time_to_spec","spec":{"scallop_mm":0.005}})";
  const auto path = std::filesystem::temp_directory_path() / ("millnet_regret_" + std::to_string(::getpid()) + ".json");
  millnet::classifier_io::save_model(m, path);
  const Model r = millnet::classifier_io::load_model(path);
  std::filesystem::remove(path);
  EXPECT_EQ(r.criterion, Criterion::Regret);
  EXPECT_EQ(r.regret_curve, m.regret_curve);
  EXPECT_EQ(r.calibration.raw, m.calibration.raw);
  EXPECT_EQ(r.calibration.right, m.calibration.right);
  EXPECT_EQ(r.calibration.prior, m.calibration.prior);
  EXPECT_EQ(r.calibration.threshold, m.calibration.threshold);
  EXPECT_EQ(r.target_json, R"({"aim":"time_to_spec","spec":{"scallop_mm":0.005}})");
}
