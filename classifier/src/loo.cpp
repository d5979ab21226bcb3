// Leave-one-out selection of the penalty coefficient α (Korosec & Kopac, "prevents over-training":
// delete a case, predict it from the rest, minimize the RMS verification error).
//
// Pass structure (N stored vectors, D inputs, C candidates, q steps per octave, R cache size,
// G grid points, P distinct output rows). A "full pass" is one blocked N×N×D GEMM; the kernels
// share one exp per pair between part-out, vector-out and filtration (see RowState).
//  1. Scan: one full pass. For each stored vector the C candidates of both modes come from the
//     same d² column: the candidates form q chains α, α/2, α/4, … so exp(−δ/(α/2)) = exp(−δ/α)²
//     — one exp per pair per chain, then a square and an add per pair and candidate, in one
//     sweep with early exit once a lane group underflows: O(N²·(q + C)). The R nearest d² of
//     every vector are kept (O(N·R) memory).
//  2. Refinement per mode around its best candidate: golden section on log α on the cache when
//     the cache is exact over the whole bracket (cheap: O(N·R) per evaluation); otherwise ONE
//     full pass for all such modes evaluating G points even in 1/α with one step over
//     [α_lo, α_hi], α_best among them (exact exps: 2 per pair and mode, then one multiply per
//     point); the chosen mode's run sums are kept (N·G·2P doubles) so its outputs need no
//     further pass. A pre-scan of every k-th vector (1/k of a pass) predicts each mode's best
//     candidate and whether the cache will cover its bracket, so that the scan pass evaluates
//     the grids too: the refinement's own pass is needed only when the prediction fails.
//  3. Filtration and verification outputs at the chosen α: from the kept sums, from the cache
//     when exact, else one full pass for both modes and the filtration together.
// So 1–3 full passes in all (1 + 1/k in the usual case), never an N×N matrix.
// Per pair, the work is the GEMM's 2D flops, q + 2·(modes on a grid) exps (simd.hpp) and the
// multiply-adds of the chains; the GEMM runs in L2-sized tiles (engine.hpp).
// Determinism: blocks are fixed by block_rows, never by the thread count; every reduction is a
// per-block partial sum combined in block order.
// Code: AlphaSearch (loo_search.hpp) runs these passes, one member each (predict_grids, scan_pass,
// refine, outputs_at_alpha), in loo_scan.cpp (pre-scan, pass 1) and loo_refine.cpp (passes 2 and 3);
// AlphaSearch::run below is their table of contents. The per-row kernels and the full passes they
// use are in loo_kernels.{hpp,cpp}; the stored set is prepared in engine.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine.hpp"
#include "loo_kernels.hpp"
#include "loo_search.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

using detail::Index;
using detail::Prepared;
using Eigen::MatrixXd;

namespace {

using namespace detail::loo;

// Median nonzero d² over all pairs (N(N−1)/2 ≤ 65,536) or 65,536 pairs from a fixed splitmix64
// sequence. O(pairs·D).
double d2_scale(const detail::RowMatrixXd& X) {  // row-major: one vector per contiguous row
  const Index n = X.rows();
  std::vector<double> v;
  const std::uint64_t all = static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n - 1) / 2;
  constexpr std::uint64_t kMaxPairs = 65536;
  if (all <= kMaxPairs) {
    for (Index i = 0; i < n; ++i)
      for (Index j = i + 1; j < n; ++j) v.push_back((X.row(i) - X.row(j)).squaredNorm());
  } else {
    std::uint64_t state = 0x6d696c6c6e6574ULL;  // fixed seed: "millnet"
    auto next = [&state]() {
      std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      return z ^ (z >> 31);
    };
    const auto un = static_cast<std::uint64_t>(n);
    for (std::uint64_t t = 0; t < kMaxPairs; ++t) {
      const auto i = static_cast<Index>(next() % un);
      auto j = static_cast<Index>(next() % (un - 1));
      if (j >= i) ++j;
      v.push_back((X.row(i) - X.row(j)).squaredNorm());
    }
  }
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !(x > 0.0); }), v.end());
  if (v.empty()) return 1.0;  // every vector identical: any α gives the same answer
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Parameter checks that need no data. Throws millnet::Error.
void check_params(const AlphaSearchParams& prm) {
  if (prm.steps_per_octave < 1 || prm.steps_per_octave > 8)
    throw Error("alpha search: steps_per_octave must be in 1…8, got " + std::to_string(prm.steps_per_octave));
  if (prm.block_rows < 1) throw Error("alpha search: block_rows must be ≥ 1");
  if (prm.cache_neighbours < 1) throw Error("alpha search: cache_neighbours must be ≥ 1");
  if (!(prm.refine_tolerance_octaves > 0)) throw Error("alpha search: refine_tolerance_octaves must be > 0");
}

