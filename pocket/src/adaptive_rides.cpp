// The adaptive planner's rides (adaptive_internal.hpp): from the end of a blocked pass back along
// the front it was cutting, the tool down and cutting nothing, pulled taut into a few chords.
#include "millnet/pocket/tolerances.hpp"

#include "adaptive_internal.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace millnet::pocket::adaptive {

// From p (the end of a pass), rides back along the front with the material on the other side
// than a cutting pass keeps it, cutting nothing (every step's newly cut cells = 0), as far as
// the front goes: until the material is out of sensing range, a wall or the material turns the
// ride away (a step more than kRideAwayDeg off the front's tangent), or kRideMaxMm. `way` gets
// the ride (p first). False when it is shorter than kRideMinMm (nothing gained).
bool Planner::ride_back(const Vec2& p0, std::vector<Vec2>& way) {
  way.assign(1, p0);
  const double side = climb_ ? 1.0 : -1.0;
  Vec2 p = p0;
  double len = 0;
  Vec2 hd(0, 0);
  const double rs = kRideStepSteps * step_;
  while (len < kRideMaxMm) {
    Vec2 cen;
    if (raster_.target_near(p, R_ + kSenseMm, nullptr, &cen) < min_work_) break;
    Vec2 u = cen - p;
    if (u.norm() < tol::coincident_mm) break;
    u.normalize();
    const Vec2 t0 = rot(u, -side * kPi / 2);  // the material on the other side
    auto dir = [&](double th) { return rot(t0, side * th); };
    auto free = [&](double th) { return cost(p, p + rs * dir(th)) <= 0; };
    double lo = -kRideAwayDeg * kPi / 180;
    if (!free(lo)) break;
    double hi = kPi / 2;
    if (free(hi))
      lo = hi;
    else
      for (int it = 0; it < 7; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (free(mid))
          lo = mid;
        else
          hi = mid;
      }
    const Vec2 nd = dir(lo);
    if (hd.norm() > 0 && hd.dot(nd) < std::cos(kPi / 2)) break;  // it would turn back on itself
    p += rs * nd;
    hd = nd;
    way.push_back(p);
    len += rs;
  }
  last_heading_ = hd.norm() > 0 ? Vec2(-hd) : Vec2(1, 0);
  return len >= kRideMinMm;
}

// The straight move a→b keeps the walls' margin and cuts nothing: no uncut cell within R of a
// position every 4 steps along it (the test every step of a ride passes; between two samples
// 4·step = D/10 apart a cell within R of the move but of neither sample lies at most
// (D/10)²/(8R) = D/400, a tenth of a D/40 cell, a fifth of a D/80 one, beyond R of both).
bool Planner::air_ok(const Vec2& a, const Vec2& b) const {
  if (!walls_.move_ok(a, b)) return false;
  if (raster_.capsule_clear(a, b, R_)) return true;  // no uncut cell within R of the move at all
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (4 * step_))));
  for (int i = 1; i <= n; ++i)
    if (!raster_.clear_within(a + (b - a) * (static_cast<double>(i) / n), R_)) return false;
  return true;
}

// A ride (steps of step_ along the front, each cutting nothing) pulled taut: from each vertex
// the farthest later one that air_ok reaches (galloping, then bisection: O(log n) tests a
// vertex). The ride's hundreds of 0.25 mm steps, each turning a few degrees, held the machine
// to ≈ 36 mm/s by the junction-deviation rule where its air feed is 80 mm/s; its chords are
// also shorter.
std::vector<Vec2> Planner::taut_ride(const std::vector<Vec2>& way) const {
  std::vector<Vec2> out{way.front()};
  std::size_t k = 0;
  const std::size_t last = way.size() - 1;
  while (k < last) {
    std::size_t good = k + 1, stride = 1;  // one step of the ride: air_ok by construction
    while (good < last) {
      const std::size_t next = std::min(last, good + stride);
      if (!air_ok(way[k], way[next])) {
        std::size_t lo = good, hi = next;  // lo passes, hi fails
        while (hi - lo > 1) {
          const std::size_t mid = lo + (hi - lo) / 2;
          (air_ok(way[k], way[mid]) ? lo : hi) = mid;
        }
        good = lo;
        break;
      }
      good = next;
      stride *= 2;
    }
    out.push_back(way[good]);
    k = good;
  }
  return out;
}

void Planner::append_link(const std::vector<Vec2>& way) {
  RawChain& c = chains_.back();
  for (std::size_t i = 1; i < way.size(); ++i) {
    mark_move(way[i - 1], way[i]);
    c.pts.push_back(way[i]);
    stats_.ride_length_mm += (way[i] - way[i - 1]).norm();
  }
  ++stats_.links;
}

}  // namespace millnet::pocket::adaptive
