#pragma once
// Arc fitting of tool paths: runs of short straight segments that follow one circle (the chorded
// round joins and wall arcs Clipper's offsets are made of) become one arc each, written as G2/G3.
// What a commercial CAM post does: the program is a few hundred arcs instead of thousands of
// 0.3 mm lines, the controller gets the exact circle, and nothing moves by more than the
// tolerance.
//
//   contract  every point of the fitted path lies within tol_mm of the input polyline (vertices
//             within tol of the circle, and each replaced chord's sagitta within tol), so the swept
//             area changes by at most tol_mm across its edges;
//             with `walls`, an arc is kept only where it keeps the walls' clearance
//             (Clearance::wall_distance ≥ clearance − tol::clear_mm at samples ≤ tol::arc_fit_sample_mm
//             apart; tolerances.hpp bounds what can happen between two samples);
//             each arc turns one way by at most 180° (|bulge| ≤ 1) and replaces ≥ kMinArcSegments
//             segments; existing arcs and the vertices between runs are kept as they are.
//   cost      O(n log n) fits for n vertices (each run grows by doubling, then bisection), each fit
//             O(run length), plus the clearance samples of the arcs kept.
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpath.hpp"

#include <vector>

namespace millnet::pocket {

/// Fewest straight segments an arc replaces (three: two segments always lie on some circle).
inline constexpr std::size_t kMinArcSegments = 3;

/// The open polyline `pts` (bulges of arcs kept) with its circular runs replaced by arcs. The first
/// and last vertices stay where they are.
[[nodiscard]] std::vector<Vertex> fit_arcs(const std::vector<Vertex>& pts, double tol_mm, const Clearance* walls);

/// fit_arcs on every chain of a path; a chain's feeds (if assigned) are dropped: fitting comes
/// before the feed map. Returns the number of arcs made.
std::size_t fit_arcs(Path2D& path, double tol_mm, const Clearance* walls);

}  // namespace millnet::pocket