// The scan candidates, descending: α_k = hi · 2^(−r/q) · 2^(−m), k = r + q·m over the range
// [lo, hi] (relative to the d² scale unless alpha_min/alpha_max are given). ldexp halves exactly,
// which the squaring chains need.
std::vector<double> scan_candidates(const AlphaSearchParams& prm, double d2_median) {
  double hi = prm.range_high * d2_median, lo = prm.range_low * d2_median;
  if (prm.alpha_min > 0 || prm.alpha_max > 0) {
    if (!(prm.alpha_min > 0 && prm.alpha_max > prm.alpha_min))
      throw Error("alpha search: alpha_min/alpha_max must both be > 0 with alpha_min < alpha_max");
    lo = prm.alpha_min;
    hi = prm.alpha_max;
  } else if (!(prm.range_low > 0 && prm.range_high > prm.range_low)) {
    throw Error("alpha search: range_low/range_high must both be > 0 with range_low < range_high");
  }
  const int q = prm.steps_per_octave;
  const auto nc = static_cast<Index>(std::floor(q * std::log2(hi / lo) + 1e-9)) + 1;
  if (nc < 2) throw Error("alpha search: the α range is narrower than one scan step");
  std::vector<double> alphas(static_cast<std::size_t>(nc));
  for (Index k = 0; k < nc; ++k)
    alphas[static_cast<std::size_t>(k)] =
        std::ldexp(hi * std::exp2(-static_cast<double>(k % q) / q), -static_cast<int>(k / q));
  return alphas;
}

}  // namespace

// ---- select_alpha, pass by pass ----------------------------------------------------------------
// The passes of the header comment, each a member of AlphaSearch (loo_search.hpp):
//   pre-scan   predict_grids       every k-th vector: which refinement grids the scan can evaluate
//   pass 1     scan_pass           all candidates of both modes, the predicted grids, the cache
//   pass 2     refine              per mode: golden section on the cache, else a grid
//   pass 3     outputs_at_alpha    verification and filtration at the chosen α

namespace detail::loo {

void AlphaSearch::run(LooReport& rep) {
  Grids predicted = predict_grids();
  const ScanParts scan = scan_pass(predicted);
  if (prm.progress) prm.progress(1, 2);
  std::vector<Figures> scan_figures[2];
  scan_curve(scan, scan_figures, rep);
  Grids own_pass;  // grids the pre-scan did not predict
  const GridPoint chosen_point = refine(scan_figures, predicted, own_pass, rep);
  if (prm.outputs_at_alpha) {
    outputs_at_alpha(chosen_point, rep);
  } else {
    const ModeOptimum& copt = chosen == kPart ? rep.part : rep.vector;
    rep.alpha = copt.alpha;
    rep.rms_part_at_alpha = rep.part.rms;
    rep.rms_vector_at_alpha = rep.vector.rms;
    rep.accuracy_part_at_alpha = rep.part.accuracy;
    rep.accuracy_vector_at_alpha = rep.vector.accuracy;
  }
  rep.nearest_d2.resize(n);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) rep.nearest_d2(P.to_orig[i]) = cache.m[kPart][i];
  rep.full_passes = full_passes;
  rep.neighbour_cache_used = full_passes == 1;
  if (prm.progress) prm.progress(2, 2);
}

}  // namespace detail::loo

const char* to_string(LooMode m) { return m == LooMode::PartOut ? "part" : "vector"; }

LooMode loo_mode_from_string(const std::string& s) {
  if (s == "part") return LooMode::PartOut;
  if (s == "vector") return LooMode::VectorOut;
  throw Error("leave-one-out mode: got \"" + s + "\", expected \"part\" or \"vector\"");
}

