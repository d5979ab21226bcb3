#pragma once
// Named tolerances of the pocket module (all in mm unless the name says otherwise).
namespace millnet::pocket::tol {
inline constexpr double on_curve_mm = 1e-9;            ///< a point this close to a wall is on it
inline constexpr double clear_mm = 1e-6;               ///< allowed clearance deficit in gouge checks (numeric noise)
inline constexpr double gouge_check_mm = 0.01;         ///< the tests' independent G-code replay tolerance
inline constexpr double join_mm = 1e-6;                ///< vertices closer than this are the same point
inline constexpr double chain_join_mm = 1e-3;          ///< DXF loose entities whose ends are this close are chained
inline constexpr double arc_chord_mm = 0.001;          ///< chord error when arcs are flattened (Clipper, plots)
inline constexpr double clipper_resolution_mm = 1e-4;  ///< integer grid of Clipper coordinates
/// The contour pass flattens arcs (the region's and Clipper's round joins) within this chord error.
inline constexpr double contour_chord_mm = 0.0002;
/// Extra clearance of the contour pass: a chord of a convex wall arc lies up to contour_chord_mm
/// inside the true wall, and so does a chord of the offset's round join: twice that, plus the
/// rounding of Clipper's integer grid at both ends. Keeps the contour gouge-free while the uncut
/// sliver it leaves is ≈ 0.0006 mm × wall length.
inline constexpr double contour_margin_mm = 2 * contour_chord_mm + 2 * clipper_resolution_mm;
///< (covers Clipper's chord and rounding errors)
inline constexpr double uncut_chord_mm = 0.0002;  ///< chord error of the uncut-area booleans
/// Arc fitting (arc_fit.hpp): how far a fitted arc may move from the chorded path it replaces. The
/// offsets' round joins are chorded at arc_chord_mm and their rings simplified within it, twice
/// over for the inner rings (offset of an offset): their vertices lie within 2·arc_chord_mm of
/// the true circle.
inline constexpr double arc_fit_mm = 2 * arc_chord_mm;
/// Spacing of the clearance samples along a fitted arc. Between two samples the arc comes at most
/// its sagitta over this spacing closer to a wall it runs along (0.05² / 8r: 0.06 µm at r = 5 mm),
/// far below the tests' 0.01 mm replay tolerance.
inline constexpr double arc_fit_sample_mm = 0.05;
/// The adaptive planner's step points are simplified within this (Douglas–Peucker): the path
/// moves ≤ 0.005 mm, a sliver of engagement far below the feed map's cell, while a 5 mm trochoid
/// needs a vertex every ≈ 0.45 mm instead of every planning step (0.25 mm).
inline constexpr double adaptive_simplify_mm = 0.005;
/// Computed positions closer than this are one (floating-point noise, far below join_mm): no
/// direction between them, no move from one to the other.
inline constexpr double coincident_mm = 1e-9;
/// A path (or a cost in mm of path) shorter than another by less than this is no shorter: searches
/// do not swap candidates on rounding noise.
inline constexpr double improvement_mm = 1e-9;
/// Directions closer than this, degrees, are one (the zigzag's candidate directions).
inline constexpr double same_angle_deg = 1e-6;
}  // namespace millnet::pocket::tol
