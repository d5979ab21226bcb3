#pragma once
// Offsets of a region through Clipper (libpolyclipping, integer coordinates at
// tol::clipper_resolution_mm, arcs flattened within tol::arc_chord_mm): the area the tool centre
// may reach is the region shrunk by tool radius + stock to leave (islands grown).
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <vector>

namespace millnet::pocket {

/// Region offset inward by delta_mm (> 0 shrinks the boundary and grows islands, round joins).
/// Each connected component of the result is one PolyArea; empty when nothing is left.
[[nodiscard]] std::vector<PolyArea> offset_inward(const Region& region, double delta_mm,
                                                  double chord_tol_mm = tol::arc_chord_mm);

[[nodiscard]] double area(const PolyArea& a);                   ///< outer minus holes, mm²
[[nodiscard]] double area(const std::vector<PolyArea>& areas);  ///< Σ area, mm²

/// Offset of polygon areas by delta_mm (> 0 grows outers and shrinks holes, < 0 the reverse),
/// round joins with chord error ≤ chord_tol_mm. Used to grow the tool-centre area back by the
/// tool radius (the area the tool can reach).
[[nodiscard]] std::vector<PolyArea> offset_areas(const std::vector<PolyArea>& areas, double delta_mm,
                                                 double chord_tol_mm = tol::arc_chord_mm);

/// The area with each loop simplified (Douglas–Peucker, closed): every dropped vertex lies within
/// eps_mm of the chord that replaces it, so each loop moves by at most eps_mm. A loop keeps at least
/// 3 vertices. O(n log n) typical per loop.
[[nodiscard]] PolyArea simplified(const PolyArea& a, double eps_mm);

/// Area swept by a disk of radius_mm moving along each open polyline (union of capsules; a
/// single-point polyline is a disk). Round ends and joins, chord error ≤ chord_tol_mm.
[[nodiscard]] std::vector<PolyArea> swept_area(const std::vector<std::vector<Vec2>>& polylines, double radius_mm,
                                               double chord_tol_mm = tol::arc_chord_mm);

/// The wall loops: the loops of the region offset inward by clearance_mm + tol::contour_margin_mm
/// (where the tool centre runs along every wall: the contour pass, the SOM's wall rings, the
/// adaptive planner's wall pass), per component its outer loop (counter-clockwise) then its holes
/// (clockwise). Loops of fewer than 3 vertices are skipped.
[[nodiscard]] std::vector<std::vector<Vec2>> wall_loops(const Region& region, double clearance_mm);

/// a minus b (Clipper difference), as areas.
[[nodiscard]] std::vector<PolyArea> difference(const std::vector<PolyArea>& a, const std::vector<PolyArea>& b);

}  // namespace millnet::pocket
