// The adaptive planner's links through cut area (adaptive_internal.hpp): the lattice of positions a
// link may pass through, the straight moves it may make (no wall, at most the target's cut), the
// Dijkstra search for the nearest start, taut links, and backtracking where no link leaves.
#include "adaptive_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <queue>
#include <utility>
#include <vector>

namespace millnet::pocket::adaptive {

Vec2 Planner::lattice_point(std::size_t k) const {
  return lat_lo_ + kLatticeMm * Vec2(static_cast<double>(k % static_cast<std::size_t>(lnx_)),
                                     static_cast<double>(k / static_cast<std::size_t>(lnx_)));
}

std::size_t Planner::lattice_index(const Vec2& p) const {
  const int x = std::clamp(static_cast<int>(std::lround((p.x() - lat_lo_.x()) / kLatticeMm)), 0, lnx_ - 1);
  const int y = std::clamp(static_cast<int>(std::lround((p.y() - lat_lo_.y()) / kLatticeMm)), 0, lny_ - 1);
  return lin(x, y, lnx_);
}

bool Planner::lattice_allowed(std::size_t k) {
  if (lat_ok_[k] < 0) lat_ok_[k] = link_walls_.point_ok(lattice_point(k)) ? 1 : 0;
  return lat_ok_[k] == 1;
}

bool Planner::link_ok(const Vec2& a, const Vec2& b) const {
  if (!exact_.move_ok(a, b)) return false;
  const double L = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(L / step_)));
  const double allowed = max_cells_ * (L / n) / step_ + 0.5;
  if (raster_.capsule_clear(a, b, R_)) return true;  // through cut area: every count below is 0
  // The uncut cells of each sample's disk, from the last one's by the two crescents between them
  // (the same rounding as the full disk, so the same counts): O(R·step/h² + R/h) a sample.
  // The count at a itself is kept while the raster is unchanged: the links tried from one
  // position (the search's seeds, a taut pull) share it.
  if (!(a == fresh_at_) || raster_.version() != fresh_version_) {
    fresh_at_ = a;
    fresh_version_ = raster_.version();
    fresh_a_ = raster_.fresh(a, R_);
  }
  Vec2 prev = a;
  int fresh = fresh_a_;
  for (int i = 1; i <= n; ++i) {
    const Vec2 q = a + (b - a) * (static_cast<double>(i) / n);
    fresh += raster_.fresh_beyond(prev, q, R_) - raster_.fresh_beyond(q, prev, R_);
    if (fresh > allowed) return false;
    prev = q;
  }
  return true;
}

