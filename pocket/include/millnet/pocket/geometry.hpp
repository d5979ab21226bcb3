#pragma once
// Pocket geometry: closed loops of lines and arcs in the DXF LWPOLYLINE "bulge" convention.
//   * Loop = vertices; segment k runs from v[k] to v[(k+1) % n]; its shape is v[k].bulge =
//     tan(sweep/4), 0 = straight line, > 0 = counter-clockwise arc, |bulge| ≤ 1 (a half circle) after
//     validation (larger arcs are split in two).
//   * Region = boundary (CCW after normalization) + islands (CW after normalization), mm.
// Tolerances are named in pocket/tolerances.hpp.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace millnet::pocket {

using Vec2 = Eigen::Vector2d;

struct Vertex {
  double x = 0, y = 0, bulge = 0;
  [[nodiscard]] Vec2 p() const { return {x, y}; }
};
using Loop = std::vector<Vertex>;

struct Region {
  Loop boundary;
  std::vector<Loop> islands;
};

/// A polygon with holes as polylines (outer CCW, holes CW, first point not repeated): what
/// offsets (offset.hpp), partitions and uncut areas are made of.
struct PolyArea {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
};

/// One segment of a loop or path: a line (bulge == 0) or a circular arc from a to b.
struct Segment {
  Vec2 a, b;
  double bulge = 0;
  [[nodiscard]] bool is_arc() const { return bulge != 0.0; }
};

struct Arc {
  Vec2 center;
  double radius = 0;
  double start_angle = 0;  ///< radians, angle of a about center
  double sweep = 0;        ///< radians, signed (> 0 = CCW), |sweep| = 4·atan(|bulge|)
};

[[nodiscard]] std::vector<Segment> segments(const Loop& loop);
[[nodiscard]] Arc arc_of(const Segment& s);  ///< requires s.is_arc()
[[nodiscard]] double length(const Segment& s);
[[nodiscard]] Vec2 point_at(const Segment& s, double t);  ///< t ∈ [0, 1] by arc length
[[nodiscard]] Vec2 closest_point(const Segment& s, const Vec2& p);
[[nodiscard]] double distance(const Segment& s, const Vec2& p);  ///< exact for arcs
/// Smallest distance between the straight move [p, q] and segment s (exact for arcs).
[[nodiscard]] double distance(const Segment& s, const Vec2& p, const Vec2& q);
[[nodiscard]] double signed_area(const Loop& loop);  ///< > 0 for CCW; arcs exact
[[nodiscard]] double perimeter(const Loop& loop);
/// Point in loop by winding number (arcs exact); points on the loop (within tol::on_curve_mm)
/// count as inside.
[[nodiscard]] bool inside(const Loop& loop, const Vec2& p);
/// Inside the boundary and outside every island.
[[nodiscard]] bool inside(const Region& region, const Vec2& p);
/// Polyline approximation of a loop whose chords stay within `chord_tol_mm` of the arcs
/// (first vertex not repeated at the end).
[[nodiscard]] std::vector<Vec2> flatten(const Loop& loop, double chord_tol_mm);
/// The same for an open path of vertices (segment k from pts[k] to pts[k + 1] with pts[k].bulge):
/// every vertex, and chords within `chord_tol_mm` of each arc.
[[nodiscard]] std::vector<Vec2> flatten_open(const std::vector<Vertex>& pts, double chord_tol_mm);
/// Area of the region (boundary minus islands), mm².
[[nodiscard]] double area(const Region& region);

/// The part of `region` that lies inside `keep` (Clipper intersection, non-zero fill; arcs
/// flattened within tol::arc_chord_mm, coordinates on tol::clipper_resolution_mm): one region per
/// connected piece, its boundary counter-clockwise and its islands clockwise, straight segments.
/// Empty when they do not overlap. O((n + m) log(n + m)) for n + m vertices.
[[nodiscard]] std::vector<Region> intersect(const Region& region, const std::vector<PolyArea>& keep);

/// What validate_and_normalize() changed (never silently).
struct NormalizeReport {
  std::vector<std::string> notes;  ///< e.g. "boundary was clockwise: reversed"
};

/// Checks a region and normalizes it in place: closes nothing silently, throws millnet::Error
/// (with `source` and the loop/vertex index) for: empty input, fewer than 2 vertices, zero-length
/// segments, |bulge| not finite, self-intersections, islands crossing the boundary or each other,
/// islands outside the boundary. Splits arcs with |bulge| > 1 (noted), orients boundary CCW and
/// islands CW (noted when flipped).
NormalizeReport validate_and_normalize(Region& region, const std::string& source);

/// Fast clearance queries against every wall (boundary and island segments) of a region, for a
/// tool centre that must stay `clearance` mm away from the walls (tool radius + stock to leave):
/// walls are bucketed in a uniform grid so that a query looks only at nearby segments.
class Clearance {
public:
  Clearance(const Region& region, double clearance_mm);
  ~Clearance();
  Clearance(Clearance&&) noexcept;
  Clearance& operator=(Clearance&&) noexcept;
  [[nodiscard]] double clearance() const;
  /// Distance from p to the nearest wall (exact for arcs).
  [[nodiscard]] double wall_distance(const Vec2& p) const;
  /// Tool centre p is inside the region and at least clearance − tol::clear_mm from every wall.
  [[nodiscard]] bool point_ok(const Vec2& p) const;
  /// The straight move p→q sweeps the tool disk without overcutting: both ends point_ok and the
  /// segment keeps ≥ clearance − tol::clear_mm from every wall.
  [[nodiscard]] bool move_ok(const Vec2& p, const Vec2& q) const;
  /// The segment p→q keeps ≥ clearance − tol::clear_mm from every wall, whether or not it lies in
  /// the region: move_ok is point_ok(p) and this. For callers that know p is inside (a raster
  /// cell): the winding test is the costly part of point_ok.
  [[nodiscard]] bool segment_clear(const Vec2& p, const Vec2& q) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace millnet::pocket
