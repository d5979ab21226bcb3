#pragma once
// Offsets of a region through Clipper (libpolyclipping, integer coordinates at
// tol::clipper_resolution_mm, arcs flattened within tol::arc_chord_mm): the area the tool centre
// may reach is the region shrunk by tool radius + stock to leave (islands grown).
#include "millnet/pocket/geometry.hpp"

#include <vector>

namespace millnet::pocket {

/// A polygon with holes as polylines (outer CCW, holes CW, first point not repeated).
struct PolyArea {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
};

/// Region offset inward by delta_mm (> 0 shrinks the boundary and grows islands, round joins).
/// Each connected component of the result is one PolyArea; empty when nothing is left.
[[nodiscard]] std::vector<PolyArea> offset_inward(const Region& region, double delta_mm,
                                                  double chord_tol_mm = 0.001);

[[nodiscard]] double area(const PolyArea& a);  ///< outer minus holes, mm²

}  // namespace millnet::pocket
