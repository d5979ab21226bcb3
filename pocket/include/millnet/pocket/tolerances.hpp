#pragma once
// Named tolerances of the pocket module (all in mm unless the name says otherwise).
namespace millnet::pocket::tol {
inline constexpr double on_curve_mm = 1e-9;      ///< a point this close to a wall is on it
inline constexpr double clear_mm = 1e-6;         ///< allowed clearance deficit in gouge checks (numeric noise)
inline constexpr double gouge_check_mm = 0.01;   ///< the tests' independent G-code replay tolerance
inline constexpr double join_mm = 1e-6;          ///< vertices closer than this are the same point
inline constexpr double chain_join_mm = 1e-3;    ///< DXF loose entities whose ends are this close are chained
inline constexpr double arc_chord_mm = 0.001;    ///< chord error when arcs are flattened (Clipper, plots)
inline constexpr double clipper_resolution_mm = 1e-4;  ///< integer grid of Clipper coordinates
inline constexpr double contour_margin_mm = 0.005;    ///< the contour pass keeps this much extra off the walls
                                                       ///< (covers Clipper's chord and rounding errors)
inline constexpr double uncut_chord_mm = 0.0002;       ///< chord error of the uncut-area booleans
}  // namespace millnet::pocket::tol