bool Planner::find_start(const Vec2& from, Vec2& start, Vec2& toward, std::vector<Vec2>& way, const Vec2* goal) {
  if (goal && link_ok(from, *goal)) {
    way = {from, *goal};
    start = toward = *goal;
    return true;
  }
  const std::size_t n = lat_ok_.size();
  std::vector<double> dist(n, kInf);
  std::vector<long> prev(n, -1);
  std::vector<std::uint8_t> state(n, 0);  // 0 unknown, 1 usable, 2 not
  auto usable = [&](std::size_t k) {
    if (state[k] == 0) {
      // Cutting only removes material: a position once found cleared stays cleared.
      if (!lat_safe_[k] && lattice_allowed(k) && safe(lattice_point(k))) lat_safe_[k] = 1;
      state[k] = lat_safe_[k] ? 1 : 2;
    }
    return state[k] == 1;
  };
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const std::size_t c0 = lattice_index(from);
  const int cx0 = static_cast<int>(c0 % static_cast<std::size_t>(lnx_)),
            cy0 = static_cast<int>(c0 / static_cast<std::size_t>(lnx_));
  // Seeds: the lattice positions round the tool a straight link reaches, in growing rings.
  const int max_ring = static_cast<int>(std::ceil((R_ + 3) / kLatticeMm));
  for (int r = 1; r <= max_ring && open.empty(); ++r)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
        const int x = cx0 + dx, y = cy0 + dy;
        if (x < 0 || y < 0 || x >= lnx_ || y >= lny_) continue;
        const std::size_t k = lin(x, y, lnx_);
        if (!usable(k) || !link_ok(from, lattice_point(k))) continue;
        const double d = (lattice_point(k) - from).norm();
        if (d < dist[k]) {
          dist[k] = d;
          open.push({d, k});
        }
      }
  const double reach = R_ + 1.5 * kLatticeMm;
  while (!open.empty()) {  // O(lattice · log lattice) at worst
    const auto [d, k] = open.top();
    open.pop();
    if (d > dist[k]) continue;
    Vec2 near;
    const bool found = goal ? (lattice_point(k) - *goal).norm() <= 2.5 * kLatticeMm && link_ok(lattice_point(k), *goal)
                            : !dead_[k] && raster_.target_near(lattice_point(k), reach, &near) >= min_work_;
    if (found) {
      start = goal ? *goal : lattice_point(k);
      toward = goal ? *goal : near;
      std::vector<Vec2> rev;
      if (goal) rev.push_back(*goal);
      for (long c = static_cast<long>(k); c >= 0; c = prev[static_cast<std::size_t>(c)])
        rev.push_back(lattice_point(static_cast<std::size_t>(c)));
      rev.push_back(from);
      way.assign(rev.rbegin(), rev.rend());
      return true;
    }
    const int x0 = static_cast<int>(k % static_cast<std::size_t>(lnx_)),
              y0 = static_cast<int>(k / static_cast<std::size_t>(lnx_));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = x0 + dx, y = y0 + dy;
        if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= lnx_ || y >= lny_) continue;
        const std::size_t q = lin(x, y, lnx_);
        if (!usable(q)) continue;
        const double nd = d + kLatticeMm * ((dx != 0 && dy != 0) ? std::numbers::sqrt2 : 1.0);
        if (nd < dist[q]) {
          dist[q] = nd;
          prev[q] = static_cast<long>(k);
          open.push({nd, q});
        }
      }
  }
  return false;
}

// Cuts along `way` (from the tool's position) pulled taut: each straight move as long as
// link_ok allows. False (nothing appended) when a move between two lattice neighbours fails.
bool Planner::link_along(const std::vector<Vec2>& way) {
  std::vector<Vec2> taut{way.front()};
  std::size_t k = 0;
  while (k + 1 < way.size()) {
    std::size_t far = k + 1;
    if (!link_ok(taut.back(), way[far])) return false;
    while (far + 1 < way.size() && link_ok(taut.back(), way[far + 1])) ++far;
    taut.push_back(way[far]);
    k = far;
  }
  RawChain& c = chains_.back();
  for (std::size_t i = 1; i < taut.size(); ++i) {
    mark_move(taut[i - 1], taut[i]);
    c.pts.push_back(taut[i]);
    stats_.link_length_mm += (taut[i] - taut[i - 1]).norm();
  }
  ++stats_.links;
  return true;
}

void Planner::mark_move(const Vec2& a, const Vec2& b) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_)));
  for (int t = 1; t <= n; ++t) raster_.mark(a + (b - a) * (static_cast<double>(t) / n), R_);
}

// Where no link leaves the tool's position: back along the chain's own path (cut area, the tool
// down) to a point every kBacktrackMm from which a link reaches `goal`, then that link. False
// (nothing appended) when none within kBacktrackTries does. O(tries · lattice search).
bool Planner::backtrack_to(const Vec2& goal) {
  RawChain& c = chains_.back();
  if (c.pts.size() < 2) return false;
  double run = 0;
  int tries = 0;
  for (std::size_t k = c.pts.size() - 1; k-- > 0 && tries < kBacktrackTries;) {
    run += (c.pts[k + 1] - c.pts[k]).norm();
    if (run < kBacktrackMm) continue;
    run = 0;
    ++tries;
    Vec2 start, toward;
    std::vector<Vec2> way;
    if (!find_start(c.pts[k], start, toward, way, &goal)) continue;
    const std::vector<Vec2> back(c.pts.rbegin() + 1, c.pts.rend() - static_cast<std::ptrdiff_t>(k));
    double len = 0;
    for (const Vec2& q : back) {  // retrace: already cut
      len += (q - c.pts.back()).norm();
      c.pts.push_back(q);
    }
    if (link_along(way)) {
      stats_.backtrack_length_mm += len;
      return true;
    }
    c.pts.resize(c.pts.size() - back.size());
    return false;
  }
  return false;
}

}  // namespace millnet::pocket::adaptive
