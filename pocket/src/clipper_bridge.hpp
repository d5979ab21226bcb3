#pragma once
// Conversions between millnet's mm polylines and Clipper 6's integer paths (private to pocket/).
// Coordinates are scaled by `scale` (integer units per mm) and rounded to the nearest unit.
#include "millnet/core/shoelace.hpp"

#include "offset.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace millnet::pocket::clipper_bridge {

[[nodiscard]] inline ClipperLib::IntPoint to_int(const Vec2& v, double scale) {
  return {static_cast<ClipperLib::cInt>(std::llround(v.x() * scale)),
          static_cast<ClipperLib::cInt>(std::llround(v.y() * scale))};
}

[[nodiscard]] inline ClipperLib::Path to_path(const std::vector<Vec2>& pts, double scale) {
  ClipperLib::Path p;
  p.reserve(pts.size());
  for (const Vec2& v : pts) p.push_back(to_int(v, scale));
  return p;
}

[[nodiscard]] inline std::vector<Vec2> from_path(const ClipperLib::Path& p, double scale) {
  std::vector<Vec2> out;
  out.reserve(p.size());
  for (const auto& q : p) out.emplace_back(static_cast<double>(q.X) / scale, static_cast<double>(q.Y) / scale);
  return out;
}

/// Outer nodes of a PolyTree with their holes (outer CCW, holes CW); outers nested in holes start
/// new components. O(nodes).
inline void collect(const ClipperLib::PolyNode& node, std::vector<PolyArea>& out, double scale) {
  for (const ClipperLib::PolyNode* child : node.Childs) {
    if (child->IsHole()) continue;
    PolyArea a;
    a.outer = from_path(child->Contour, scale);
    if (shoelace_area(a.outer) < 0) std::reverse(a.outer.begin(), a.outer.end());
    for (const ClipperLib::PolyNode* hole : child->Childs) {
      auto h = from_path(hole->Contour, scale);
      if (shoelace_area(h) > 0) std::reverse(h.begin(), h.end());
      a.holes.push_back(std::move(h));
      collect(*hole, out, scale);
    }
    out.push_back(std::move(a));
  }
}

}  // namespace millnet::pocket::clipper_bridge
