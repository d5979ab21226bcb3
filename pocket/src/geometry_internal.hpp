#pragma once
// Internal helpers of the pocket geometry shared by geometry.cpp, clearance.cpp, gcode.cpp, …
// (not installed; mm throughout).
#include "millnet/pocket/geometry.hpp"

#include <limits>
#include <vector>

namespace millnet::pocket::detail {

/// z of the 2D cross product a × b (> 0: b turns left of a).
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

struct BBox {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  [[nodiscard]] bool overlaps(const BBox& o) const {
    return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y();
  }
};

/// A static bounding-box tree (median splits on the longer side, leaves of ≤ 8 boxes) answering
/// "which boxes overlap this one" in O(log n + answers) for boxes that overlap few others; it
/// replaced the all-pairs loops of the validation (issue 15: 57 s for a 100,000-vertex boundary).
class BoxTree {
public:
  explicit BoxTree(std::vector<BBox> boxes);
  /// Indices of the boxes that overlap q (closed boxes: touching counts), in no particular order.
  void overlapping(const BBox& q, std::vector<std::size_t>& out) const;
  [[nodiscard]] const BBox& box(std::size_t i) const { return boxes_[i]; }

private:
  struct Node {
    BBox box;
    std::size_t begin = 0, end = 0;   ///< range of idx_ (leaves)
    std::size_t left = 0, right = 0;  ///< children (0 = leaf: the root is never a child)
  };
  std::size_t build(std::size_t begin, std::size_t end);
  std::vector<BBox> boxes_;
  std::vector<std::size_t> idx_;
  std::vector<Node> nodes_;
};

/// Exact axis-aligned box of a line or arc.
[[nodiscard]] BBox bbox(const Segment& s);
/// True when the direction phi (radians, about the centre) lies within the arc's sweep.
[[nodiscard]] bool angle_in_arc(const Arc& arc, double phi);
/// True when the point's direction from the centre lies within the arc's sweep.
[[nodiscard]] bool point_on_arc_span(const Arc& arc, const Vec2& q);
/// All intersection points of two segments (lines or arcs, exact); collinear / co-circular
/// overlaps are reported by their end points.
[[nodiscard]] std::vector<Vec2> intersections(const Segment& s, const Segment& t);
/// Smallest distance between two segments (lines or arcs), exact.
[[nodiscard]] double segment_distance(const Segment& s, const Segment& t);
/// Winding-number test, arcs exact; points on the loop give an unspecified answer.
[[nodiscard]] bool strictly_inside_loop(const Loop& loop, const Vec2& p);
/// Distance from p to the nearest segment of the loop, O(n).
[[nodiscard]] double loop_distance(const Loop& loop, const Vec2& p);
/// The same loop traversed the other way (bulges negated and shifted).
[[nodiscard]] Loop reversed(const Loop& loop);

}  // namespace millnet::pocket::detail
