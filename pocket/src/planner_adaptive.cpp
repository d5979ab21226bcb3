// The adaptive (constant-engagement) planner (planner_adaptive.hpp): plan_adaptive, which reads as
// the list of the planner's passes, and the clearing loop that chains them (entries, return
// stripes, rides, links). The passes themselves are in adaptive_*.cpp (adaptive_internal.hpp).
#include "millnet/pocket/planner_adaptive.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "adaptive_internal.hpp"
#include "offset.hpp"
#include "millnet/core/settings_view.hpp"
#include "work_internal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace millnet::pocket {

namespace adaptive {

void Planner::clear_area() {
  std::optional<Vec2> pos;  // tool down here, or nullopt (retracted)
  std::size_t guard = 0;
  const std::size_t max_rounds = 200000;
  while (guard++ < max_rounds) {
    if (pos) {
      if (next_pass(*pos)) continue;
      pos.reset();  // nothing linkable from here
    }
    // Retracted: a new component's entry, or a start elsewhere in one already entered.
    if (!enter_next(pos)) break;
  }
}

bool Planner::next_pass(Vec2& pos) {
  // Both ways: a pass blocked at a wall turns round and cuts the next stripe of the same front back
  // the other way (the other milling direction), with no ride.
  if (both_ && last_blocked_ && last_cells_ >= min_work_ && turn_round(pos)) return true;
  pass_climb_ = climb_;
  // First the front's upstream end: ride back along the material (kept on the other side, nothing
  // cut) to where the front meets a wall, and climb-cut it again from there.
  if (last_cells_ >= min_work_ && ride_and_cut(pos)) return true;
  return link_and_cut(pos);
}

bool Planner::turn_round(Vec2& pos) {
  pass_climb_ = !pass_climb_;
  const double got = cut_pass(pos, -last_dir_, true);
  last_cells_ = got;
  pos = current_end();
  return got >= min_work_;
}

bool Planner::ride_and_cut(Vec2& pos) {
  std::vector<Vec2> way;
  if (!ride_back(pos, way)) return false;
  // Where no pass can start at the ride's end (every first step would cut more than the target: 116
  // of 257 passes on four_islands cut nothing there), the ride and the link to the nearest start
  // from its end become one link, pulled taut: one move through cut area instead of a ride, a stop
  // and a link.
  const std::vector<Vec2> ride = taut_ride(way);  // a few chords instead of a step every D/40
  Vec2 start, toward;
  std::vector<Vec2> beyond;
  if (!can_start(way.back(), last_heading_) && find_start(way.back(), start, toward, beyond)) {
    std::vector<Vec2> all = ride;
    all.insert(all.end(), beyond.begin() + 1, beyond.end());
    if (link_along(all)) {
      pos = pass_from(start, toward);
      return true;
    }
  }
  append_link(ride);
  last_cells_ = cut_pass(way.back(), last_heading_, true);
  pos = current_end();
  return true;
}

bool Planner::link_and_cut(Vec2& pos) {
  Vec2 start, toward;
  std::vector<Vec2> way;
  if (!find_start(pos, start, toward, way)) return false;
  if (link_along(way))
    pos = pass_from(start, toward);
  else
    dead_[lattice_index(start)] = 1;
  return true;
}

bool Planner::enter_next(std::optional<Vec2>& pos) {
  // A component not entered yet, the nearest entry first.
  std::optional<std::size_t> pick;
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    if (entries_[k].entered) continue;
    if (!pick)
      pick = k;
    else if (!chains_.empty() && (entries_[k].p - current_end()).norm() < (entries_[*pick].p - current_end()).norm())
      pick = k;
  }
  if (pick) {
    enter(entries_[*pick], pos);
    return true;
  }
  // Every component entered: uncut target left where no link reaches? Re-enter at a cleared start.
  if (raster_.uncut_target_cells() < static_cast<std::size_t>(min_work_)) return false;
  return reenter(pos);
}

