// Facade: plan → contour → feeds → levels → G-code → metrics.
#include "millnet/pocket/machining.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/cut_links.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "offset.hpp"

#include <algorithm>
#include <tuple>
#include <cmath>
#include <limits>
#include <optional>

namespace millnet::pocket {

namespace {
/// A wall loop may start every this many mm along it (straight edges are split to allow it).
constexpr double kWallStartMm = 2.0;

Chain loop_chain(const std::vector<Vec2>& loop, const Path2D& after, double R) {
  // Start at the loop vertex nearest to any vertex of the area-clearing path.
  std::size_t best_k = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < loop.size(); ++k)
    for (const Chain& c : after.chains)
      for (const Vertex& v : c.pts) {
        const double d = (v.p() - loop[k]).norm();
        if (d < best) {
          best = d;
          best_k = k;
        }
      }
  Chain ch;
  ch.role = "contour";
  ch.predrill = !(best <= 0.5 * R);
  for (std::size_t i = 0; i <= loop.size(); ++i) {
    const Vec2& p = loop[(best_k + i) % loop.size()];
    ch.pts.push_back({p.x(), p.y(), 0.0});
  }
  return ch;
}

void fill_program_metrics(MachiningResult& r, const CutParams& cut, const GcodeParams& gp,
                          const gcode::MotionModel& machine) {
  const gcode::ProgramStats st = gcode::stats(r.program, machine, stock_frame(cut));
  r.metrics.time_kinematic_min = st.kinematic_time_min;
  r.metrics.max_engagement_deg = max_engagement_deg(r.feed_profile);
  r.metrics.cut_length_mm = st.xy_cut_length_mm;
  r.metrics.rapid_length_mm = st.xy_rapid_length_mm;
  r.metrics.retractions = static_cast<double>(st.retractions);
  r.metrics.plunges = static_cast<double>(st.entries);
  r.metrics.time_adjusted_min = st.time_at_feeds_min;
  r.metrics.time_constant_min = st.time_constant_feed_min;
  r.metrics.levels = static_cast<double>(r.levels.size());
  // Pre-drill points: distinct holes the program drills (predrill entry) or would need.
  std::vector<Vec2> holes;
  for (const LevelPlan& L : r.levels)
    for (const Vec2& p : L.predrill)
      if (std::none_of(holes.begin(), holes.end(), [&](const Vec2& h) { return (h - p).norm() < tol::join_mm; }))
        holes.push_back(p);
  r.metrics.predrill_points = gp.entry == Entry::Predrill ? static_cast<double>(holes.size()) : 0.0;
}

GcodeParams gcode_params(const CutParams& cut, const MachiningOptions& opt) {
  GcodeParams gp;
  gp.cut = cut;
  gp.entry = opt.entry;
  gp.entry_angle_deg = opt.entry_angle_deg;
  gp.ramp_clearance_mm = opt.ramp_clearance_mm;
  gp.program_name = opt.program_name;
  gp.comments = opt.comments;
  return gp;
}

/// Removes from `pts` every point within 1e-6 mm of one of `gone`. O(|pts| · |gone|).
void drop_points(std::vector<Vec2>& pts, const std::vector<Vec2>& gone) {
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [&](const Vec2& p) {
                             return std::any_of(gone.begin(), gone.end(),
                                                [&](const Vec2& g) { return (g - p).norm() < tol::join_mm; });
                           }),
            pts.end());
}

/// Entry points of chains that plunge into uncut material, appended to the level's list.
void collect_predrill(LevelPlan& L) {
  for (const Chain& c : L.path.chains)
    if (c.predrill && !c.pts.empty()) {
      const Vec2 p = c.pts.front().p();
      if (std::none_of(L.predrill.begin(), L.predrill.end(),
                       [&](const Vec2& h) { return (h - p).norm() < tol::join_mm; }))
        L.predrill.push_back(p);
    }
}

/// Each wall loop's possible starts: its vertices, straight edges split every kWallStartMm, at
/// least kWallStartMm apart along the loop (a loop's chorded arcs have a vertex every ≈ 0.3 mm).
struct WallStarts {
  std::vector<std::vector<Vec2>> loops;
  std::vector<std::vector<std::size_t>> starts;  ///< per loop, the indices of its starts

