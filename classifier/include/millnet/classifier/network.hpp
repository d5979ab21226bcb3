#pragma once
// The Grabec-style probabilistic network of Korosec & Kopac (seed 004), with α chosen by
// leave-one-out. Facade for the CLI:
//
//   classifier::TrainingSet set{inputs, outputs, groups, strategies};   // N×D, N×K, N, K
//   classifier::Model model = classifier::train(set, {});                // normalize, LOO α, store
//   classifier::Prediction p = classifier::predict(model, new_inputs);   // M×D → M×K, d²_min, flag
//
// The network (all distances on z-scored inputs, never the raw ones):
//   d²_j = ‖x − x_j‖²                        squared Euclidean distance to stored vector j
//   s_j  = exp(−(d²_j − d²_min) / α)         d²_min subtracted: identical after normalization,
//                                            and the nearest vector always has s = 1 (no 0/0)
//   s̄_j = s_j / Σ s                          output = Σ_j s̄_j · y_j
// so the outputs are probabilities summing to 1 whenever every stored output row sums to 1
// (one-hot strategy labels).
#include "millnet/core/budget.hpp"
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "millnet/classifier/normalizer.hpp"
#include "millnet/classifier/regret.hpp"
#include "millnet/core/progress.hpp"

namespace millnet::classifier {

/// What "training" stores. Raw (un-normalized) inputs.
struct TrainingSet {
  Eigen::MatrixXd inputs;               ///< N×D (e.g. D = 225 heights in mm)
  Eigen::MatrixXd outputs;              ///< N×K (one-hot strategy rows)
  std::vector<std::string> groups;      ///< N: the source part of each vector (leave-one-part-out unit)
  std::vector<std::string> strategies;  ///< K strategy names
};

enum class LooMode {
  PartOut,    ///< default: every vector of the left-out vector's group is excluded
  VectorOut,  ///< the paper's literal per-vector leave-one-out (only the vector itself excluded)
};
[[nodiscard]] const char* to_string(LooMode m);
/// "part" | "vector"; throws millnet::Error naming the accepted values otherwise.
[[nodiscard]] LooMode loo_mode_from_string(const std::string& s);

/// α search. Candidates are log-spaced: α_k = α_hi · 2^(−k/steps_per_octave), k = 0…n−1,
/// from α_hi down to ≥ α_lo. Range: [alpha_min, alpha_max] if both > 0, else
/// [range_low, range_high] × (median nonzero d² between stored vectors, over a fixed
/// deterministic sample of ≤ 65,536 pairs). The default gives 40 candidates over 6 decades.
struct AlphaSearchParams {
  LooMode mode = LooMode::PartOut;
  double range_low = 1e-3;
  double range_high = 1e3;
  double alpha_min = 0.0;  ///< absolute override (both must be > 0)
  double alpha_max = 0.0;
  int steps_per_octave = 2;  ///< 1…8; the scan costs one exp per stored pair per step
  /// golden section (on the cache) stops when the bracket is narrower; a grid refinement (when
  /// the cache is not exact over the bracket) uses one step in 1/α over the whole bracket: this
  /// wide, but at most 1/16 of the narrower half bracket
  double refine_tolerance_octaves = 1e-3;
  Eigen::Index block_rows = 256;        ///< query rows per GEMM block (memory 8·N·block_rows B/thread)
  Eigen::Index cache_neighbours = 256;  ///< R nearest d² kept per stored vector for the refinement
  /// Pre-scan every k-th stored vector (against all N; 1/k of a pass) to predict each mode's best
  /// candidate, so that the scan pass also evaluates its refinement grid (saves the grid's own
  /// pass when the prediction holds; results are identical either way). < 2 = off; skipped when
  /// fewer than 16 vectors would be pre-scanned.
  Eigen::Index prescan_stride = 10;
  ProgressFn progress;  ///< (passes done, passes planned), called from serial code
  /// false: no outputs at the chosen α (LooReport's verification and filtration stay empty, its
  /// figures at α are the refinement's) — for a caller that picks its own α among the scan's and
  /// then calls outputs_at_alpha once (train's regret criterion: one full pass fewer).
  bool outputs_at_alpha = true;
  /// false: where the neighbour cache cannot refine a mode's optimum, it stays the scan's best
  /// candidate (refine_evaluations 0) — no refinement grid, no pre-scan. For a caller that chooses
  /// α among the scan's candidates by another figure (train's regret criterion): the grids were
  /// 3 of its 10 s on 500 parts × 22 variants.
  bool refine_on_grid = true;
};

/// One point of the coarse scan; the RMS of both modes are computed from the same d² blocks.
struct CurvePoint {
  double alpha = 0;
  double rms_part = 0, rms_vector = 0;            ///< sqrt(mean over N·K of squared output error)
  double accuracy_part = 0, accuracy_vector = 0;  ///< share of vectors whose argmax equals their label
};

enum class Edge { None, Low, High };  ///< where a scan optimum sits (Low = smallest α scanned)
[[nodiscard]] const char* to_string(Edge e);

/// The refined optimum of one mode.
struct ModeOptimum {
  double alpha = 0;
  double rms = 0;
  double accuracy = 0;
  Edge edge = Edge::None;      ///< optimum of the scan at the scan's edge (the range may be too narrow)
  int refine_evaluations = 0;  ///< golden-section evaluations, or grid points evaluated
};

struct LooReport {
  LooMode mode = LooMode::PartOut;  ///< the mode that chose alpha
  double alpha = 0;                 ///< chosen α (= part.alpha or vector.alpha)
  double d2_scale = 0;              ///< median nonzero d² used to place the scan
  std::vector<CurvePoint> curve;    ///< scan, ascending α (values from squaring chains, ≤ ~1e-10 rel. error)
  ModeOptimum part, vector;         ///< each mode's own refined optimum
  double rms_part_at_alpha = 0, rms_vector_at_alpha = 0;  ///< both figures at the chosen α
  double accuracy_part_at_alpha = 0, accuracy_vector_at_alpha = 0;
  Eigen::MatrixXd filtration;         ///< N×K outputs at α with every vector included (paper Fig. 6)
  Eigen::MatrixXd verification;       ///< N×K outputs at α with the chosen mode's exclusion
  Eigen::VectorXd nearest_d2;         ///< N: d² to the nearest vector of another group (another vector if one group)
  bool neighbour_cache_used = false;  ///< refinement and outputs ran on the R-nearest cache (no pass after the scan)
  int full_passes = 0;                ///< passes over all N² pairs (each = one N×N×D GEMM in blocks)
};

/// Leave-one-out α selection on NORMALIZED inputs Xn (N×D), outputs Y (N×K), groups (N).
/// Work: one scan pass (N²·D GEMM + N²·steps exps + ≤ N²·candidates multiply/adds, shared by
/// both modes), an R-nearest cache (N·R memory) for a golden-section refinement (N·R exps per
/// evaluation) when the cache is exact over the refinement bracket; otherwise a grid (one step
/// in 1/α, ≤ 17 + 16·2^(1/q) points per mode: 40 at q = 2, exact), evaluated in the scan pass
/// when a pre-scan of every prescan_stride-th vector predicted it, else in its own pass. Outputs
/// at the chosen α come from the grid, the cache, or one more pass: 1–3 full passes in all
/// (usually 1 + 1/prescan_stride). Memory O(N·D + N·R + threads·N·block_rows) (the grid keeps
/// ≤ N·49·2P doubles, P = distinct output rows, only within 2·N·(D + R)); never N×N.
/// Deterministic: bitwise identical results for any OpenMP thread count.
/// Throws millnet::Error on shape mismatch, non-finite values, N < 2, or PartOut with one group.
[[nodiscard]] LooReport select_alpha(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y,
                                     const std::vector<std::string>& groups, const AlphaSearchParams& params);

/// The outputs and figures at α into `rep` (alpha, mode, verification in `mode`, filtration, both
/// modes' RMS and accuracy at α): one full blocked pass, O(N²·D + N²·K).
void outputs_at_alpha(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y, const std::vector<std::string>& groups,
                      double alpha, LooMode mode, Eigen::Index block_rows, LooReport& rep);

/// Verification (mode PartOut/VectorOut) outputs at one α by a full blocked pass (no cache):
/// N×K. Used for figures at a given α and as the reference in tests.
[[nodiscard]] Eigen::MatrixXd verification_outputs(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y,
                                                   const std::vector<std::string>& groups, double alpha, LooMode mode,
                                                   Eigen::Index block_rows = 256);

/// The paper's Fig. 6: per labelled vector (labels 1…K; 0 or less: unlabelled, skipped), the output
/// of its own strategy in `filtration` and in `verification`, in row order. O(N).
struct TrueOutputs {
  std::vector<double> filtration, verification;
};
[[nodiscard]] TrueOutputs true_label_outputs(const LooReport& loo, const std::vector<int>& labels);

/// RMS over all N·K outputs of (outputs − Y); accuracy = share of rows whose argmax matches Y's.
[[nodiscard]] double rms_error(const Eigen::MatrixXd& outputs, const Eigen::MatrixXd& Y);
[[nodiscard]] double argmax_accuracy(const Eigen::MatrixXd& outputs, const Eigen::MatrixXd& Y);

/// Raw network evaluation: queries Qn (M×D, normalized) against stored Xn (N×D) with outputs Y.
struct NetworkOutputs {
  Eigen::MatrixXd outputs;  ///< M×K
  Eigen::VectorXd d2_min;   ///< M: squared distance to the nearest stored vector (normalized units)
  Eigen::VectorXi nearest;  ///< M: index of that stored vector (first one on ties)
};
[[nodiscard]] NetworkOutputs evaluate_network(const Eigen::MatrixXd& Xn, const Eigen::MatrixXd& Y,
                                              const Eigen::MatrixXd& Qn, double alpha, Eigen::Index block_rows = 256);

/// What α is chosen for (issue 39 §1).
enum class Criterion {
  Rms,     ///< the paper's: the leave-one-out RMS error of the outputs
  Regret,  ///< the mean leave-one-part-out regret of the parts' picks (regret.hpp), ties by the RMS
};
[[nodiscard]] const char* to_string(Criterion c);

struct TrainParams {
  AlphaSearchParams search;
  Criterion criterion = Criterion::Rms;
  /// A query is unfamiliar when d²_min > unfamiliar_factor × (unfamiliar_percentile of the
  /// training set's leave-one-part-out nearest d², LooReport::nearest_d2; nearest-rank method).
  double unfamiliar_factor = 4.0;
  double unfamiliar_percentile = 0.95;
  /// > 0: skip the search and use this α (the LOO figures are then computed at it).
  double fixed_alpha = 0.0;
  /// The leave-one-out's N² vector pairs are checked against limits.max_pairs before any is
  /// computed (issue 12 §1; estimate_loo_work).
  WorkLimits limits;
};

/// The leave-one-out's cost: N² vector pairs of `inputs`-long distances (the training set's N×inputs
/// matrix, normalized, and the R-nearest cache of 256 per vector: 8·N·inputs + 12·256·N bytes).
[[nodiscard]] WorkEstimate estimate_loo_work(Eigen::Index n_vectors, Eigen::Index n_inputs);

/// How one input row is made from a part: the height-field raster and the n×n grid it is resampled
/// to, row-major. Recorded by whoever built the training table, so that a model file describes its
/// own inputs; the classifier itself never reads it.
struct InputSpec {
  double raster_mm = 0;         ///< > 0
  int grid = 0;                 ///< n ≥ 2
  bool aspect_feature = false;  ///< the footprint aspect follows the n² heights as one more input
  /// The part's wall share (datasets::wall_share) follows as this many equal inputs (each z-scored
  /// like every input, so c copies weigh √c against one height; issue 39 §3's ablation); 0: none.
  int wall_share_copies = 0;
  [[nodiscard]] Eigen::Index inputs() const {
    return static_cast<Eigen::Index>(grid) * grid + (aspect_feature ? 1 : 0) + wall_share_copies;
  }
  bool operator==(const InputSpec&) const = default;
};

/// A trained network: everything needed to predict, plus the LOO record.
struct Model {
  double alpha = 0;
  Normalizer normalizer;
  std::vector<std::string> strategies;  ///< K
  Eigen::MatrixXd inputs;               ///< N×D raw stored inputs
  Eigen::MatrixXd outputs;              ///< N×K
  std::vector<std::string> groups;      ///< N
  double unfamiliar_threshold = 0;      ///< on d²_min (normalized units)
  double unfamiliar_factor = 0, unfamiliar_percentile = 0;
  LooReport loo;
  std::optional<InputSpec> input_spec;  ///< empty in model files written before it was recorded
  Criterion criterion = Criterion::Rms;
  /// Leave-one-part-out mean regret at each α of loo.curve (same order), plus the chosen α's; empty
  /// with the Rms criterion.
  std::vector<std::pair<double, double>> regret_curve;
  /// P(pick is the part's best), fitted on the leave-one-part-out picks at α (regret.hpp).
  Calibration calibration;
  /// What the outputs were computed for, as JSON text (e.g. {"aim": "time_to_spec", "spec": {…}});
  /// empty when the outputs are labels given by hand. Recorded by the caller; the classifier
  /// itself never reads it.
  std::string target_json;
};

/// Validates the set, fits the normalizer, selects α (or uses params.fixed_alpha), and stores.
[[nodiscard]] Model train(const TrainingSet& set, const TrainParams& params = {});

struct Prediction {
  Eigen::MatrixXd probabilities;  ///< M×K (rows sum to 1 for one-hot stored outputs)
  Eigen::VectorXd d2_min;         ///< M, normalized units
  std::vector<bool> unfamiliar;   ///< M: d2_min > model.unfamiliar_threshold
};

/// Predicts raw inputs (M×D, same columns as the training inputs). Throws on a D mismatch.
[[nodiscard]] Prediction predict(const Model& model, const Eigen::MatrixXd& inputs);

/// The network's conditional average of each strategy's regret (regret.hpp: pick_regret of every
/// stored output row): M×K, the regret a pick of slot k is expected to cost on each input row.
/// O(M·N·(D + K)).
[[nodiscard]] Eigen::MatrixXd expected_regret(const Model& model, const Eigen::MatrixXd& inputs);

}  // namespace millnet::classifier
