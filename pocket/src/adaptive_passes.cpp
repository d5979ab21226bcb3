// The adaptive planner's step selection (adaptive_internal.hpp): one pass, step by step, each step
// turned as far toward the sensed material as the target engagement allows, and the checks a pass
// start needs.
#include "millnet/pocket/tolerances.hpp"

#include "adaptive_internal.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace millnet::pocket::adaptive {

Vec2 Planner::pass_from(const Vec2& start, const Vec2& toward) {
  last_cells_ = cut_pass(start, first_dir(start, toward), true);
  if (last_cells_ < min_work_) dead_[lattice_index(start)] = 1;
  return current_end();
}

Vec2 Planner::first_dir(const Vec2& start, const Vec2& toward) const {
  Vec2 v = toward - start;
  if (v.norm() < tol::coincident_mm) v = Vec2(1, 0);
  return rot(v.normalized(), climb_ ? kPi / 2 : -kPi / 2);
}

double Planner::cost(const Vec2& p, const Vec2& q) const {
  // A move no longer than the room p has beyond the clearance cannot reach a wall (every point of
  // it lies within its length of p): one distance query per position instead of an exact sweep
  // per candidate direction.
  if (!(p == room_at_)) {
    room_at_ = p;
    room_ = walls_.point_ok(p) ? walls_.wall_distance(p) - walls_.clearance() : -1.0;
    p_clear_ = raster_.clear_within(p, R_);
    p_pad_ = -1;
  }
  const double d = (q - p).norm();
  if (!(d < room_) && !walls_.move_ok(p, q)) return kInf;
  // Every caller stands on cut ground (a pass, a ride, a link's end), so only the crescent the step
  // adds can hold uncut cells; checked once per position, the full disk where it is not so.
  if (!p_clear_) return raster_.fresh(q, R_);
  if (d > p_pad_) {  // p's runs, for every step from p up to this long
    p_pad_ = std::max(2 * step_, d);
    raster_.runs(p, R_, p_pad_, p_runs_);
  }
  return raster_.fresh_beyond(p_runs_, q, R_);
}

std::optional<Vec2> Planner::material_tangent(const Vec2& p, const Vec2& d, double side) const {
  Vec2 cen;
  if (raster_.target_near(p, R_ + kSenseMm, nullptr, &cen) < min_work_) return std::nullopt;
  Vec2 u = cen - p;
  if (u.norm() < tol::coincident_mm) u = d;
  return rot(u.normalized(), side * kPi / 2);
}

std::optional<double> Planner::first_feasible(const Vec2& p, const Vec2& t0, double side) const {
  for (const double th : {kPi / 2, -kPi / 2, -2 * kPi / 3, -5 * kPi / 6, -kPi})
    if (cost(p, p + step_ * rot(t0, -side * th)) <= max_cells_) return th;
  return std::nullopt;
}

bool Planner::can_start(const Vec2& p, const Vec2& d) const {
  const double side = pass_climb_ ? 1.0 : -1.0;
  const std::optional<Vec2> t0 = material_tangent(p, d, side);
  if (!t0) return false;
  return first_feasible(p, *t0, side).has_value();
}

// One pass from p (already there, its disk cleared) heading about d. Returns the cells cut.
//
// The steering: the material is sensed as the centroid of the uncut target cells within
// R + kSenseMm of the tool (so the pass finds it again after a turn, unlike a one-step probe);
// the tangent t0 keeps it on the right (climb) or left (conventional). Each step goes in the
// direction turned as far toward the material as the step's newly cut area allows (≤ the
// target's: bisection over θ ∈ [−90°, 90°] from t0), so that in open material the pass rides
// the cut boundary at the target engagement (rings that spiral out), slides along walls (a move
// the walls refuse costs +inf) and loops round where the material is narrow. A pass ends when no
// target material is within sensing range, when every direction is refused, or after
// kIdleMm of path that cut nothing (that tail is dropped).
double Planner::cut_pass(Vec2 p, Vec2 d, bool first_wide) {
  RawChain& c = chains_.back();
  if (c.pts.empty() || (c.pts.back() - p).norm() > tol::join_mm) c.pts.push_back(p);
  const std::size_t base = c.pts.size();
  const double side = pass_climb_ ? 1.0 : -1.0;  // rot(t0, -side·θ), θ > 0: toward the material
  const std::size_t idle_steps = static_cast<std::size_t>(std::ceil((R_ + kSenseMm) / step_));
  double total = 0;
  bool blocked = false;
  std::size_t idle = 0, last_productive = base;
  const std::size_t max_steps = 4000000;
  auto at = [&](const Vec2& dir) { return Vec2(p + step_ * dir); };
  for (std::size_t n = 0; n < max_steps; ++n) {
    const std::optional<Vec2> tangent = material_tangent(p, d, side);
    if (!tangent) break;  // nothing near: done
    const Vec2 t0 = *tangent;
    auto dir = [&](double th) { return rot(t0, -side * th); };
    // Straight at the material when that step is light enough (or cuts nothing); otherwise the
    // direction turned furthest toward it within the target, by bisection from the first
    // feasible probe.
    std::optional<double> chosen = first_feasible(p, t0, side);
    if (chosen && *chosen < kPi / 2) {
      double lo = *chosen, hi = kPi / 2;
      for (int it = 0; it < 7; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (cost(p, at(dir(mid))) <= max_cells_)
          lo = mid;
        else
          hi = mid;
      }
      chosen = lo;
    }
    if (!chosen || (n > 0 && *chosen < -kBlockedDeg * kPi / 180)) {  // blocked (it could only back away)
      blocked = true;
      break;
    }
    Vec2 nd = dir(*chosen);
    if (n > 0 || !first_wide) {
      // Smoothness: a turn toward the material of at most kMaxTurnDeg per step (a turn away from
      // it is what keeps the cut at the target and is kept).
      double turn = std::atan2(d.x() * nd.y() - d.y() * nd.x(), d.dot(nd));  // signed, in [−π, π]
      if (std::abs(turn) > kPi - 1e-6) turn = -side * kPi;                   // a reversal: round toward the material
      const double lim = kMaxTurnDeg * kPi / 180;
      if (-side * turn > lim) {
        const Vec2 lim_dir = rot(d, -side * lim);
        if (cost(p, at(lim_dir)) <= max_cells_) nd = lim_dir;
      }
    }
    const Vec2 q = at(nd);
    const int got = raster_.mark(q, R_);
    d = nd;
    p = q;
    c.pts.push_back(q);
    total += got;
    ++stats_.steps;
    if (got > 0) {
      idle = 0;
      last_productive = c.pts.size();
    } else if (++idle >= idle_steps) {
      break;
    }
  }
  if (c.pts.size() > last_productive) blocked = false;  // it ended idle, not at a wall
  c.pts.resize(std::max(last_productive, base));        // drop the idle tail
  last_blocked_ = blocked;
  last_dir_ = d;
  ++stats_.passes;
  if (total < min_work_) ++stats_.idle_passes;
  return total;
}

}  // namespace millnet::pocket::adaptive
