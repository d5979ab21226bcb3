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
// Code: AlphaSearch below runs these passes, one member each (predict_grids, scan_pass, refine,
// outputs_at_alpha); the per-row kernels and the full passes they use are in loo_kernels.{hpp,cpp}.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "engine.hpp"
#include "loo_kernels.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/tolerances.hpp"
#include "millnet/core/error.hpp"

namespace millnet::classifier {

using detail::Index;
using detail::Prepared;
using Eigen::ArrayXd;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

using namespace detail::loo;
using detail::Lane;

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

struct Golden {
  double alpha = 0;
  Figures fig;
  int evaluations = 0;
};

// Golden section on u = ln α over [lo, hi] (α values); returns the best point evaluated, seeded
// with (alpha0, f0) so that the refinement never ends worse than the scan. Ties keep the
// smaller α. At most 200 evaluations.
template <class F>
Golden golden_section(F&& f, double lo, double hi, double alpha0, Figures f0, double tol_ln) {
  Golden best{alpha0, f0, 0};
  auto eval = [&](double u) {
    const double alpha = std::exp(u);
    const Figures fig = f(alpha);
    ++best.evaluations;
    if (fig.rms < best.fig.rms || (fig.rms == best.fig.rms && alpha < best.alpha)) {
      best.alpha = alpha;
      best.fig = fig;
    }
    return fig.rms;
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = std::log(lo), b = std::log(hi);
  if (!(b - a > tol_ln)) return best;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = eval(c), fd = eval(d);
  while (b - a > tol_ln && best.evaluations < 200) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = eval(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = eval(d);
    }
  }
  return best;
}

// ---- select_alpha, pass by pass ----------------------------------------------------------------
// The passes of the header comment, each a member of AlphaSearch (the state they share):
//   pre-scan   predict_grids       every k-th vector: which refinement grids the scan can evaluate
//   pass 1     scan_pass           all candidates of both modes, the predicted grids, the cache
//   pass 2     refine              per mode: golden section on the cache, else a grid
//   pass 3     outputs_at_alpha    verification and filtration at the chosen α

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

// Per-thread buffers of the scan kernel.
struct ScanBuffers {
  ArrayXd e;
  std::vector<double> Sng, tmp, sib;
  std::vector<Lane> acc;
};

// Scan sums per block: 2·C entries per block (part-out candidates, then vector-out).
using ScanParts = std::vector<std::vector<PartialSums>>;

// Refinement grids of one pass (the scan's when the pre-scan predicted them, else their own) with
// the kept sums and the figures per point.
struct Grids {
  std::vector<GridSpec> specs;
  std::vector<GridStore> stores;
  GridParts parts;  // per-block sums while they are evaluated during the scan
  std::vector<std::vector<Figures>> figures;
};

// A grid whose results count for a mode's optimum.
struct GridResult {
  const GridSpec* spec = nullptr;
  const std::vector<Figures>* figures = nullptr;
  GridStore* store = nullptr;
};

// The chosen mode's optimum as a point of a grid (spec == nullptr: not on a grid).
struct GridPoint {
  const GridSpec* spec = nullptr;
  const GridStore* store = nullptr;
  Index point = 0;
};

class AlphaSearch {
public:
  AlphaSearch(const Prepared& prepared, const AlphaSearchParams& params, std::vector<double> candidates)
      : P(prepared),
        prm(params),
        n(P.X.rows()),
        n_outputs(P.Y.cols()),
        n_patterns(P.patterns.rows()),
        block_rows(prm.block_rows),
        n_blocks((n + block_rows - 1) / block_rows),
        neighbours(std::min(prm.cache_neighbours, n)),
        alphas(std::move(candidates)),
        n_candidates(static_cast<Index>(this->alphas.size())),
        per_octave(prm.steps_per_octave),
        same_modes(P.singleton_groups),
        chosen(prm.mode == LooMode::PartOut ? kPart : kVector),
        tol_ln(prm.refine_tolerance_octaves * std::log(2.0)),
        margin_refine(tol::kRefineTruncationMargin + std::log(static_cast<double>(n))),
        // keeping the chosen mode's grid sums costs N·points·2P doubles: only within 2·N·(D + R)
        store_budget(std::max(static_cast<double>(n) * static_cast<double>(P.X.cols() + neighbours) * 2.0, 1e6)) {
    inv_alphas.resize(this->alphas.size());
    for (std::size_t k = 0; k < inv_alphas.size(); ++k) inv_alphas[k] = 1.0 / this->alphas[k];
    cache.dplus.assign(static_cast<std::size_t>(n), kInf);
    for (auto& m : cache.m) m.assign(static_cast<std::size_t>(n), 0.0);
  }

