#pragma once
// Private to the leave-one-out α search (loo.cpp): the state its passes share, AlphaSearch, whose
// members are the passes of loo.cpp's header comment, one file per pass:
//   loo.cpp          select_alpha and AlphaSearch::run, the table of contents of the search
//   loo_scan.cpp     pre-scan and pass 1: every candidate of both modes, the neighbour cache
//   loo_refine.cpp   pass 2 (refinement per mode) and pass 3 (outputs at the chosen α)
// The per-row kernels and the full passes they use are in loo_kernels.{hpp,cpp}.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine.hpp"
#include "loo_kernels.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/tolerances.hpp"

namespace millnet::classifier::detail::loo {

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

// The α search: its passes, one member each, and the state they share (the prepared set, the
// candidates, the neighbour cache). run() is the table of contents.
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
  void run(LooReport& rep);

private:
  // ---- pre-scan: every k-th vector as a query against all N (1/k of a pass) predicts each
  // mode's best candidate, so that the scan pass can evaluate the refinement grid too; if the
  // full scan disagrees, the grid takes its own pass as before.
  Grids predict_grids() const;

  std::vector<GridSpec> prescan(Index stride) const;

  // ---- pass 1: scan + cache: every candidate of both modes, the predicted grids, and the R
  // nearest d² of every vector; then the range of α where the cache is exact.
  ScanParts scan_pass(Grids& predicted);

  // The cache in block order (CSR), and per mode the α up to which it is exact.
  void assemble_cache(const std::vector<Index>& row_length, std::vector<std::vector<double>>& block_d2,
                      std::vector<std::vector<std::int32_t>>& block_j);

  // Both modes' scan figures per candidate, and the scan curve (ascending α) into rep.
  void scan_curve(const ScanParts& scan, std::vector<Figures> fig[2], LooReport& rep) const;

  // ---- pass 2: refinement per mode ----------------------------------------------------------
  // Golden section on the cache when it is exact (looser refinement margin) over the mode's whole
  // bracket; otherwise the grid evaluated during the scan when the pre-scan predicted this
  // bracket, else ONE full pass for every remaining mode together. Returns the chosen mode's
  // optimum when it lies on a grid.
  GridPoint refine(const std::vector<Figures> scan_figures[2], Grids& predicted, Grids& own_pass, LooReport& rep);

  // Golden section on the cache around candidate `best` when the cache is exact over the whole
  // bracket; false (opt untouched) otherwise.
  bool refine_on_cache(int mode, Index best, ModeOptimum& opt);

  // Whether the pre-scan predicted exactly the grids `want` of the mode; their indices in match.
  static bool was_predicted(const std::vector<GridSpec>& predicted, int mode, const std::vector<GridSpec>& want,
                            std::vector<std::size_t>& match);

  // Each mode's optimum over its grid points (ties → smaller α) into rep; the chosen mode's as a
  // grid point.
  GridPoint grid_optima(const std::vector<GridResult>& grids, LooReport& rep) const;

  // ---- pass 3: outputs at the chosen α: from the grid sums kept for it, else from the cache
  // when it is exact for every mode, else one full pass for both modes and the filtration.
  void outputs_at_alpha(const GridPoint& on_grid, LooReport& rep);

  // ---- shared steps ----------------------------------------------------------------------------

  // Scan of one loaded row into sums (2·C entries: part-out, then vector-out): other-group sums
  // at every candidate from q squaring chains α, α/2, α/4, … (one exp per pair per chain, then a
  // square and an add per pair and candidate): O(N·(q + C)).
  void scan_row(const RowState& s, Index i, PartialSums* sums, ScanBuffers& B, Eigen::RowVectorXd& out) const;

  // The candidate with the smallest RMS; ties → smaller α.
  Index best_candidate(const std::vector<Figures>& f) const;

  // One grid over the bracket [α_lo, α_hi] around candidate `best`, points even in 1/α with ONE
  // step h (so each pair costs 2 exps, e at the first point and the ratio r = exp(−δ·h), then a
  // multiply per point): h is the finer of the two halves' steps, each half [α_hi, α_best] and
  // [α_best, α_lo] having width / tolerance steps, at most kMaxSteps; α_best is a grid point
  // and the grid ends at or just past α_lo.
  void bracket_grid(int mode, Index best, std::vector<GridSpec>& out_specs) const;

  // Stores for the chosen mode's grids when their sums fit the budget (else left empty).
  std::vector<GridStore> make_stores(const std::vector<GridSpec>& specs) const;

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

}  // namespace millnet::classifier::detail::loo