  explicit WallStarts(const std::vector<Chain>& walls) {
    for (const Chain& w : walls) {
      std::vector<Vec2> l;
      for (std::size_t k = 0; k + 1 < w.pts.size(); ++k) {
        const Vec2 a = w.pts[k].p(), b = w.pts[k + 1].p();
        const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kWallStartMm)));
        for (int t = 0; t < n; ++t) l.push_back(a + (b - a) * (static_cast<double>(t) / n));
      }
      std::vector<std::size_t> s;
      double run = kWallStartMm;
      for (std::size_t k = 0; k < l.size(); ++k) {
        if (k > 0) run += (l[k] - l[k - 1]).norm();
        if (run >= kWallStartMm - 1e-9) {
          s.push_back(k);
          run = 0;
        }
      }
      loops.push_back(std::move(l));
      starts.push_back(std::move(s));
    }
  }

  /// Loop i from its vertex v round to v again.
  [[nodiscard]] std::vector<Vec2> rotated(std::size_t i, std::size_t v) const {
    std::vector<Vec2> out;
    for (std::size_t j = 0; j <= loops[i].size(); ++j) out.push_back(loops[i][(v + j) % loops[i].size()]);
    return out;
  }
};

/// A way through cut material from the tool to start v of wall loop `loop`.
struct WallLink {
  std::size_t loop = 0, v = 0;
  std::vector<Vec2> way;
};

/// The nearest start of a loop not done yet that a way through cut material from `from` reaches
/// (cut_links.hpp); nullopt when none does.
std::optional<WallLink> link_to_wall(const CutLinker& linker, const Vec2& from, const WallStarts& ws,
                                     const std::vector<char>& done, double tool_diameter) {
  std::vector<LinkTarget> targets;
  std::vector<std::pair<std::size_t, std::size_t>> owner;
  for (std::size_t i = 0; i < done.size(); ++i) {
    if (done[i] || ws.loops[i].size() < 3) continue;
    for (std::size_t v : ws.starts[i]) {
      targets.push_back({ws.loops[i][v], approach_of(ws.rotated(i, v), tool_diameter), 0.0});
      owner.push_back({i, v});
    }
  }
  auto l = linker.best_link(from, targets);
  if (!l) return std::nullopt;
  return WallLink{owner[l->target].first, owner[l->target].second, std::move(l->way)};
}

/// No way through cut material: wall chain w joined to the path's last chain by a straight
/// wall-clear move from its vertex nearest the tool where there is one (as before issue 11's
/// links), else entered anew as a chain of its own.
void join_or_enter(Chain& w, bool tool_down, const Clearance& clear, CutLinker& linker, Path2D& path) {
  if (!tool_down || w.pts.size() < 3) {
    linker.sweep(w);
    path.chains.push_back(std::move(w));
    return;
  }
  Chain& prev = path.chains.back();
  const Vec2 end = prev.pts.back().p();
  // w is closed (last = first): rotate its distinct vertices to start nearest `end`.
  const std::size_t n = w.pts.size() - 1;
  std::size_t best = 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((w.pts[k].p() - end).squaredNorm() < (w.pts[best].p() - end).squaredNorm()) best = k;
  if (!clear.move_ok(end, w.pts[best].p())) {
    linker.sweep(w);
    path.chains.push_back(std::move(w));
    return;
  }
  std::vector<Vec2> joined{end};
  for (std::size_t k = 0; k <= n; ++k) {
    const Vertex& v = w.pts[(best + k) % n];
    joined.push_back(v.p());
    if ((prev.pts.back().p() - v.p()).norm() > tol::join_mm) prev.pts.push_back({v.x, v.y, 0.0});
  }
  prev.feed.clear();
  linker.sweep(joined);
}

}  // namespace

void link_wall_chains(const Region& region, const CutParams& cut, Path2D& path, std::vector<Chain>& walls) {
  const Clearance clear(region, cut.clearance());
  CutLinker linker(region, cut, kLinkSliverMm2);
  for (const Chain& c : path.chains) linker.sweep(c);  // O(path length · R / cell²)
  const WallStarts ws(walls);
  std::vector<char> done(walls.size(), 0);
  for (std::size_t left = walls.size(); left > 0; --left) {
    const bool tool_down = !path.chains.empty() && !path.chains.back().pts.empty();
    std::optional<WallLink> pick;
    if (tool_down) pick = link_to_wall(linker, path.chains.back().pts.back().p(), ws, done, cut.tool.diameter);
    if (pick) {
      Chain& prev = path.chains.back();
      const std::vector<Vec2> loop = ws.rotated(pick->loop, pick->v);
      for (const Vec2& p : pick->way)
        if ((prev.pts.back().p() - p).norm() > tol::join_mm) prev.pts.push_back({p.x(), p.y(), 0.0});
      for (const Vec2& p : loop)
        if ((prev.pts.back().p() - p).norm() > tol::join_mm) prev.pts.push_back({p.x(), p.y(), 0.0});
      prev.feed.clear();
      linker.sweep(pick->way);
      linker.sweep(loop);
      done[pick->loop] = 1;
      continue;
    }
    // No way through cut material: the first loop left.
    const auto i = static_cast<std::size_t>(std::find(done.begin(), done.end(), 0) - done.begin());
    done[i] = 1;
    join_or_enter(walls[i], tool_down, clear, linker, path);
  }
  walls.clear();
}

