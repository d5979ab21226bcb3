// Tool points (Shin & Suh §3): grid points at the stepover spacing whose tool disk fits.
#include "millnet/pocket/toolpoints.hpp"

#include "geometry_internal.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::pocket {

Vec2 GridFrame::at(int i, int j) const {
  const double a = angle_deg * std::numbers::pi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  const double u = j * spacing, v = i * spacing;
  return origin + Vec2(c * u - s * v, s * u + c * v);
}

GridRange grid_range(const Region& region, const GridFrame& frame) {
  if (!(frame.spacing > 0) || !std::isfinite(frame.spacing))
    throw Error("--stepover / /pocket/stepover: the tool-point grid spacing must be > 0, got " +
                format_double(frame.spacing));
  GridRange r;
  if (region.boundary.empty()) return r;
  // Index range: the boundary's box expressed in grid coordinates (inverse rotation).
  const double a = frame.angle_deg * std::numbers::pi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
  for (const Segment& seg : segments(region.boundary)) {
    const detail::BBox b = detail::bbox(seg);
    for (const Vec2& q : {b.lo, b.hi, Vec2(b.lo.x(), b.hi.y()), Vec2(b.hi.x(), b.lo.y())}) {
      const Vec2 d = q - frame.origin;
      const double u = c * d.x() + s * d.y(), v = -s * d.x() + c * d.y();
      umin = std::min(umin, u);
      umax = std::max(umax, u);
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
    }
  }
  r.j0 = std::floor(umin / frame.spacing);
  r.j1 = std::ceil(umax / frame.spacing);
  r.i0 = std::floor(vmin / frame.spacing);
  r.i1 = std::ceil(vmax / frame.spacing);
  return r;
}

ToolPoints make_tool_points(const Region& region, const GridFrame& frame, double clearance_mm) {
  const GridRange r = grid_range(region, frame);
  ToolPoints tp;
  tp.frame = frame;
  if (region.boundary.empty()) return tp;
  // The caller's budget (pocket::check_work) bounds rows · cols; this is the last line against an
  // int overflow of the indices for a caller that skipped it.
  // Names the flag and the key, not this function (issue 15; tests/corpus/cli/pocket_grid_too_fine.args).
  if (const double span = std::max(r.j1 - r.j0, r.i1 - r.i0); !(span <= 2e5)) {
    auto whole = [](double x) {  // 1000000 rather than 1e+06
      return x < 1e15 ? std::to_string(static_cast<long long>(std::ceil(x))) : format_double(x);
    };
    throw Error("--stepover / /pocket/stepover: stepover " + format_double(frame.spacing) + " mm over a pocket " +
                whole(span * frame.spacing) + " mm across makes " + whole(span) +
                " tool points per side; at most 200000 (raise the stepover)");
  }
  if (!(std::max({std::abs(r.i0), std::abs(r.i1), std::abs(r.j0), std::abs(r.j1)}) < 2e9))
    throw Error("make_tool_points: the grid origin lies too far from the pocket for int grid indices");
  const Clearance clear(region, clearance_mm);
  const int j0 = static_cast<int>(r.j0), j1 = static_cast<int>(r.j1);
  const int i0 = static_cast<int>(r.i0), i1 = static_cast<int>(r.i1);
  // O(rows · cols) point_ok queries, each looking at the walls in nearby buckets only.
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const Vec2 p = frame.at(i, j);
      if (clear.point_ok(p)) {
        tp.pts.push_back(p);
        tp.ij.push_back({i, j});
      }
    }
  return tp;
}

}  // namespace millnet::pocket
