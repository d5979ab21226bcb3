#include "millnet/pocket/planner_som.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "arc_fit.hpp"
#include "offset.hpp"
#include "work_internal.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace millnet::pocket {

namespace {

/// A chain being built: tool-centre points and whether each may be blended (grid points yes, ring
/// vertices no: the ring must pass through them to sweep the wall).
struct Poly {
  std::vector<Vec2> pts;
  std::vector<char> blendable;
};

/// Splices the closed `ring` into one of `chains` with the tool down: after vertex k of a chain
/// the tool goes straight to ring vertex v, around the ring back to v, then on to vertex k + 1 (or
/// the chain ends there). The cheapest (added length) of the candidates whose two moves are
/// move_ok; candidates pair each chain vertex with its kNear nearest ring vertices. False when
/// none is free. O(chain vertices · ring vertices) distances, then move_ok calls in cost order.
bool splice_ring(std::vector<Poly>& chains, const std::vector<Vec2>& ring, const Clearance& clear) {
  constexpr std::size_t kNear = 4;
  struct Cand {
    double cost;
    std::size_t c, k, v;
  };
  std::vector<Cand> cands;
  const std::size_t n = ring.size();
  std::vector<std::pair<double, std::size_t>> d(n);
  for (std::size_t c = 0; c < chains.size(); ++c) {
    const auto& P = chains[c].pts;
    std::vector<std::array<std::size_t, kNear>> near(P.size());
    for (std::size_t k = 0; k < P.size(); ++k) {
      for (std::size_t v = 0; v < n; ++v) d[v] = {(ring[v] - P[k]).squaredNorm(), v};
      const std::size_t m = std::min(kNear, n);
      std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(m), d.end());
      for (std::size_t i = 0; i < kNear; ++i) near[k][i] = d[std::min(i, m - 1)].second;
    }
    for (std::size_t k = 0; k < P.size(); ++k) {
      const bool last = k + 1 == P.size();
      for (std::size_t from = k; from <= (last ? k : k + 1); ++from)
        for (std::size_t v : near[from]) {
          const double out = (ring[v] - P[k]).norm();
          const double cost = last ? out : out + (P[k + 1] - ring[v]).norm() - (P[k + 1] - P[k]).norm();
          cands.push_back({cost, c, k, v});
        }
    }
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) {
    return std::tie(a.cost, a.c, a.k, a.v) < std::tie(b.cost, b.c, b.k, b.v);
  });
  for (const Cand& x : cands) {
    Poly& ch = chains[x.c];
    const bool last = x.k + 1 == ch.pts.size();
    if (!clear.move_ok(ch.pts[x.k], ring[x.v])) continue;
    if (!last && !clear.move_ok(ring[x.v], ch.pts[x.k + 1])) continue;
    std::vector<Vec2> loop;
    for (std::size_t i = 0; i <= n; ++i) loop.push_back(ring[(x.v + i) % n]);
    const auto at = static_cast<std::ptrdiff_t>(x.k + 1);
    ch.pts.insert(ch.pts.begin() + at, loop.begin(), loop.end());
    ch.blendable.insert(ch.blendable.begin() + at, loop.size(), 0);
    return true;
  }
  return false;
}

/// The chains of the smoothed tour (blendable grid points), then each wall ring spliced into one of
/// them with the tool down, or a chain of its own (not blendable) where no splice is free. Returns
/// the chains; ring_links counts the spliced rings. O(rings · path vertices · ring vertices).
std::vector<Poly> tour_and_rings(const ToolPoints& tp, const SmoothedTour& sm,
                                 const std::vector<std::vector<Vec2>>& rings, const Clearance& clear,
                                 std::size_t& ring_links) {
  std::vector<Poly> polys;
  for (const auto& ch : sm.chains) {  // O(path vertices)
    Poly p;
    for (int k : ch) p.pts.push_back(tp.pts[static_cast<std::size_t>(k)]);
    p.blendable.assign(p.pts.size(), 1);
    polys.push_back(std::move(p));
  }
  ring_links = 0;
  for (const auto& r : rings) {
    if (splice_ring(polys, r, clear)) {
      ++ring_links;
      continue;
    }
    Poly p;
    p.pts = r;
    p.pts.push_back(r.front());
    p.blendable.assign(p.pts.size(), 0);
    polys.push_back(std::move(p));
  }
  return polys;
}