const char* to_string(Edge e) { return e == Edge::None ? "none" : e == Edge::Low ? "low" : "high"; }

double rms_error(const MatrixXd& outputs, const MatrixXd& Y) {
  if (outputs.rows() != Y.rows() || outputs.cols() != Y.cols() || Y.size() == 0)
    throw Error("rms_error: outputs and targets differ in shape or are empty");
  return std::sqrt((outputs - Y).squaredNorm() / static_cast<double>(Y.size()));
}

double argmax_accuracy(const MatrixXd& outputs, const MatrixXd& Y) {
  if (outputs.rows() != Y.rows() || outputs.cols() != Y.cols() || Y.rows() == 0)
    throw Error("argmax_accuracy: outputs and targets differ in shape or are empty");
  Index ok = 0;
  for (Index i = 0; i < Y.rows(); ++i) ok += detail::argmax(outputs.row(i)) == detail::argmax(Y.row(i)) ? 1 : 0;
  return static_cast<double>(ok) / static_cast<double>(Y.rows());
}

MatrixXd verification_outputs(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups,
                              double alpha, LooMode mode, Index block_rows) {
  if (!(alpha > 0) || !std::isfinite(alpha)) throw Error("verification_outputs: alpha must be finite and > 0");
  if (block_rows < 1) throw Error("verification_outputs: block_rows must be ≥ 1");
  const Prepared P = detail::prepare(Xn, Y, groups);
  if (mode == LooMode::PartOut && P.members.size() < 2)
    throw Error("leave-one-part-out needs at least 2 groups (source parts)");
  MatrixXd out(Xn.rows(), Y.cols());
  (void)full_pass(P, alpha, mode == LooMode::PartOut ? kPart : kVector, block_rows, &out);
  return out;
}

void outputs_at_alpha(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups, double alpha,
                      LooMode mode, Index block_rows, LooReport& rep) {
  if (!(alpha > 0) || !std::isfinite(alpha)) throw Error("outputs_at_alpha: alpha must be finite and > 0");
  if (block_rows < 1) throw Error("outputs_at_alpha: block_rows must be ≥ 1");
  const Prepared P = detail::prepare(Xn, Y, groups);
  if (mode == LooMode::PartOut && P.members.size() < 2)
    throw Error("leave-one-part-out needs at least 2 groups (source parts)");
  detail::loo::Figures fig[2];
  rep.verification.resize(Xn.rows(), Y.cols());
  rep.filtration.resize(Xn.rows(), Y.cols());
  const int chosen = mode == LooMode::PartOut ? detail::loo::kPart : detail::loo::kVector;
  detail::loo::final_pass(P, alpha, chosen, block_rows, fig, rep.verification, rep.filtration);
  rep.alpha = alpha;
  rep.mode = mode;
  rep.rms_part_at_alpha = fig[detail::loo::kPart].rms;
  rep.rms_vector_at_alpha = fig[detail::loo::kVector].rms;
  rep.accuracy_part_at_alpha = fig[detail::loo::kPart].accuracy;
  rep.accuracy_vector_at_alpha = fig[detail::loo::kVector].accuracy;
  ++rep.full_passes;
}

LooReport select_alpha(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups,
                       const AlphaSearchParams& prm) {
  check_params(prm);
  const Prepared P = detail::prepare(Xn, Y, groups);
  if (P.members.size() < 2)
    throw Error(
        "leave-one-out: the stored vectors come from a single group (source part); both figures "
        "(part-out and vector-out) need at least 2 groups");
  LooReport rep;
  rep.mode = prm.mode;
  rep.d2_scale = d2_scale(P.X);
  AlphaSearch(P, prm, scan_candidates(prm, rep.d2_scale)).run(rep);
  return rep;
}

TrueOutputs true_label_outputs(const LooReport& loo, const std::vector<int>& labels) {
  TrueOutputs t;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 1) continue;
    const auto r = static_cast<Eigen::Index>(i), k = static_cast<Eigen::Index>(labels[i] - 1);
    t.filtration.push_back(loo.filtration(r, k));
    t.verification.push_back(loo.verification(r, k));
  }
  return t;
}

}  // namespace millnet::classifier
