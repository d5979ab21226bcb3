#pragma once
// The one shoelace area of millnet: a closed polyline's signed area (first point not repeated).
// Header-only over any point type with x() and y() (Eigen::Vector2d in ingest and pocket). Loops
// with arcs have their own exact area, pocket::signed_area(Loop), which adds circular segments.
#include <cstddef>

namespace millnet {

/// Signed area, mm², > 0 counter-clockwise. O(points).
template <class Points>
[[nodiscard]] double shoelace_area(const Points& pts) {
  double a = 0;
  const std::size_t n = pts.size();
  for (std::size_t k = 0; k < n; ++k) {
    const auto& p = pts[k];
    const auto& q = pts[(k + 1) % n];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * a;
}

}  // namespace millnet