void Planner::enter(Entry_& e, std::optional<Vec2>& pos) {
  e.entered = true;
  chains_.push_back(RawChain{});
  chains_.back().predrill = true;
  ++stats_.entries;
  Vec2 d(0, 1);
  if (const auto hx = entry_helix(exact_, e.p, cut_.tool.diameter)) {
    raster_.mark(hx->first, hx->second + R_);
    // The helix's flat turn at the floor, in the plan too: it makes the path sweep the bore (the
    // uncut-area figures), and with another entry than the helix it is what cuts it. A program
    // entering by the helix skips it (Chain::entry_turn): the helix's own flat turn cut it.
    const Vec2 out = e.p - hx->first;
    const int nseg = std::max(8, static_cast<int>(std::ceil(2 * kPi * hx->second / step_)));
    chains_.back().pts.push_back(e.p);
    for (int k = 1; k <= nseg; ++k)
      chains_.back().pts.push_back(hx->first + rot(out, (climb_ ? 1.0 : -1.0) * 2 * kPi * k / nseg));
    chains_.back().turn_end = chains_.back().pts.size() - 1;
    d = rot(out.normalized(), climb_ ? kPi / 2 : -kPi / 2);  // round the hole, material outside
  } else {
    raster_.mark(e.p, R_);
    ++stats_.entries_without_helix;
  }
  last_cells_ = cut_pass(e.p, d, true);
  pos = current_end();
}

bool Planner::reenter(std::optional<Vec2>& pos) {
  for (std::size_t k = 0; k < lat_ok_.size(); ++k) {  // O(lattice), only after a failed search
    if (dead_[k] || !lattice_allowed(k)) continue;
    const Vec2 p = lattice_point(k);
    Vec2 near;
    if (raster_.target_near(p, R_ + 1.5 * kLatticeMm, &near) < min_work_ || !safe(p)) continue;
    chains_.push_back(RawChain{});
    chains_.back().predrill = false;
    ++stats_.reentries;
    const double got = cut_pass(p, first_dir(p, near), true);
    last_cells_ = got;
    if (got < min_work_) dead_[k] = 1;
    pos = current_end();
    return true;
  }
  return false;
}

}  // namespace adaptive

namespace {

using adaptive::kPi;

void check_adaptive_params(const AdaptiveParams& params) {
  if (!(params.safety > 0 && params.safety <= 1))
    throw Error("adaptive planner: safety must be in (0, 1], got " + std::to_string(params.safety));
  if (params.step_mm < 0 || params.raster_mm < 0 || !std::isfinite(params.step_mm) || !std::isfinite(params.raster_mm))
    throw Error("adaptive planner: step_mm and raster_mm must be >= 0 (0 = default)");
}

/// Components thinner than a raster cell: their wall loops (walls_cut is set, so nothing else
/// would cut them; the path must not be empty).
void wall_loop_chains(const Region& region, const CutParams& cut, PlanResult& res) {
  for (const auto& loop : wall_loops(region, cut.clearance())) {
    Chain c;
    for (const Vec2& v : loop) c.pts.push_back({v.x(), v.y(), 0.0});
    c.pts.push_back(c.pts.front());
    res.predrill.push_back(c.pts.front().p());
    res.path.chains.push_back(std::move(c));
  }
}

}  // namespace

// The default cell: a step's crescent on D/40 cells holds a few cells more or fewer than its area,
// depending on where the cell centres fall (±2–3 cells, 0.66–0.85 mm of width at 0.25 mm steps on a
// Ø10 tool), which is ±6–7° at a 45° target; on D/80 the stray is about half.
double adaptive_raster_mm(const Region& region, const CutParams& cut, const AdaptiveParams& params) {
  constexpr double kMaxFineCells = 1e7;
  if (params.raster_mm > 0) return params.raster_mm;
  const double D = cut.tool.diameter;
  return raster::cells_of(region, D / 80, D) <= kMaxFineCells ? D / 80 : D / 40;
}