/// The chains into res's path, their blendable corners blended (within the grid's coverage slack)
/// when `blend`, each a pre-drilled cut. Returns the corner arcs made.
std::size_t add_chains(const std::vector<Poly>& polys, bool blend, const CornerBlendParams& bp, const MoveOk& move_ok,
                       PlanResult& res) {
  std::size_t arcs = 0;
  for (const Poly& p : polys) {
    Chain c;
    if (blend) {
      CornerBlendStats bs;
      c.pts = blend_corners(p.pts, p.blendable, bp, move_ok, &bs);
      arcs += static_cast<std::size_t>(bs.blended);
    } else {
      for (const Vec2& q : p.pts) c.pts.push_back(Vertex{q.x(), q.y(), 0.0});
    }
    c.predrill = true;
    c.role = "cut";
    res.predrill.push_back(c.pts.front().p());
    res.path.chains.push_back(std::move(c));
  }
  return arcs;
}

}  // namespace

PlanResult plan_som(const Region& region, const CutParams& cut, const GridFrame& frame, const SomParams& som,
                    const SmoothingParams& smooth, const SomPathParams& path) {
  const auto t0 = std::chrono::steady_clock::now();
  cut.check("plan_som");
  PlanResult res;
  res.planner = "som";
  const double clearance = cut.clearance();
  // Coverage slack of the grid: a point more than R inside the rings lies ≤ g/√2 from a grid point
  // that keeps ≥ s from the rings, so grid points nearer to them than s can go (the rings sweep
  // what they would), and a corner blend may leave a grid point by less than s.
  const double R = cut.tool.diameter / 2;
  const double slack = std::max(0.0, R - frame.spacing / std::sqrt(2.0));
  if (!(path.blend_radius_mm >= 0) || !std::isfinite(path.blend_radius_mm))
    throw Error("/pocket/smoothing/blend_radius_mm: must be a number ≥ 0");
  std::vector<std::vector<Vec2>> rings;
  if (path.walls) rings = wall_loops(region, clearance);
  res.tool_points = make_tool_points(region, frame, clearance + (path.walls ? slack : 0.0));  // O(grid cells)
  const ToolPoints& tp = res.tool_points;
  const std::size_t n = tp.pts.size();
  if (n == 0 && rings.empty()) {
    std::ostringstream msg;
    msg << "no tool point fits: no grid point (spacing " << frame.spacing << " mm) keeps the tool disk (radius "
        << clearance << " mm incl. stock to leave) inside the pocket";
    res.status = PlanStatus::NoToolPoints;
    res.message = msg.str();
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  const Clearance clear(region, clearance);
  const MoveOk move_ok = [&clear](const Vec2& p, const Vec2& q) { return clear.move_ok(p, q); };

  SomResult ring;
  SmoothedTour sm;
  if (n > 0) {
    ring = som_tour(tp.pts, som);
    sm = smooth_tour(tp, ring.order, move_ok, smooth);
  }
  std::size_t ring_links = 0;
  const std::vector<Poly> polys = tour_and_rings(tp, sm, rings, clear, ring_links);
  CornerBlendParams bp;
  bp.max_radius_mm = path.blend_radius_mm > 0 ? path.blend_radius_mm : 0.5 * frame.spacing;
  bp.max_deviation_mm = 0.9 * slack;
  bp.clearance_mm = clearance;
  // No blend below a tenth of the tool's diameter. Such an arc buys no speed on a real machine,
  // which holds v²/r within its acceleration (1 mm at 500 mm/s² allows 22 mm/s, below the bench's
  // 25 mm/s), and a fine tour (stepover 1 over a 100 mm square: 20,000 corners) made the uncut-area
  // booleans of its flattened arcs run for 8 minutes instead of 3 s (CliLimits.MaxWork…).
  bp.min_radius_mm = 0.1 * cut.tool.diameter;
  const std::size_t arcs = add_chains(polys, path.blend_corners && slack > 0, bp, move_ok, res);
  res.walls_cut = path.walls;
  // The wall rings' chorded round joins and wall arcs as G2/G3 (arc_fit.hpp), as the offset
  // planner's; the tour's own moves are 5 mm lines and blends, which no circle fits within 2 µm.
  // Only with the rings (the seed's tour, the 1995 preset, keeps its bytes).
  if (path.walls) fit_arcs(res.path, tol::arc_fit_mm, &clear);
  SomStats st;
  st.tool_points = n;
  st.som_passes = ring.passes;
  st.som_converged = ring.converged;
  st.som_nodes = ring.nodes;
  st.smoothing = sm.stats;
  st.cut_length_mm = res.path.cut_length();
  st.rapid_length_mm = res.path.rapid_length();
  st.retractions = res.path.retractions();
  st.predrill_points = res.predrill.size();
  st.grid_bound_mm = n > 0 ? (static_cast<double>(n) - 1) * frame.spacing : 0.0;
  st.cut_over_bound = st.grid_bound_mm > 0 ? st.cut_length_mm / st.grid_bound_mm : 1.0;
  st.wall_rings = rings.size();
  st.wall_ring_links = ring_links;
  st.corner_arcs = arcs;
  res.stats = st;
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

// ---- the registry's entry ----

namespace {

PlannerSpec parse_som(const SettingsView& pc, const PlannerContext& ctx) {
  SomSpec spec;
  const auto grid = pc.section("grid");
  spec.frame.origin = {grid->number("origin_x"), grid->number("origin_y")};
  spec.frame.angle_deg = grid->number("angle_deg");
  spec.frame.spacing = ctx.cut->stepover;
  const auto s = pc.section("som");
  SomParams& som = spec.som;
  som.node_factor = s->number("node_factor");
  som.g0 = s->number("g0");
  som.alpha = s->number("alpha");
  som.adaptive_alpha = s->flag("adaptive_alpha");
  som.c = s->number("c");
  som.k_scale_mm = s->number("k_scale_mm");
  som.alpha_min = s->number("alpha_min");
  som.w = s->number("w");
  som.max_passes = static_cast<int>(s->integer("max_passes"));
  som.tolerance_mm = s->number("tolerance_mm");
  som.seed = ctx.seed;
  const auto m = pc.section("smoothing");
  SmoothingParams& smooth = spec.smooth;
  smooth.linking = m->flag("linking");
  smooth.link_max_ratio = m->number("link_max_ratio");
  smooth.link_max_mm = m->number("link_max_mm");
  smooth.weak = m->flag("weak");
  smooth.extra_passes = m->flag("extra_passes");
  smooth.opt_neighbours = static_cast<int>(m->integer("opt_neighbours"));
  smooth.retract_penalty_mm = m->number("retract_penalty_mm");
  smooth.max_opt_moves = static_cast<long>(m->integer("max_opt_moves"));
  spec.path.walls = s->flag("walls");
  spec.path.blend_corners = m->flag("blend_corners");
  spec.path.blend_radius_mm = m->number("blend_radius_mm");
  return spec;
}

PlanResult plan_som_spec(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  const SomSpec& s = *spec.get<SomSpec>();
  return plan_som(region, cut, s.frame, s.som, s.smooth, s.path);
}

/// The tool-point grid make_tool_points visits (exact), then the ring: M = max(3, round(node_factor
/// · N)) nodes, N ≤ the grid points (som.hpp); then the time of the run as the ring node pulls and
/// winner queries of its schedule (som_node_steps), checked against max_pairs. (Issue 42: the
/// tool points × ring nodes counted before refused a 2 × 2 m pocket at stepover 5 by 5.2e10 "pairs";
/// its tour of N = 157,609 points takes ~10 s, for 3.7e8 steps of the schedule.)
std::vector<WorkEstimate> som_work(const Region& region, const CutParams&, const PlannerSpec& spec) {
  const SomSpec& som = *spec.get<SomSpec>();
  const detail::BBox box = detail::boundary_box(region);
  const double n = grid_range(region, som.frame).points();
  const double m = std::max(3.0, std::round(som.som.node_factor * n));
  const std::string grid = detail::over("stepover", som.frame.spacing, box);
  return {{grid, n, "tool points", 24.0 * n},
          {"node_factor " + detail::mm(som.som.node_factor) + " × the tool points of " + grid, m, "SOM ring nodes",
           32.0 * m},
          {grid + " (its SOM's adaptation passes; a larger stepover or another planner)", som_node_steps(n, som.som),
           "ring node pulls and winner searches", 32.0 * m, false, true}};
}

}  // namespace

PlannerEntry som_planner() {
  return {"som",     "Shin & Suh's self-organising map over the stepover grid, smoothed",
          parse_som, plan_som_spec,
          som_work,  {{"som", {}, {}}}};
}

}  // namespace millnet::pocket
