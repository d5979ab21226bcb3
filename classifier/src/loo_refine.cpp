// The leave-one-out α search's refinement and outputs (loo_search.hpp): pass 2, per mode a golden
// section on the neighbour cache or a grid around the best scan candidate; pass 3, the
// verification and filtration outputs at the chosen α.
#include <algorithm>
#include <cmath>
#include <vector>

#include "loo_search.hpp"

namespace millnet::classifier::detail::loo {

namespace {

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

}  // namespace

GridPoint AlphaSearch::refine(const std::vector<Figures> scan_figures[2], Grids& predicted, Grids& own_pass,
                              LooReport& rep) {
  std::vector<GridResult> grids;  // every grid whose results count
  predicted.figures = grid_results(predicted.parts, predicted.specs, n, n_outputs);
  for (int mode : {kPart, kVector}) {
    const Index best = best_candidate(scan_figures[mode]);
    ModeOptimum& opt = mode == kPart ? rep.part : rep.vector;
    opt.edge = best == 0 ? Edge::High : best == n_candidates - 1 ? Edge::Low : Edge::None;
    if (mode == kVector && same_modes) continue;
    if (refine_on_cache(mode, best, opt)) continue;
    if (!prm.refine_on_grid) {  // the scan's best candidate
      opt.alpha = alphas[static_cast<std::size_t>(best)];
      opt.rms = scan_figures[mode][static_cast<std::size_t>(best)].rms;
      opt.accuracy = scan_figures[mode][static_cast<std::size_t>(best)].accuracy;
      opt.refine_evaluations = 0;
      continue;
    }
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

bool AlphaSearch::refine_on_cache(int mode, Index best, ModeOptimum& opt) {
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

bool AlphaSearch::was_predicted(const std::vector<GridSpec>& predicted, int mode, const std::vector<GridSpec>& want,
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

GridPoint AlphaSearch::grid_optima(const std::vector<GridResult>& grids, LooReport& rep) const {
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

void AlphaSearch::outputs_at_alpha(const GridPoint& on_grid, LooReport& rep) {
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

}  // namespace millnet::classifier::detail::loo