std::size_t link_chains(const Region& region, const CutParams& cut, Path2D& path, std::vector<Vec2>& predrill) {
  std::vector<Vec2> joined;
  if (path.chains.size() < 2) return 0;
  CutLinker linker(region, cut, kLinkSliverMm2);
  std::vector<Chain> out{std::move(path.chains.front())};
  linker.sweep(out.back());
  for (std::size_t k = 1; k < path.chains.size(); ++k) {
    Chain& next = path.chains[k];
    std::optional<CutLinker::Link> l;
    if (!next.pts.empty() && !out.back().pts.empty()) {
      const std::vector<Vec2> pts = flatten_open(next.pts, tol::arc_chord_mm);
      l = linker.best_link(out.back().pts.back().p(), {{pts.front(), approach_of(pts, cut.tool.diameter), 0.0}});
    }
    if (!l) {
      linker.sweep(next);
      out.push_back(std::move(next));
      continue;
    }
    Chain& prev = out.back();
    prev.pts.back().bulge = 0;  // the link leaves in a straight line
    for (const Vec2& p : l->way)
      if ((prev.pts.back().p() - p).norm() > tol::join_mm) prev.pts.push_back({p.x(), p.y(), 0.0});
    for (const Vertex& v : next.pts) {
      if ((prev.pts.back().p() - v.p()).norm() <= tol::join_mm)
        prev.pts.back().bulge = v.bulge;
      else
        prev.pts.push_back(v);
    }
    prev.feed.clear();
    linker.sweep(l->way);
    linker.sweep(next);
    joined.push_back(next.pts.front().p());
  }
  path.chains = std::move(out);
  drop_points(predrill, joined);  // those starts need no pre-drilled hole now
  return joined.size();
}

void complete_path(const Region& region, const CutParams& cut, const PlanResult& plan, const MachiningOptions& opt,
                   Path2D& path, std::vector<Vec2>& predrill) {
  if (opt.contour && !plan.walls_cut) {
    // Not arc-fitted (2026-11-25): fit_arcs on the zigzag bench programs made them 2–3 % slower
    // on the machine model (an arc piece that cuts anywhere loses the air feed its chords had).
    std::vector<Chain> walls = contour_chains(region, cut, path);
    if (opt.link_walls) {
      link_wall_chains(region, cut, path, walls);
    } else {
      for (Chain& c : walls) path.chains.push_back(std::move(c));
    }
  }
  if (opt.link_walls && !plan.helix_entry_holes) (void)link_chains(region, cut, path, predrill);
}

double max_engagement_deg(const FeedProfile& profile) {
  // From the swept width (FeedPiece::swept_width_mm), not the centre count n₃: a crescent one cell
  // thick holds several centres more or fewer than its area, and the largest of thousands of
  // steps read 15–18° high at 90° on the bench's D/40 grid.
  const double D = profile.n1 * profile.grid_mm;
  double best = 0;
  for (const FeedPiece& p : profile.pieces)  // O(pieces)
    best = std::max(best, D > 0 ? std::clamp(p.swept_width_mm / D, 0.0, 1.0) : 0.0);
  return std::acos(1 - 2 * best) * 180 / M_PI;
}

std::vector<Chain> contour_chains(const Region& region, const CutParams& cut, const Path2D& after) {
  std::vector<Chain> out;
  for (const auto& loop : wall_loops(region, cut.clearance()))  // O(loops)
    out.push_back(loop_chain(loop, after, cut.tool.diameter / 2));
  return out;
}