  // Fills rep (mode and d2_scale set by the caller): the table of contents of the search.
  void run(LooReport& rep) {
    Grids predicted = predict_grids();
    const ScanParts scan = scan_pass(predicted);
    if (prm.progress) prm.progress(1, 2);
    std::vector<Figures> scan_figures[2];
    scan_curve(scan, scan_figures, rep);
    Grids own_pass;  // grids the pre-scan did not predict
    const GridPoint chosen_point = refine(scan_figures, predicted, own_pass, rep);
    outputs_at_alpha(chosen_point, rep);
    rep.nearest_d2.resize(n);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) rep.nearest_d2(P.to_orig[i]) = cache.m[kPart][i];
    rep.full_passes = full_passes;
    rep.neighbour_cache_used = full_passes == 1;
    if (prm.progress) prm.progress(2, 2);
  }

private:
  // ---- pre-scan: every k-th vector as a query against all N (1/k of a pass) predicts each
  // mode's best candidate, so that the scan pass can evaluate the refinement grid too; if the
  // full scan disagrees, the grid takes its own pass as before.
  Grids predict_grids() const {
    Grids g;
    const Index stride = prm.prescan_stride;
    if (stride >= 2 && n / stride >= 16) g.specs = prescan(stride);
    g.stores = make_stores(g.specs);
    g.parts = make_grid_parts(g.specs, n_blocks);
    return g;
  }

