#pragma once
// A pocket region as the independent G-code replay reads it (testing/gcode_replay.hpp): the same
// loops of [x, y, bulge], so that the replay's own geometry checks the planners' output.
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpath.hpp"
#include "testing/gcode_replay.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace millnet::testing {

inline ReplayPocket to_replay(const pocket::Region& r) {
  ReplayPocket p;
  for (const pocket::Vertex& v : r.boundary) p.boundary.push_back({v.x, v.y, v.bulge});
  for (const pocket::Loop& l : r.islands) {
    p.islands.emplace_back();
    for (const pocket::Vertex& v : l) p.islands.back().push_back({v.x, v.y, v.bulge});
  }
  return p;
}

/// Coverage probe, independent of the planners: every point of a 0.5 mm grid where a tool of radius
/// R fits with 0.2 mm to spare (so it is certainly reachable) must lie within R + 0.01 mm of a
/// replayed cutting move below Z = 0, sampled every 0.25 mm (arcs on their circle). A missing ring
/// or pass leaves points up to a stepover farther. Counts into `probed` and returns the unswept.
inline std::size_t unswept_points(const ReplayResult& rep, const pocket::Region& region, double R,
                                  std::size_t& probed) {
  using pocket::Vec2;
  const double h = 0.5;
  const std::vector<Vec2> b = pocket::flatten(region.boundary, 0.01);
  Vec2 lo = b.front(), hi = b.front();
  for (const Vec2& p : b) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const long nx = std::lround((hi.x() - lo.x()) / h) + 1, ny = std::lround((hi.y() - lo.y()) / h) + 1;
  std::vector<char> cut_cell(static_cast<std::size_t>(nx * ny), 0);
  // Within the tool's radius up to the replay's 0.01 mm: where stepover = R the middle of a ring is
  // exactly R from it, a cusp of no area the tool's edge touches.
  const double r_stamp = R + 0.01;
  const long rc = static_cast<long>(std::floor(r_stamp / h));
  auto stamp = [&](double x, double y) {
    const long cx = std::lround((x - lo.x()) / h), cy = std::lround((y - lo.y()) / h);
    for (long dy = -rc - 1; dy <= rc + 1; ++dy)
      for (long dx = -rc - 1; dx <= rc + 1; ++dx) {
        const long gx = cx + dx, gy = cy + dy;
        if (gx < 0 || gy < 0 || gx >= nx || gy >= ny) continue;
        if (std::hypot(lo.x() + static_cast<double>(gx) * h - x, lo.y() + static_cast<double>(gy) * h - y) <= r_stamp)
          cut_cell[static_cast<std::size_t>(gy * nx + gx)] = 1;
      }
  };
  for (const auto& mv : rep.moves) {
    if (mv.g == 0 || mv.to[2] > -1e-9 || mv.from[2] > -1e-9) continue;
    const double len = std::hypot(mv.to[0] - mv.from[0], mv.to[1] - mv.from[1]);
    if (mv.g == 1) {
      const int n = std::max(1, static_cast<int>(std::ceil(len / 0.25)));
      for (int k = 0; k <= n; ++k)
        stamp(mv.from[0] + (mv.to[0] - mv.from[0]) * k / n, mv.from[1] + (mv.to[1] - mv.from[1]) * k / n);
    } else {  // arc: by angle about its centre
      const double cx = mv.center[0], cy = mv.center[1];
      const double r = std::hypot(mv.from[0] - cx, mv.from[1] - cy);
      const double a0 = std::atan2(mv.from[1] - cy, mv.from[0] - cx), a1 = std::atan2(mv.to[1] - cy, mv.to[0] - cx);
      double sweep = a1 - a0;
      if (mv.g == 3 && sweep <= 0) sweep += 2 * M_PI;
      if (mv.g == 2 && sweep >= 0) sweep -= 2 * M_PI;
      const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) * r / 0.25)));
      for (int k = 0; k <= n; ++k) stamp(cx + r * std::cos(a0 + sweep * k / n), cy + r * std::sin(a0 + sweep * k / n));
    }
  }
  const pocket::Clearance walls(region, 0.0);
  std::size_t unswept = 0;
  for (long gy = 0; gy < ny; ++gy)
    for (long gx = 0; gx < nx; ++gx) {
      const Vec2 p(lo.x() + static_cast<double>(gx) * h, lo.y() + static_cast<double>(gy) * h);
      if (!pocket::inside(region, p) || walls.wall_distance(p) < R + 0.2) continue;
      ++probed;
      if (!cut_cell[static_cast<std::size_t>(gy * nx + gx)]) ++unswept;
    }
  return unswept;
}

/// Issue 11's bench setting (configs/bench/roughing-issue11.json): Ø10, stepover 5, depth 5 in one
/// level, every cutting move at 1500 mm/min, plunges and entries at 300 mm/min, no feed map.
inline pocket::CutParams issue11_bench_cut() {
  pocket::CutParams cut;
  cut.tool.diameter = 10;
  cut.stepover = 5;
  cut.depth = 5;
  cut.step_down = 5;
  cut.feed_slot = cut.feed_half = cut.feed_min = cut.feed_max = 1500;
  cut.feed_plunge = 300;
  cut.feed_adjust = false;
  return cut;
}

}  // namespace millnet::testing
