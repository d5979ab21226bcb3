#pragma once
// A network whose outputs are the strategies' scores (issue 39: the best 1, a strategy twice as
// long 0.5, one that gouges or misses the specification 0) judged the way a shop would judge it:
// by the regret of the strategy it picks for a part it has not seen — the picked strategy's time
// / the best time − 1 (tol::kMissRegret for a pick that scores 0).
//
//   std::vector<PartPick> picks = part_picks(loo.verification, Y, groups);  // leave-one-part-out
//   RegretSummary s = summarize(picks);                 // top-1, mean / median / p90 regret, ρ
//   Calibration c = calibrate(picks, Y, groups);        // confidence = P(pick is the best)
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace millnet::classifier {

/// The regret of picking slot k (0-based) on a part whose output row is y (its scores): 0 for the
/// largest output, 1/y_k − 1 for y_k > 0, tol::kMissRegret for y_k ≤ 0. For a one-hot row: 0 on the
/// label, kMissRegret elsewhere (so the mean regret is the error rate). O(K).
[[nodiscard]] double pick_regret(const Eigen::Ref<const Eigen::RowVectorXd>& y, Eigen::Index k);

/// One part's pick: the mean of its vectors' predicted outputs (its rotated variants), the slot
/// with the largest mean (first on ties), and what that pick costs on the part.
struct PartPick {
  std::string part;
  Eigen::Index best = 0;                                       ///< 0-based, argmax of the part's own outputs
  Eigen::Index pick = 0;                                       ///< 0-based, argmax of `predicted`
  double regret = 0;                                           ///< pick_regret(outputs, pick)
  bool miss = false;                                           ///< the pick scores 0 on the part
  double margin = 0;                                           ///< predicted[pick] − the second largest predicted
  double spearman = std::numeric_limits<double>::quiet_NaN();  ///< predicted vs true, active slots
  double d2_min = 0;             ///< smallest d² of its vectors to another part (if given)
  Eigen::RowVectorXd predicted;  ///< K
  Eigen::RowVectorXd outputs;    ///< K, the part's stored outputs
};

/// Parts in order of first appearance in `groups`. `predicted` and `Y` are N×K; every vector of a
/// part must carry the same stored output row (throws millnet::Error naming the part otherwise).
/// `d2_min` (N, optional: empty) gives each vector's nearest d² to another part. Spearman's ρ is
/// over the "active" slots (a nonzero output on some part), ties ranked by their mean rank. O(N·K).
[[nodiscard]] std::vector<PartPick> part_picks(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& Y,
                                               const std::vector<std::string>& groups,
                                               const Eigen::VectorXd& d2_min = Eigen::VectorXd());

/// Whether every vector of a part carries the same output row (what part_picks needs). O(N·K).
[[nodiscard]] bool one_output_per_part(const Eigen::MatrixXd& Y, const std::vector<std::string>& groups);

struct RegretSummary {
  std::size_t parts = 0;
  double top1 = 0;                                             ///< share of parts whose pick is their best
  double mean = 0, median = 0, p90 = 0;                        ///< regret over the parts (nearest-rank percentiles)
  std::size_t misses = 0;                                      ///< picks that score 0
  double spearman = std::numeric_limits<double>::quiet_NaN();  ///< mean over the parts where defined
};
[[nodiscard]] RegretSummary summarize(const std::vector<PartPick>& picks);

/// The shop's baseline without a network: always the slot that is best on the most parts (lowest
/// slot on ties), judged on the same parts. O(parts · K).
struct Baseline {
  Eigen::Index slot = 0;  ///< 0-based
  RegretSummary figures;
};
[[nodiscard]] Baseline always_the_same(const std::vector<PartPick>& picks);

/// Leave-one-part-out outputs of the network at each α of `alphas`: one N×K matrix per α, from one
/// blocked pass over the N² pairs. Work O(N²·(D + |alphas|·K)), memory O(|alphas|·N·K).
/// Deterministic for any thread count.
[[nodiscard]] std::vector<Eigen::MatrixXd> part_out_outputs(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y,
                                                            const std::vector<std::string>& groups,
                                                            const std::vector<double>& alphas,
                                                            Eigen::Index block_rows = 256);

/// What a pick's confidence means: the probability that it is the part's best strategy. Fitted
/// on leave-one-part-out picks: an isotonic (non-decreasing) map of the raw confidence — the
/// pick's margin over the runner-up, times the part's familiarity min(1, threshold / d²_min) —
/// to the share of picks that were right (per block (right + 1) / (picks + 2), the rule of
/// succession: never 0 or 1 from finitely many parts); then shrunk towards the pick's prior (the share of
/// training parts it is best on) as the part gets unfamiliar:
///   confidence = f·map(margin·f) + (1 − f)·prior[pick],   f = min(1, threshold / d²_min).
struct Calibration {
  std::vector<double> raw;    ///< ascending upper ends of the map's blocks
  std::vector<double> right;  ///< per block: share of its picks that were right (non-decreasing)
  std::vector<double> prior;  ///< K: share of the training parts each slot is best on
  double threshold = 0;       ///< the unfamiliar threshold on d²_min (f = 1 within it)
  [[nodiscard]] bool empty() const { return raw.empty(); }
  /// f of a part with nearest d² `d2_min`.
  [[nodiscard]] double familiarity(double d2_min) const;
  /// The calibrated confidence of picking `pick` with `margin` at `d2_min`. O(log blocks).
  [[nodiscard]] double confidence(Eigen::Index pick, double margin, double d2_min) const;
};

/// Fits the calibration on `picks` (their margin, d2_min, pick and best). O(P log P).
[[nodiscard]] Calibration calibrate(const std::vector<PartPick>& picks, std::size_t slots, double threshold);

/// The reliability table of a calibration, honestly measured: each part's confidence from a
/// calibration fitted without it (leave-one-part-out again), binned by confidence; per bin the
/// parts, their mean confidence and the share that were right. O(P² log P).
struct ReliabilityBin {
  double low = 0, high = 0;
  std::size_t parts = 0;
  double mean_confidence = 0, share_right = 0;
};
[[nodiscard]] std::vector<ReliabilityBin> reliability(const std::vector<PartPick>& picks, std::size_t slots,
                                                      double threshold, int bins = 5);

}  // namespace millnet::classifier
