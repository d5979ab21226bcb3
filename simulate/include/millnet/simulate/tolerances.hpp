#pragma once
// Named tolerances of the simulator: the guards of its closed forms against degenerate geometry
// (floating-point noise, far below a z-map cell). Lengths in mm, angles in radians; the options'
// defaults (SweepOptions, MetricsOptions in zmap.hpp) are the user-facing tolerances.
namespace millnet::simulate::tol {

/// A line whose XY length is at most this has no XY direction: it is swept as a vertical move
/// (the lower end's disk), and a joint never hands its cutter to it.
inline constexpr double xy_length_mm = 1e-9;

/// A line longer than this in XY gives the cells it cuts an across-feed direction (roughness
/// profiles); a shorter one is a plunge.
inline constexpr double across_length_mm = 1e-12;

/// An arc whose start is this close to its centre has no radius (an input error).
inline constexpr double min_arc_radius_mm = 1e-9;

/// An arc whose start and end are less than this apart in angle (rad) is a full circle.
inline constexpr double full_circle_rad = 1e-12;

/// An arc whose Z changes by at most this is planar (swept exactly); otherwise a helix (chords).
inline constexpr double planar_arc_dz_mm = 1e-12;

/// A point this close to an arc's centre has no direction from it: its distance to the arc is the
/// radius, and the cell takes no radial across-feed direction.
inline constexpr double at_centre_mm = 1e-12;

/// The XY shadow of a planar arc (the ring |ρ − ρ0| ≤ R) is widened by this on both sides, so
/// that rounding never drops a cell the exact envelope reaches.
inline constexpr double arc_shadow_margin_mm = 1e-9;

/// A cell centre within this fraction of a cell outside a span still counts as inside (the span
/// ends are computed, the envelope is exact: a cell too many costs nothing, a cell too few would).
inline constexpr double cell_range_slack_cells = 1e-9;

/// The ball kernel skips the half end disk a neighbouring primitive sweeps (clip_to_live_band in
/// sweep_kernels.cpp); it keeps this much beyond the exact line s = 0 (or s = L).
inline constexpr double live_band_margin_mm = 1e-6;

/// The ball kernel leaves out the cells at a row's ends that stand this far or more below the
/// lowest the swept ball can reach on the row (its lowest tip raised by its profile at the row's
/// distance from the move): the envelope there is surely above them, so the kernel would lower none
/// of them, whatever its rounding (≤ 1e-13 mm on a 100 mm part).
inline constexpr double envelope_skip_margin_mm = 1e-9;

/// The Ra profile runs along the grid axis closest to the across-feed direction, stretched by
/// 1 / cos of the angle between them; the cos is floored at this (it is ≥ 1/√2 for a unit
/// direction: the floor only guards the division).
inline constexpr double min_profile_cos = 1e-6;

/// The exact gouge check (exact_gouge.hpp) samples a flat or bull cutter's core disk on rings at
/// most this far apart, and each ring at most this far between samples (mm).
inline constexpr double exact_disk_step_mm = 0.05;

/// ... with at most this many rings (a wide disk is sampled more coarsely, the step stated by it).
inline constexpr int exact_disk_max_rings = 24;

/// The outermost ring of that disk lies this far inside the rim, so that a cutter whose rim just
/// meets a vertical wall's top edge is not read as standing on the wall (mm).
inline constexpr double exact_rim_inset_mm = 1e-4;

/// The bins of the exact check's triangle grid are at least this big, and at most this many.
inline constexpr double exact_min_bin_mm = 0.25;
inline constexpr double exact_max_bins = 4e6;

/// A triangle whose XY projection has at most this area (mm²) is vertical: it has no inside.
inline constexpr double exact_vertical_area_mm2 = 1e-12;

}  // namespace millnet::simulate::tol