  std::vector<GridSpec> prescan(Index stride) const {
    const auto nc = static_cast<std::size_t>(n_candidates);
    std::vector<Index> rows_idx;
    for (Index i = 0; i < n; i += stride) rows_idx.push_back(i);
    const auto m = static_cast<Index>(rows_idx.size());
    detail::RowMatrixXd Q(m, P.X.cols());
    VectorXd sqQ(m);
    for (Index t = 0; t < m; ++t) {
      Q.row(t) = P.X.row(rows_idx[static_cast<std::size_t>(t)]);
      sqQ(t) = P.sq(rows_idx[static_cast<std::size_t>(t)]);
    }
    const Index nbq = (m + block_rows - 1) / block_rows;
    ScanParts pre(static_cast<std::size_t>(nbq), std::vector<PartialSums>(2 * nc));
    // each pre-scanned row's neighbour-cache gap per mode (first dropped d² − row minimum)
    std::vector<double> pre_gap[2];
    for (auto& g : pre_gap) g.assign(static_cast<std::size_t>(m), kInf);
    detail::for_each_d2_block(P.X, P.sq, Q, sqQ, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
      RowState s;
      ScanBuffers B;
      detail::NearestBuffers sel;
      Eigen::RowVectorXd out(n_outputs);
      for (Index c = 0; c < rows; ++c) {
        const Index i = rows_idx[static_cast<std::size_t>(r0 + c)];
        load_row(P, D2.col(c).data(), i, s);
        scan_row(s, i, pre[static_cast<std::size_t>(b)].data(), B, out);
        const double dplus = detail::nearest_cut(D2.col(c).data(), n, neighbours, sel);
        pre_gap[kPart][static_cast<std::size_t>(r0 + c)] = dplus - s.mp;
        pre_gap[kVector][static_cast<std::size_t>(r0 + c)] = dplus - s.mv;
      }
    });
    std::vector<GridSpec> specs;
    for (int mode : {kPart, kVector}) {
      if (mode == kVector && same_modes) continue;
      std::vector<Figures> f(nc);
      for (std::size_t k = 0; k < nc; ++k)
        f[k] = finish_slot(pre, static_cast<std::size_t>(mode) * nc + k, m, n_outputs);
      const Index best = best_candidate(f);
      // The refinement will run on the cache if it covers the bracket for every row: skip the
      // grid when the pre-scanned rows say it will, with a factor 2 to spare for the rows not
      // pre-scanned (if it does not, the grid takes its own pass; results are identical).
      const double est_covered = *std::min_element(pre_gap[mode].begin(), pre_gap[mode].end()) / margin_refine;
      if (alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))] <= 0.5 * est_covered) continue;
      bracket_grid(mode, best, specs);
    }
    return specs;
  }

  // ---- pass 1: scan + cache: every candidate of both modes, the predicted grids, and the R
  // nearest d² of every vector; then the range of α where the cache is exact.
  ScanParts scan_pass(Grids& predicted) {
    const auto un = static_cast<std::size_t>(n);
    ScanParts scan(static_cast<std::size_t>(n_blocks),
                   std::vector<PartialSums>(2 * static_cast<std::size_t>(n_candidates)));
    std::vector<std::vector<double>> block_d2(static_cast<std::size_t>(n_blocks));
    std::vector<std::vector<std::int32_t>> block_j(static_cast<std::size_t>(n_blocks));
    std::vector<Index> row_length(un);
    detail::for_each_d2_block(P.X, P.sq, P.X, P.sq, block_rows, [&](Index b, Index r0, Index rows, const MatrixXd& D2) {
      RowState s;
      ScanBuffers B;
      GridBuffers GB;
      detail::NearestBuffers sel;
      Eigen::RowVectorXd out(n_outputs);
      auto& sums = scan[static_cast<std::size_t>(b)];
      auto& cd = block_d2[static_cast<std::size_t>(b)];
      auto& cj = block_j[static_cast<std::size_t>(b)];
      for (Index c = 0; c < rows; ++c) {
        const Index i = r0 + c;
        const auto ui = static_cast<std::size_t>(i);
        const auto d = D2.col(c).array();
        const auto cd_before = static_cast<Index>(cd.size());
        load_row(P, D2.col(c).data(), i, s);
        cache.m[kPart][ui] = s.mp;
        cache.m[kVector][ui] = s.mv;
        cache.m[kFiltration][ui] = s.mf;  // load_row's minimum over the whole row
        scan_row(s, i, sums.data(), B, out);
        if (!predicted.specs.empty()) grid_row(P, s, i, predicted.specs, predicted.stores, predicted.parts, b, GB, out);
        // R nearest (self and siblings included), in ascending j: expected O(N).
        const double dplus = detail::nearest_cut(D2.col(c).data(), n, neighbours, sel);
        cache.dplus[ui] = dplus;
        for (std::int32_t j : sel.idx)
          if (d(j) < dplus) {
            cd.push_back(d(j));
            cj.push_back(j);
          }
        row_length[ui] = static_cast<Index>(cd.size()) - cd_before;
      }
    });
    assemble_cache(row_length, block_d2, block_j);
    return scan;
  }

  // The cache in block order (CSR), and per mode the α up to which it is exact.
  void assemble_cache(const std::vector<Index>& row_length, std::vector<std::vector<double>>& block_d2,
                      std::vector<std::vector<std::int32_t>>& block_j) {
    const auto un = static_cast<std::size_t>(n);
    cache.offset.assign(un + 1, 0);
    for (std::size_t i = 0; i < un; ++i) cache.offset[i + 1] = cache.offset[i] + row_length[i];
    cache.d2.reserve(static_cast<std::size_t>(cache.offset[un]));
    cache.j.reserve(static_cast<std::size_t>(cache.offset[un]));
    for (std::size_t b = 0; b < block_d2.size(); ++b) {
      cache.d2.insert(cache.d2.end(), block_d2[b].begin(), block_d2[b].end());
      cache.j.insert(cache.j.end(), block_j[b].begin(), block_j[b].end());
      std::vector<double>().swap(block_d2[b]);
      std::vector<std::int32_t>().swap(block_j[b]);
    }
    const double margin = tol::kTruncationMargin + std::log(static_cast<double>(n));
    for (int mode : {kPart, kVector, kFiltration}) {
      double gap = kInf;  // smallest (first dropped d² − row minimum) over all rows
      for (std::size_t i = 0; i < un; ++i) gap = std::min(gap, cache.dplus[i] - cache.m[mode][i]);
      cache.covered[mode] = std::max(gap / margin, 0.0);
      cache.covered_refine[mode] = std::max(gap / margin_refine, 0.0);
    }
  }

  // Both modes' scan figures per candidate, and the scan curve (ascending α) into rep.
  void scan_curve(const ScanParts& scan, std::vector<Figures> fig[2], LooReport& rep) const {
    const auto nc = static_cast<std::size_t>(n_candidates);
    for (int mode : {kPart, kVector}) {
      fig[mode].resize(nc);
      for (std::size_t k = 0; k < nc; ++k)
        fig[mode][k] = finish_slot(scan, static_cast<std::size_t>(mode) * nc + k, n, n_outputs);
    }
    if (same_modes) fig[kVector] = fig[kPart];
    for (Index k = n_candidates - 1; k >= 0; --k) {
      const auto uk = static_cast<std::size_t>(k);
      rep.curve.push_back(
          {alphas[uk], fig[kPart][uk].rms, fig[kVector][uk].rms, fig[kPart][uk].accuracy, fig[kVector][uk].accuracy});
    }
  }

  // ---- pass 2: refinement per mode ----------------------------------------------------------
  // Golden section on the cache when it is exact (looser refinement margin) over the mode's whole
  // bracket; otherwise the grid evaluated during the scan when the pre-scan predicted this
  // bracket, else ONE full pass for every remaining mode together. Returns the chosen mode's
  // optimum when it lies on a grid.
  GridPoint refine(const std::vector<Figures> scan_figures[2], Grids& predicted, Grids& own_pass, LooReport& rep) {
    std::vector<GridResult> grids;  // every grid whose results count
    predicted.figures = grid_results(predicted.parts, predicted.specs, n, n_outputs);
    for (int mode : {kPart, kVector}) {
      const Index best = best_candidate(scan_figures[mode]);
      ModeOptimum& opt = mode == kPart ? rep.part : rep.vector;
      opt.edge = best == 0 ? Edge::High : best == n_candidates - 1 ? Edge::Low : Edge::None;
      if (mode == kVector && same_modes) continue;
      if (refine_on_cache(mode, best, opt)) continue;
      std::vector<GridSpec> want;
      bracket_grid(mode, best, want);
      std::vector<std::size_t> match;
      if (was_predicted(predicted.specs, mode, want, match)) {
        for (std::size_t g : match) grids.push_back({&predicted.specs[g], &predicted.figures[g], &predicted.stores[g]});
      } else {
        own_pass.specs.insert(own_pass.specs.end(), want.begin(), want.end());
      }
    }
    own_pass.stores = make_stores(own_pass.specs);
    if (!own_pass.specs.empty()) {
      ++full_passes;
      own_pass.figures = grid_pass(P, own_pass.specs, block_rows, own_pass.stores);
      for (std::size_t g = 0; g < own_pass.specs.size(); ++g)
        grids.push_back({&own_pass.specs[g], &own_pass.figures[g], &own_pass.stores[g]});
    }
    const GridPoint point = grid_optima(grids, rep);
    if (same_modes) {
      const Edge e = rep.vector.edge;
      rep.vector = rep.part;
      rep.vector.edge = e;
    }
    return point;
  }

  // Golden section on the cache around candidate `best` when the cache is exact over the whole
  // bracket; false (opt untouched) otherwise.
  bool refine_on_cache(int mode, Index best, ModeOptimum& opt) {
    const double a_hi = alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))];
    const double a_lo = alphas[static_cast<std::size_t>(std::min<Index>(best + 1, n_candidates - 1))];
    const double a0 = alphas[static_cast<std::size_t>(best)];
    if (!(a_hi <= cache.covered_refine[mode])) return false;
    const Evaluator ev{P, cache, block_rows, &full_passes, true};
    const Figures f0 = ev(a0, mode);
    const Golden g = golden_section([&](double a) { return ev(a, mode); }, a_lo, a_hi, a0, f0, tol_ln);
    opt.alpha = g.alpha;
    opt.rms = g.fig.rms;
    opt.accuracy = g.fig.accuracy;
    opt.refine_evaluations = g.evaluations + 1;
    return true;
  }

  // Whether the pre-scan predicted exactly the grids `want` of the mode; their indices in match.
  static bool was_predicted(const std::vector<GridSpec>& predicted, int mode, const std::vector<GridSpec>& want,
                            std::vector<std::size_t>& match) {
    for (std::size_t g = 0; g < predicted.size(); ++g)
      if (predicted[g].mode == mode) match.push_back(g);
    bool same = match.size() == want.size();
    for (std::size_t t = 0; same && t < want.size(); ++t) {
      const GridSpec& a = predicted[match[t]];
      same = a.u0 == want[t].u0 && a.h == want[t].h && a.points == want[t].points;
    }
    return same;
  }

  // Each mode's optimum over its grid points (ties → smaller α) into rep; the chosen mode's as a
  // grid point.
  GridPoint grid_optima(const std::vector<GridResult>& grids, LooReport& rep) const {
    GridPoint chosen_point;
    for (int mode : {kPart, kVector}) {
      ModeOptimum& opt = mode == kPart ? rep.part : rep.vector;
      bool first = true;
      for (const GridResult& g : grids) {
        const GridSpec& sp = *g.spec;
        if (sp.mode != mode) continue;
        for (Index t = 0; t < sp.points; ++t) {
          const double a = 1.0 / (sp.u0 + static_cast<double>(t) * sp.h);
          const Figures& f = (*g.figures)[static_cast<std::size_t>(t)];
          if (first || f.rms < opt.rms || (f.rms == opt.rms && a < opt.alpha)) {
            first = false;
            opt.alpha = a;
            opt.rms = f.rms;
            opt.accuracy = f.accuracy;
            if (mode == chosen) chosen_point = {&sp, g.store, t};
          }
        }
        opt.refine_evaluations += static_cast<int>(sp.points);
      }
    }
    return chosen_point;
  }

  // ---- pass 3: outputs at the chosen α: from the grid sums kept for it, else from the cache
  // when it is exact for every mode, else one full pass for both modes and the filtration.
  void outputs_at_alpha(const GridPoint& on_grid, LooReport& rep) {
    rep.alpha = chosen == kPart ? rep.part.alpha : rep.vector.alpha;
    rep.verification.resize(n, n_outputs);
    rep.filtration.resize(n, n_outputs);
    Figures fm[2];
    if (on_grid.spec && !on_grid.store->S.empty()) {  // no further pass
      outputs_from_store(P, *on_grid.spec, *on_grid.store, on_grid.point, chosen, fm, rep.verification, rep.filtration);
    } else if (rep.alpha <= std::min({cache.covered[kPart], cache.covered[kVector], cache.covered[kFiltration]})) {
      const Evaluator ev{P, cache, block_rows, &full_passes, false};
      fm[chosen] = ev(rep.alpha, chosen, &rep.verification);
      fm[1 - chosen] = ev(rep.alpha, 1 - chosen);
      (void)ev(rep.alpha, kFiltration, &rep.filtration);
    } else {  // one pass for both modes and the filtration
      ++full_passes;
      final_pass(P, rep.alpha, chosen, block_rows, fm, rep.verification, rep.filtration);
    }
    rep.rms_part_at_alpha = fm[kPart].rms;
    rep.rms_vector_at_alpha = fm[kVector].rms;
    rep.accuracy_part_at_alpha = fm[kPart].accuracy;
    rep.accuracy_vector_at_alpha = fm[kVector].accuracy;
    // the chosen mode's optimum is reported with the exact figures at its α
    ModeOptimum& copt = chosen == kPart ? rep.part : rep.vector;
    copt.rms = fm[chosen].rms;
    copt.accuracy = fm[chosen].accuracy;
    if (same_modes) {
      ModeOptimum& other = chosen == kPart ? rep.vector : rep.part;
      other.rms = copt.rms;
      other.accuracy = copt.accuracy;
    }
  }

  // ---- shared steps ----------------------------------------------------------------------------

  // Scan of one loaded row into sums (2·C entries: part-out, then vector-out): other-group sums
  // at every candidate from q squaring chains α, α/2, α/4, … (one exp per pair per chain, then a
  // square and an add per pair and candidate): O(N·(q + C)).
  void scan_row(const RowState& s, Index i, PartialSums* sums, ScanBuffers& B, Eigen::RowVectorXd& out) const {
    const Index nc = n_candidates, q = per_octave, np = n_patterns;
    B.Sng.resize(static_cast<std::size_t>(nc) * static_cast<std::size_t>(np));
    for (Index r = 0; r < std::min<Index>(q, nc); ++r) {
      exp_floored(s.delta, inv_alphas[static_cast<std::size_t>(r)], B.e);
      const Index steps = (nc - r + q - 1) / q;  // candidates r, r + q, r + 2q, …
      for (Index p = 0; p < np; ++p)
        power_sums<true>(B.e.data(), nullptr, P.pstart[static_cast<std::size_t>(p)],
                         P.pstart[static_cast<std::size_t>(p) + 1], steps, B.Sng.data() + r * np + p, q * np, B.acc);
    }
    score_modes(P, s, i, inv_alphas.data(), nc, B.Sng.data(), sums,
                same_modes ? nullptr : sums + static_cast<std::size_t>(nc), out, B.tmp, B.sib);
  }

  // The candidate with the smallest RMS; ties → smaller α.
  Index best_candidate(const std::vector<Figures>& f) const {
    Index best = 0;
    for (Index k = 1; k < n_candidates; ++k)
      if (f[static_cast<std::size_t>(k)].rms <= f[static_cast<std::size_t>(best)].rms) best = k;
    return best;
  }

  // One grid over the bracket [α_lo, α_hi] around candidate `best`, points even in 1/α with ONE
  // step h (so each pair costs 2 exps, e at the first point and the ratio r = exp(−δ·h), then a
  // multiply per point): h is the finer of the two halves' steps, each half [α_hi, α_best] and
  // [α_best, α_lo] having width / tolerance steps, at most kMaxSteps; α_best is a grid point
  // and the grid ends at or just past α_lo.
  void bracket_grid(int mode, Index best, std::vector<GridSpec>& out_specs) const {
    constexpr double kMaxSteps = 16;
    const double a_hi = alphas[static_cast<std::size_t>(std::max<Index>(best - 1, 0))];
    const double a_lo = alphas[static_cast<std::size_t>(std::min<Index>(best + 1, n_candidates - 1))];
    const double a0 = alphas[static_cast<std::size_t>(best)];
    double h = kInf;
    for (const auto& [a_top, a_bot] : {std::pair{a_hi, a0}, std::pair{a0, a_lo}}) {
      if (!(a_top > a_bot)) continue;
      const double steps = std::clamp(std::ceil(std::log(a_top / a_bot) / tol_ln), 1.0, kMaxSteps);
      h = std::min(h, (1.0 / a_bot - 1.0 / a_top) / steps);
    }
    if (!(h < kInf)) return;
    const double above = a_hi > a0 ? std::round((1.0 / a0 - 1.0 / a_hi) / h) : 0.0;
    const double below = a0 > a_lo ? std::ceil((1.0 / a_lo - 1.0 / a0) / h - 1e-9) : 0.0;
    GridSpec sp;
    sp.mode = mode;
    sp.h = h;
    sp.u0 = 1.0 / a0 - above * h;
    sp.points = static_cast<Index>(above + below) + 1;
    out_specs.push_back(sp);
  }

  // Stores for the chosen mode's grids when their sums fit the budget (else left empty).
  std::vector<GridStore> make_stores(const std::vector<GridSpec>& specs) const {
    std::vector<GridStore> st(specs.size());
    double need = 0;
    for (const auto& g : specs)
      if (g.mode == chosen) need += static_cast<double>(n) * static_cast<double>(g.points * n_patterns) * 2.0;
    for (std::size_t g = 0; g < specs.size(); ++g)
      if (specs[g].mode == chosen && need <= store_budget) {
        const auto sz = static_cast<std::size_t>(n * specs[g].points * n_patterns);
        st[g].S.assign(sz, 0.0);
        st[g].Sg.assign(sz, 0.0);
        st[g].shift.resize(static_cast<std::size_t>(n));
      }
    return st;
  }

  const Prepared& P;
  const AlphaSearchParams& prm;
  const Index n;           // stored vectors N
  const Index n_outputs;   // K
  const Index n_patterns;  // distinct output rows P
  const Index block_rows, n_blocks;
  const Index neighbours;            // R: nearest d² kept per vector
  const std::vector<double> alphas;  // scan candidates, descending
  std::vector<double> inv_alphas;
  const Index n_candidates;    // C
  const Index per_octave;      // q: candidates per octave (= squaring chains)
  const bool same_modes;       // one vector per group: part-out = vector-out
  const int chosen;            // the mode that chooses α
  const double tol_ln;         // refinement tolerance in ln α
  const double margin_refine;  // truncation margin of the refinement on the cache
  const double store_budget;   // doubles the chosen mode's grid sums may take
  Cache cache;
  int full_passes = 1;  // the scan
};

}  // namespace