MachiningResult machine_levels(std::vector<LevelPlan> levels, const CutParams& cut, const MachiningOptions& opt) {
  MachiningResult r;
  const GcodeParams gp = gcode_params(cut, opt);
  for (std::size_t k = 0; k < levels.size(); ++k) {
    LevelPlan& L = levels[k];
    const FeedProfile prof = assign_feeds(L.path, L.region, cut, L.top_z - L.z);
    if (k == 0) r.feed_profile = prof;
    collect_predrill(L);
  }
  if (!levels.empty()) r.path = levels.front().path;
  r.levels = std::move(levels);
  r.program = build_program(r.levels, gp);
  fill_program_metrics(r, cut, gp, opt.machine);
  // Complete clearing, level by level (issue 11): what each level region's path leaves of the
  // area the tool can reach there. O(levels · booleans over the level's path).
  for (const LevelPlan& L : r.levels) {
    const UncutArea u = uncut_area(L.region, L.path, cut.clearance(), cut.tool.diameter / 2);
    r.level_uncut_mm2.push_back(u.uncut_mm2);
    r.metrics.uncut_area_mm2 += u.uncut_mm2;
    r.metrics.reachable_area_mm2 += u.reachable_mm2;
    r.metrics.pocket_area_mm2 += area(L.region);
  }
  return r;
}

MachiningResult machine_pocket(const Region& region, const CutParams& cut, const PlanResult& plan,
                               const MachiningOptions& opt) {
  MachiningResult r;
  r.status = plan.status;
  r.message = plan.message;
  r.metrics.tool_points = static_cast<double>(plan.tool_points.pts.size());
  r.metrics.planning_time_s = plan.planning_time_s;
  r.metrics.planner_stats = plan.stats;
  r.metrics.pocket_area_mm2 = area(region);
  if (plan.status != PlanStatus::Ok || plan.path.chains.empty()) {
    if (r.status == PlanStatus::Ok) {
      r.status = PlanStatus::NothingToCut;
      r.message = "the planner returned no path";
    }
    return r;
  }
  const std::vector<double> zs = level_zs(cut.depth, cut.step_down);
  Path2D path = plan.path;
  for (Chain& c : path.chains) c.feed.clear();  // the feed map decides
  std::vector<Vec2> predrill = plan.predrill;
  complete_path(region, cut, plan, opt, path, predrill);
  // Feeds on the first level; deeper levels repeat the same plan under already-cut material, so
  // each one sees the same engagement: one feed map serves all.
  std::vector<EntryHole> holes;
  if (plan.helix_entry_holes && opt.entry == Entry::Helix) {
    // The disks build_program's helices clear (the same entry_helix, the same clearance).
    const Clearance clear(region, cut.clearance());
    for (std::size_t ci = 0; ci < path.chains.size(); ++ci) {
      const Chain& c = path.chains[ci];
      if (!c.predrill || c.pts.empty()) continue;
      if (const auto hx = entry_helix(clear, c.pts.front().p(), cut.tool.diameter))
        holes.push_back({ci, hx->first, hx->second + cut.tool.diameter / 2});
    }
  }
  const FeedProfile prof = assign_feeds(path, region, cut, cut.depth / static_cast<double>(zs.size()), holes);
  r.feed_profile = prof;
  r.path = path;
  double top = 0;
  for (double z : zs) {
    LevelPlan L;
    L.z = z;
    L.top_z = top;
    L.region = region;
    L.path = path;
    L.predrill = predrill;
    collect_predrill(L);
    r.levels.push_back(std::move(L));
    top = z;
  }
  const GcodeParams gp = gcode_params(cut, opt);
  r.program = build_program(r.levels, gp);
  fill_program_metrics(r, cut, gp, opt.machine);
  const auto* som = std::get_if<SomStats>(&plan.stats);
  r.metrics.tour_length_mm = som ? som->smoothing.tour_length_mm : plan.path.cut_length();
  const UncutArea u = uncut_area(region, path, cut.clearance(), cut.tool.diameter / 2);
  r.metrics.uncut_area_mm2 = u.uncut_mm2;
  r.metrics.reachable_area_mm2 = u.reachable_mm2;
  return r;
}

std::vector<std::size_t> rank_by_time_to_clear(const std::vector<const MachiningResult*>& results) {
  std::vector<std::size_t> order(results.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto key = [&](std::size_t i) {
    const MachiningResult& m = *results[i];
    return std::tuple(m.status != PlanStatus::Ok, !(m.metrics.uncut_area_mm2 <= kClearedUncutMm2),
                      m.metrics.time_kinematic_min);
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  std::vector<std::size_t> rank(results.size());
  for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = k + 1;
  return rank;
}

}  // namespace millnet::pocket
