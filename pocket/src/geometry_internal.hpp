#pragma once
// Internal helpers of the pocket geometry shared by geometry.cpp, clearance.cpp, gcode.cpp, …
// (not installed; mm throughout).
#include "millnet/pocket/geometry.hpp"

#include <limits>
#include <vector>

namespace millnet::pocket::detail {

struct BBox {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
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