namespace detail {

Prepared prepare(const MatrixXd& Xn, const MatrixXd& Y, const std::vector<std::string>& groups) {
  const Index n = Xn.rows();
  if (n < 2) throw Error("classifier: need at least 2 stored vectors, got " + std::to_string(n));
  if (Xn.cols() < 1) throw Error("classifier: inputs have no columns (expected N×D, D ≥ 1)");
  if (Y.rows() != n || Y.cols() < 1)
    throw Error("classifier: outputs are " + std::to_string(Y.rows()) + "×" + std::to_string(Y.cols()) + ", expected " +
                std::to_string(n) + "×K with K ≥ 1 (one row per input vector)");
  if (static_cast<Index>(groups.size()) != n)
    throw Error("classifier: " + std::to_string(groups.size()) + " group ids for " + std::to_string(n) +
                " vectors (expected one source part per vector)");
  if (!Xn.allFinite()) throw Error("classifier: inputs contain NaN or infinite values");
  if (!Y.allFinite()) throw Error("classifier: outputs contain NaN or infinite values");
  if (n > std::numeric_limits<std::int32_t>::max()) throw Error("classifier: too many stored vectors");

  Prepared P;
  const auto un = static_cast<std::size_t>(n);
  std::vector<Index> ord(un);
  std::iota(ord.begin(), ord.end(), Index{0});
  // O(N log N · K): lexicographic order of output rows, stable, so equal rows keep input order.
  std::stable_sort(ord.begin(), ord.end(), [&Y](Index a, Index b) {
    for (Index k = 0; k < Y.cols(); ++k)
      if (Y(a, k) != Y(b, k)) return Y(a, k) < Y(b, k);
    return false;
  });
  P.to_orig = ord;
  P.X.resize(n, Xn.cols());
  P.Y.resize(n, Y.cols());
  for (Index i = 0; i < n; ++i) {
    P.X.row(i) = Xn.row(ord[static_cast<std::size_t>(i)]);
    P.Y.row(i) = Y.row(ord[static_cast<std::size_t>(i)]);
  }
  P.sq = P.X.rowwise().squaredNorm();
  std::map<std::string, int> ids;  // ids by first appearance in the caller's order
  std::vector<int> gid_orig(un);
  for (std::size_t r = 0; r < un; ++r) {
    auto it = ids.try_emplace(groups[r], static_cast<int>(ids.size())).first;
    gid_orig[r] = it->second;
  }
  P.group.resize(un);
  P.members.assign(ids.size(), {});
  for (Index i = 0; i < n; ++i) {
    const int g = gid_orig[static_cast<std::size_t>(ord[static_cast<std::size_t>(i)])];
    P.group[static_cast<std::size_t>(i)] = g;
    P.members[static_cast<std::size_t>(g)].push_back(i);
  }
  P.singleton_groups = ids.size() == un;
  std::vector<Index> starts;
  for (Index i = 0; i < n; ++i)
    if (i == 0 || P.Y.row(i) != P.Y.row(i - 1)) starts.push_back(i);
  P.patterns.resize(static_cast<Index>(starts.size()), Y.cols());
  for (std::size_t p = 0; p < starts.size(); ++p) P.patterns.row(static_cast<Index>(p)) = P.Y.row(starts[p]);
  starts.push_back(n);
  P.pstart = starts;
  P.label.resize(un);
  for (Index i = 0; i < n; ++i) P.label[static_cast<std::size_t>(i)] = argmax(P.Y.row(i));
  P.pattern.resize(un);
  for (std::size_t p = 0; p + 1 < P.pstart.size(); ++p)
    for (Index i = P.pstart[p]; i < P.pstart[p + 1]; ++i)
      P.pattern[static_cast<std::size_t>(i)] = static_cast<Index>(p);
  return P;
}

}  // namespace detail

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

}  // namespace millnet::classifier
