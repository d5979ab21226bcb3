#pragma once
// The finishing tool a CAM engineer would pick for a part when none is named (issue 38): a ball as
// large as the part's size allows and no larger than its concave curved surfaces admit, so that one
// tool finishes nearly all of the surface in the least time; sharp concave corners and the
// smallest radii are left to rest machining.
//
//   const job::PartShape shape = job::part_shape(mesh, frame.stock_top);
//   const tooling::Tool* ball = job::finishing_ball(library, shape);   // null: the library has no ball
#include "millnet/ingest/mesh.hpp"
#include "millnet/tooling/cutting.hpp"

#include <vector>

namespace millnet::job {

/// A concave edge whose faces turn by more than this is a corner, not a curved surface: no ball
/// finishes it (rest machining's), so it does not bound the ball's radius. Radians (45°).
inline constexpr double kSharpConcaveRad = 0.7853981633974483;
/// Faces turning by less than this across an edge are one plane there (no radius). Radians.
inline constexpr double kFlatEdgeRad = 1e-3;
/// Faces steeper than this (from the horizontal) are walls: a height field sampled across a cliff
/// folds there into narrow facets whose creases are no radius of the part. Radians (75°).
inline constexpr double kSteepestFaceRad = 1.3089969389957472;
/// The share of concave curved edge length (by its radius, smallest first) left to rest machining:
/// the radius at this quantile is the "smallest concave radius" the ball is chosen by.
inline constexpr double kRestShare = 0.01;
/// The ball's diameter is at most the footprint's longer side over this (a 300 mm part: Ø20).
inline constexpr double kSizePerDiameter = 15;

/// What the choice reads of a part (mesh frame, mm).
struct PartShape {
  double size_mm = 0;            ///< the footprint's longer side
  double concave_radius_mm = 0;  ///< the smallest concave radius of its curved surfaces (infinity: none)
  double concave_edges_mm = 0;   ///< the length of the concave curved edges it was measured on
  double depth_mm = 0;           ///< from `stock_top` to the lowest face that faces up
};

/// The radius of curvature across every edge of the surfaces machined from above (both faces facing
/// up, neither steeper than kSteepestFaceRad) where the faces meet concavely (their normals converge) and turn by
/// kFlatEdgeRad..kSharpConcaveRad: R = d / (2 sin(θ/2)), d the distance between the two faces'
/// centroids across the edge, θ the angle between their normals (exact for a cylinder's facets);
/// the smallest such radius over all but kRestShare of the edge length. O(F log F).
[[nodiscard]] PartShape part_shape(const ingest::Mesh& mesh, double stock_top);

/// The ball of `library` for finishing a part of this shape: the largest whose diameter is at most
/// min(size / kSizePerDiameter, 2 × concave radius) and whose stick-out reaches the depth (not
/// stated: it reaches); when none is that small, the smallest ball that reaches (the concave radii
/// below it are rest machining's); when none reaches, the longest-reaching ball (the holder check
/// then refuses it, naming the depth). Ties: the shorter stick-out. Null: the library has no ball.
/// O(tools).
[[nodiscard]] const tooling::Tool* finishing_ball(const std::vector<tooling::Tool>& library, const PartShape& shape);

}  // namespace millnet::job
