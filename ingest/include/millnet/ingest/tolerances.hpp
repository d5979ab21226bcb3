#pragma once
// Named tolerances of the ingest module. Lengths in mm, areas in mm², angles in degrees; "raster
// units" are fractions of one raster step (dimensionless).
namespace millnet::ingest::tol {

/// A triangle whose 3D area is at or below this is counted as degenerate (reported, not fatal).
inline constexpr double degenerate_area_mm2 = 1e-12;

/// Raster points within this distance (raster units) outside a triangle's edge still count as
/// inside it ("inclusive with epsilon"): a raster point exactly on a shared edge or vertex is hit
/// by at least one of the triangles sharing it, whatever the rounding of (x − x0)/step.
inline constexpr double raster_edge_eps = 1e-7;

/// A triangle whose XY-projected doubled area is ≤ this × (longest XY edge)² (raster units) is
/// treated as vertical: its three edges are rasterized as segments instead of its interior.
inline constexpr double vertical_triangle_rel = 1e-9;

/// Up::Auto: a face counts as part of a flat base/cap when its normal is within this angle of
/// the axis and every vertex is within auto_up_plane_mm of the extreme plane.
inline constexpr double auto_up_flat_deg = 1.0;
inline constexpr double auto_up_plane_mm = 1e-3;

/// Point clouds: coordinates closer than this (relative to the cloud's XY extent) are the same
/// raster line when detecting a regular raster.
inline constexpr double cloud_raster_rel = 1e-6;

/// material_contours(): simplification tolerance of cv::approxPolyDP, in image pixels, and the
/// finest image pixel as a fraction of the smaller raster step.
inline constexpr double contour_simplify_px = 0.5;
inline constexpr double contour_pixel_per_step = 0.125;
/// material_contours(): largest image side in pixels (the pixel grows for huge rasters).
inline constexpr int contour_max_image_px = 4096;

}  // namespace millnet::ingest::tol