double adaptive_target_deg(const CutParams& cut, const AdaptiveParams& params) {
  double deg = params.max_engagement_deg;
  if (deg == 0) {
    const double R = cut.tool.diameter / 2;
    deg = std::acos(std::clamp(1 - cut.stepover / R, -1.0, 1.0)) * 180 / kPi;
  }
  if (!(deg > 0 && deg <= 180) || !std::isfinite(deg))
    throw Error("adaptive planner: max_engagement_deg must be in (0, 180], got " + std::to_string(deg));
  return deg;
}

PlanResult plan_adaptive(const Region& region, const CutParams& cut, const AdaptiveParams& params) {
  cut.check("adaptive planner");
  const double target = adaptive_target_deg(cut, params);
  check_adaptive_params(params);
  const auto t0 = std::chrono::steady_clock::now();
  PlanResult res;
  res.planner = "adaptive";
  res.walls_cut = true;
  res.helix_entry_holes = true;
  const auto comps = offset_inward(region, cut.clearance() + tol::contour_margin_mm, tol::contour_chord_mm);
  if (comps.empty()) {
    res.status = PlanStatus::NoToolPoints;
    res.message = "the tool (clearance " + std::to_string(cut.clearance()) + " mm) fits nowhere in the pocket";
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  adaptive::Planner p(region, cut, params, target);  // raster, target cells, entries, lattice
  p.clear_area();                                    // passes, rides and links
  p.cut_walls();                                     // the wall pass
  p.stats_.target_deg = target;
  res = p.result(std::move(res));  // the chains simplified
  if (res.path.chains.empty()) wall_loop_chains(region, cut, res);
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

// ---- the registry's entry ----

namespace {

PlannerSpec parse_adaptive(const SettingsView& pc, const PlannerContext&) {
  const auto ad = pc.section("adaptive");
  AdaptiveSpec spec;
  AdaptiveParams& a = spec.adaptive;
  a.max_engagement_deg = ad->number("max_engagement_deg");
  const std::string direction = ad->text("direction");
  a.climb = direction != "conventional";
  a.both_ways = direction == "both";
  a.step_mm = ad->number("step_mm");
  a.raster_mm = ad->number("raster_mm");
  a.safety = ad->number("safety");
  return spec;
}

PlanResult plan_adaptive_spec(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  return plan_adaptive(region, cut, spec.get<AdaptiveSpec>()->adaptive);
}

/// The cleared-area raster over the box grown by D (a byte of state and of target, a double of wall
/// distance and an int of component per cell).
std::vector<WorkEstimate> adaptive_work(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  const detail::BBox box = detail::boundary_box(region);
  const double h = adaptive_raster_mm(region, cut, spec.get<AdaptiveSpec>()->adaptive);
  const double n = std::ceil((box.hi.x() - box.lo.x() + 2 * cut.tool.diameter) / h) *
                   std::ceil((box.hi.y() - box.lo.y() + 2 * cut.tool.diameter) / h);
  // The key to change in the refusal (issue 42: a 2 × 2 m pocket was refused naming a raster_mm the
  // user never set); a coarser raster does not make it fast: the 1 × 1 m square plans in 41 s.
  const bool chosen = spec.get<AdaptiveSpec>()->adaptive.raster_mm > 0;
  return {{detail::over("raster_mm", h, box) + (chosen ? " (/pocket/adaptive/raster_mm)"
                                                       : " (raster_mm 0: D/80, D/40 past 10⁷ cells; "
                                                         "/pocket/adaptive/raster_mm)"),
           n, "adaptive raster cells", 24.0 * n}};
}

}  // namespace

PlannerEntry adaptive_planner() {
  return {"adaptive",     "passes at a constant radial engagement (trochoidal where the pocket is tight)",
          parse_adaptive, plan_adaptive_spec,
          adaptive_work,  {{"adaptive", {}, {}}}};
}

}  // namespace millnet::pocket
