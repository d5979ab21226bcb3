#pragma once
// Z-level regions of a height field: the outlines of the material at or above a height, as closed
// polygons in mm (for Z-level roughing and pocketing). OpenCV stays private to the .cpp.
#include "millnet/ingest/heightfield.hpp"

#include <Eigen/Core>

#include <vector>

namespace millnet::ingest {

/// One closed loop in mm (the last point is not repeated). Outer loops are counter-clockwise,
/// holes clockwise (mm frame, x right, y up). `parent` is the index of the enclosing outer loop in
/// the returned vector for holes, −1 for outer loops.
struct ContourLoop {
  std::vector<Eigen::Vector2d> pts;
  bool hole = false;
  int parent = -1;
};

/// Outlines of the raster points with z ≥ level_z, grown outward (erring on the side of the
/// material, as a roughing pass must). Guarantee: every raster point at or above the level lies
/// inside an outer loop (and outside its holes) at a distance of at least
///   R = grow_mm + ½·hypot(step_x, step_y)
/// from the loop, so material hidden between raster points is covered too. The loops lie at most
/// R + contour_overshoot_mm(field) from the nearest such raster point (simplification included).
/// Points not hit by the mesh carry z_min, so at levels ≤ z_min the whole rectangle is material.
/// Cost: O(image pixels) with the image pixel = contour_pixel_per_step·min(step) (capped at
/// contour_max_image_px per side), plus O(contour length).
/// Throws millnet::Error for an empty field, a non-finite level, or grow_mm < 0.
[[nodiscard]] std::vector<ContourLoop> material_contours(const HeightField& field, double level_z, double grow_mm);

/// The largest outward overshoot (mm) beyond R that material_contours() may add for `field`:
/// pixel rounding plus the approxPolyDP tolerance.
[[nodiscard]] double contour_overshoot_mm(const HeightField& field, double grow_mm);

/// Signed area (mm²) of a closed loop: > 0 counter-clockwise (millnet::shoelace_area).
[[nodiscard]] double signed_area(const std::vector<Eigen::Vector2d>& loop);

}  // namespace millnet::ingest
