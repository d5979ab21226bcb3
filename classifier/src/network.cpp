#include "millnet/classifier/network.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "engine.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

using detail::Index;
using Eigen::ArrayXd;
using Eigen::MatrixXd;
using Eigen::VectorXd;

NetworkOutputs evaluate_network(const MatrixXd& Xn, const MatrixXd& Y, const MatrixXd& Qn, double alpha,
                                Index block_rows) {
  if (Xn.rows() < 1 || Xn.cols() < 1) throw Error("network: no stored vectors");
  if (Y.rows() != Xn.rows() || Y.cols() < 1)
    throw Error("network: outputs are " + std::to_string(Y.rows()) + "×" + std::to_string(Y.cols()) +
                ", expected one row per stored vector (" + std::to_string(Xn.rows()) + ")");
  if (Qn.cols() != Xn.cols())
    throw Error("network: query has " + std::to_string(Qn.cols()) + " inputs, the stored vectors have " +
                std::to_string(Xn.cols()));
  if (!(alpha > 0) || !std::isfinite(alpha)) throw Error("network: alpha must be finite and > 0");
  if (block_rows < 1) throw Error("network: block_rows must be ≥ 1");
  if (!Qn.allFinite()) throw Error("network: query inputs contain NaN or infinite values");
  NetworkOutputs res;
  const Index m = Qn.rows();
  res.outputs.resize(m, Y.cols());
  res.d2_min.resize(m);
  res.nearest.resize(m);
  if (m == 0) return res;
  const VectorXd sqS = Xn.rowwise().squaredNorm();
  const VectorXd sqQ = Qn.rowwise().squaredNorm();
  const double neg_inv_alpha = -1.0 / alpha;
  // O(M·N·D) GEMM + O(M·N·K): every stored vector contributes, no truncation.
  detail::for_each_d2_block(Xn, sqS, Qn, sqQ, block_rows, [&](Index, Index r0, Index rows, const MatrixXd& D2) {
    ArrayXd e;
    for (Index c = 0; c < rows; ++c) {
      Index jmin = 0;
      const double dmin = D2.col(c).minCoeff(&jmin);
      // subtracting d²_min: the nearest vector has s = 1, so Σs ≥ 1 even when exp(−d²/α) underflows
      e = ((D2.col(c).array() - dmin) * neg_inv_alpha).exp();
      res.outputs.row(r0 + c) = (Y.transpose() * e.matrix()).transpose() / e.sum();
      res.d2_min(r0 + c) = dmin;
      res.nearest(r0 + c) = static_cast<int>(jmin);
    }
  });
  return res;
}

namespace {

void validate(const TrainingSet& set) {
  const Index n = set.inputs.rows();
  if (n < 2) throw Error("training set: need at least 2 vectors, got " + std::to_string(n));
  if (set.inputs.cols() < 1) throw Error("training set: inputs have no columns");
  if (set.outputs.rows() != n)
    throw Error("training set: " + std::to_string(set.outputs.rows()) + " output rows for " + std::to_string(n) +
                " input rows");
  if (set.outputs.cols() < 1) throw Error("training set: outputs have no columns");
  if (static_cast<Index>(set.strategies.size()) != set.outputs.cols())
    throw Error("training set: " + std::to_string(set.strategies.size()) + " strategy names for " +
                std::to_string(set.outputs.cols()) + " output columns");
  if (static_cast<Index>(set.groups.size()) != n)
    throw Error("training set: " + std::to_string(set.groups.size()) + " group ids for " + std::to_string(n) +
                " vectors");
  for (Index i = 0; i < n; ++i) {
    if (!set.inputs.row(i).allFinite())
      throw Error("training set: vector " + std::to_string(i) + " (" + set.groups[static_cast<std::size_t>(i)] +
                  ") has a NaN or infinite input");
    if (!set.outputs.row(i).allFinite())
      throw Error("training set: vector " + std::to_string(i) + " (" + set.groups[static_cast<std::size_t>(i)] +
                  ") has a NaN or infinite output");
  }
}

// Nearest-rank percentile of v (p in (0, 1]): the ⌈p·n⌉-th smallest value. O(n).
double percentile(std::vector<double> v, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  const std::size_t idx = std::clamp<std::size_t>(rank, 1, v.size()) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(idx), v.end());
  return v[idx];
}

}  // namespace

