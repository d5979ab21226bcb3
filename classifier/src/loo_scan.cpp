// The leave-one-out α search's pre-scan and scan pass (loo_search.hpp): every candidate α of both
// modes from one blocked pass over all pairs, the refinement grids the pre-scan predicts, and the
// neighbour cache; with the steps the later passes share (a row's scan, the best candidate, a
// bracket's grid, the grid stores).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "loo_search.hpp"

namespace millnet::classifier::detail::loo {

using Eigen::VectorXd;

Grids AlphaSearch::predict_grids() const {
  Grids g;
  const Index stride = prm.prescan_stride;
  if (prm.refine_on_grid && stride >= 2 && n / stride >= 16) g.specs = prescan(stride);
  g.stores = make_stores(g.specs);
  g.parts = make_grid_parts(g.specs, n_blocks);
  return g;
}

std::vector<GridSpec> AlphaSearch::prescan(Index stride) const {
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
    for (std::size_t k = 0; k < nc; ++k) f[k] = finish_slot(pre, static_cast<std::size_t>(mode) * nc + k, m, n_outputs);
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

ScanParts AlphaSearch::scan_pass(Grids& predicted) {
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

void AlphaSearch::assemble_cache(const std::vector<Index>& row_length, std::vector<std::vector<double>>& block_d2,
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

void AlphaSearch::scan_curve(const ScanParts& scan, std::vector<Figures> fig[2], LooReport& rep) const {
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

void AlphaSearch::scan_row(const RowState& s, Index i, PartialSums* sums, ScanBuffers& B,
                           Eigen::RowVectorXd& out) const {
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

Index AlphaSearch::best_candidate(const std::vector<Figures>& f) const {
  Index best = 0;
  for (Index k = 1; k < n_candidates; ++k)
    if (f[static_cast<std::size_t>(k)].rms <= f[static_cast<std::size_t>(best)].rms) best = k;
  return best;
}

void AlphaSearch::bracket_grid(int mode, Index best, std::vector<GridSpec>& out_specs) const {
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

std::vector<GridStore> AlphaSearch::make_stores(const std::vector<GridSpec>& specs) const {
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

}  // namespace millnet::classifier::detail::loo