WorkEstimate estimate_loo_work(Eigen::Index n_vectors, Eigen::Index n_inputs) {
  const double n = static_cast<double>(n_vectors), k = static_cast<double>(n_inputs);
  WorkEstimate e;
  e.cause = "leave-one-out over " + format_size(n) + " stored vectors";
  e.count = n * n;
  e.unit = "vector pairs";
  e.bytes = 8 * n * k + 12 * 256 * n;
  e.pairs = true;
  return e;
}

const char* to_string(Criterion c) { return c == Criterion::Regret ? "regret" : "rms"; }

namespace {

/// α by the leave-one-part-out mean regret over the scan's candidates and a refined RMS optimum
/// (ties: the lower RMS, then the larger α); the report's outputs and both modes' figures at it in
/// one more pass (select_alpha left them). O(N²·(D + candidates·K)).
void choose_by_regret(const MatrixXd& Xn, const TrainingSet& set, const AlphaSearchParams& search, Model& model) {
  LooReport& rep = model.loo;
  std::vector<double> alphas, rms;
  for (const CurvePoint& c : rep.curve) {
    alphas.push_back(c.alpha);
    rms.push_back(c.rms_part);
  }
  if (std::find(alphas.begin(), alphas.end(), rep.alpha) == alphas.end()) {  // the RMS optimum, if refined
    alphas.push_back(rep.alpha);
    rms.push_back(rep.part.rms);
  }
  const std::size_t rms_at =
      static_cast<std::size_t>(std::find(alphas.begin(), alphas.end(), rep.alpha) - alphas.begin());
  const std::vector<MatrixXd> outs = part_out_outputs(Xn, set.outputs, set.groups, alphas, search.block_rows);
  std::size_t best = rms_at;
  double best_regret = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < alphas.size(); ++a) {
    const double r = summarize(part_picks(outs[a], set.outputs, set.groups)).mean;
    model.regret_curve.emplace_back(alphas[a], r);  // the curve's α, then a refined RMS optimum's
    const bool better =
        r < best_regret - 1e-12 ||
        (std::abs(r - best_regret) <= 1e-12 &&
         (rms[a] < rms[best] - 1e-15 || (std::abs(rms[a] - rms[best]) <= 1e-15 && alphas[a] > alphas[best])));
    if (better) {
      best = a;
      best_regret = r;
    }
  }
  // The outputs at the chosen α (the RMS optimum's too: select_alpha left them here), both modes'
  // figures and the filtration in one pass.
  const bool rms_optimum = best == rms_at;
  outputs_at_alpha(Xn, set.outputs, set.groups, alphas[best], rms_optimum ? search.mode : LooMode::PartOut,
                   search.block_rows, rep);
  rep.full_passes += 1;  // part_out_outputs'
}

}  // namespace

Model train(const TrainingSet& set, const TrainParams& params) {
  validate(set);
  // Before the normalizer's copy and any distance: N² pairs, refused in one line over the limit.
  check_work(estimate_loo_work(set.inputs.rows(), set.inputs.cols()), params.limits);
  if (!(params.unfamiliar_factor > 0)) throw Error("train: unfamiliar_factor must be > 0");
  if (!(params.unfamiliar_percentile > 0 && params.unfamiliar_percentile <= 1))
    throw Error("train: unfamiliar_percentile must be in (0, 1]");
  Model model;
  model.normalizer = Normalizer::fit(set.inputs);
  const MatrixXd Xn = model.normalizer.apply(set.inputs);
  const AlphaSearchParams& search = params.search;
  if (params.fixed_alpha > 0) {  // no search: the LOO figures and outputs are computed at the given α
    LooReport rep;
    if (std::set<std::string>(set.groups.begin(), set.groups.end()).size() < 2)
      throw Error("leave-one-part-out needs at least 2 groups (source parts)");
    outputs_at_alpha(Xn, set.outputs, set.groups, params.fixed_alpha, search.mode, search.block_rows, rep);
    rep.part = {params.fixed_alpha, rep.rms_part_at_alpha, rep.accuracy_part_at_alpha, Edge::None, 0};
    rep.vector = {params.fixed_alpha, rep.rms_vector_at_alpha, rep.accuracy_vector_at_alpha, Edge::None, 0};
    // nearest d² to another group, for the unfamiliar threshold: one more blocked pass
    rep.nearest_d2.resize(Xn.rows());
    const VectorXd sq = Xn.rowwise().squaredNorm();
    std::map<std::string, int> ids;
    std::vector<int> gid(set.groups.size());
    for (std::size_t i = 0; i < gid.size(); ++i)
      gid[i] = ids.try_emplace(set.groups[i], static_cast<int>(ids.size())).first->second;
    detail::for_each_d2_block(Xn, sq, Xn, sq, search.block_rows, [&](Index, Index r0, Index rows, const MatrixXd& D2) {
      for (Index c = 0; c < rows; ++c) {
        double best = std::numeric_limits<double>::infinity();
        const int g = gid[static_cast<std::size_t>(r0 + c)];
        for (Index j = 0; j < D2.rows(); ++j)  // O(N) per row
          if (gid[static_cast<std::size_t>(j)] != g) best = std::min(best, D2(j, c));
        rep.nearest_d2(r0 + c) = best;
      }
    });
    rep.full_passes = 2;
    model.loo = std::move(rep);
  } else {
    AlphaSearchParams sp = search;
    sp.outputs_at_alpha = params.criterion != Criterion::Regret;  // choose_by_regret computes them
    sp.refine_on_grid = params.criterion != Criterion::Regret;    // it picks among the scan's α
    model.loo = select_alpha(Xn, set.outputs, set.groups, sp);
    if (params.criterion == Criterion::Regret) {
      if (!one_output_per_part(set.outputs, set.groups))
        throw Error("train: the regret criterion needs one output row per part (a part's vectors differ)");
      choose_by_regret(Xn, set, search, model);
    }
  }
  model.criterion = params.criterion;
  model.alpha = model.loo.alpha;
  model.strategies = set.strategies;
  model.inputs = set.inputs;
  model.outputs = set.outputs;
  model.groups = set.groups;
  model.unfamiliar_factor = params.unfamiliar_factor;
  model.unfamiliar_percentile = params.unfamiliar_percentile;
  std::vector<double> nd(model.loo.nearest_d2.data(), model.loo.nearest_d2.data() + model.loo.nearest_d2.size());
  model.unfamiliar_threshold = params.unfamiliar_factor * percentile(std::move(nd), params.unfamiliar_percentile);
  if (one_output_per_part(set.outputs, set.groups)) {  // a confidence is about a part's one best strategy
    const std::vector<PartPick> picks =
        part_picks(model.loo.verification, set.outputs, set.groups, model.loo.nearest_d2);
    model.calibration = calibrate(picks, static_cast<std::size_t>(set.outputs.cols()), model.unfamiliar_threshold);
  }
  return model;
}

Prediction predict(const Model& model, const MatrixXd& inputs) {
  if (inputs.cols() != model.normalizer.dims())
    throw Error("predict: input vectors have " + std::to_string(inputs.cols()) + " values, the model expects " +
                std::to_string(model.normalizer.dims()));
  const NetworkOutputs net = evaluate_network(model.normalizer.apply(model.inputs), model.outputs,
                                              model.normalizer.apply(inputs), model.alpha);
  Prediction p;
  p.probabilities = net.outputs;
  p.d2_min = net.d2_min;
  p.unfamiliar.resize(static_cast<std::size_t>(inputs.rows()));
  for (Index i = 0; i < inputs.rows(); ++i)
    p.unfamiliar[static_cast<std::size_t>(i)] = net.d2_min(i) > model.unfamiliar_threshold;
  return p;
}

MatrixXd expected_regret(const Model& model, const MatrixXd& inputs) {
  if (inputs.cols() != model.normalizer.dims())
    throw Error("predict: input vectors have " + std::to_string(inputs.cols()) + " values, the model expects " +
                std::to_string(model.normalizer.dims()));
  MatrixXd R(model.outputs.rows(), model.outputs.cols());
  for (Index j = 0; j < R.rows(); ++j)  // O(N·K²)
    for (Index k = 0; k < R.cols(); ++k) R(j, k) = pick_regret(model.outputs.row(j), k);
  return evaluate_network(model.normalizer.apply(model.inputs), R, model.normalizer.apply(inputs), model.alpha).outputs;
}

}  // namespace millnet::classifier
