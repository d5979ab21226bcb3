// Offsets and booleans through Clipper 6 (integer coordinates at tol::clipper_resolution_mm).
#include "millnet/pocket/offset.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>

namespace millnet::pocket {

namespace {
using ClipperLib::cInt;
constexpr double kScale = 1.0 / tol::clipper_resolution_mm;

ClipperLib::Path to_path(const std::vector<Vec2>& pts) {
  ClipperLib::Path p;
  p.reserve(pts.size());
  for (const Vec2& v : pts)
    p.emplace_back(static_cast<cInt>(std::llround(v.x() * kScale)), static_cast<cInt>(std::llround(v.y() * kScale)));
  return p;
}

std::vector<Vec2> from_path(const ClipperLib::Path& p) {
  std::vector<Vec2> out;
  out.reserve(p.size());
  for (const auto& q : p) out.emplace_back(static_cast<double>(q.X) / kScale, static_cast<double>(q.Y) / kScale);
  return out;
}

double path_area(const std::vector<Vec2>& pts) {
  double a = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Vec2& p = pts[k];
    const Vec2& q = pts[(k + 1) % pts.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * a;
}

/// Outer nodes with their holes; outers nested in holes start new components. O(nodes).
void collect(const ClipperLib::PolyNode& node, std::vector<PolyArea>& out) {
  for (const ClipperLib::PolyNode* child : node.Childs) {
    if (child->IsHole()) continue;
    PolyArea a;
    a.outer = from_path(child->Contour);
    if (path_area(a.outer) < 0) std::reverse(a.outer.begin(), a.outer.end());
    for (const ClipperLib::PolyNode* hole : child->Childs) {
      auto h = from_path(hole->Contour);
      if (path_area(h) > 0) std::reverse(h.begin(), h.end());
      a.holes.push_back(std::move(h));
      collect(*hole, out);
    }
    out.push_back(std::move(a));
  }
}

ClipperLib::Paths to_paths(const std::vector<PolyArea>& areas) {
  ClipperLib::Paths ps;
  for (const PolyArea& a : areas) {
    ps.push_back(to_path(a.outer));
    if (!ClipperLib::Orientation(ps.back())) ClipperLib::ReversePath(ps.back());
    for (const auto& h : a.holes) {
      ps.push_back(to_path(h));
      if (ClipperLib::Orientation(ps.back())) ClipperLib::ReversePath(ps.back());
    }
  }
  return ps;
}

std::vector<PolyArea> run_offset(ClipperLib::ClipperOffset& co, double delta_mm, double chord_tol_mm) {
  co.ArcTolerance = std::max(chord_tol_mm, tol::clipper_resolution_mm) * kScale;
  ClipperLib::PolyTree tree;
  co.Execute(tree, delta_mm * kScale);
  std::vector<PolyArea> out;
  collect(tree, out);
  return out;
}
}  // namespace

std::vector<PolyArea> offset_inward(const Region& region, double delta_mm, double chord_tol_mm) {
  if (!std::isfinite(delta_mm)) throw Error("offset_inward: delta is not finite");
  ClipperLib::ClipperOffset co;
  // Arcs are flattened with chords within chord_tol_mm: O(total flattened vertices).
  ClipperLib::Path outer = to_path(flatten(region.boundary, chord_tol_mm));
  if (!ClipperLib::Orientation(outer)) ClipperLib::ReversePath(outer);
  co.AddPath(outer, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  for (const Loop& isl : region.islands) {
    ClipperLib::Path h = to_path(flatten(isl, chord_tol_mm));
    if (ClipperLib::Orientation(h)) ClipperLib::ReversePath(h);
    co.AddPath(h, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  }
  return run_offset(co, -delta_mm, chord_tol_mm);
}

std::vector<PolyArea> offset_areas(const std::vector<PolyArea>& areas, double delta_mm, double chord_tol_mm) {
  ClipperLib::ClipperOffset co;
  co.AddPaths(to_paths(areas), ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  return run_offset(co, delta_mm, chord_tol_mm);
}

std::vector<PolyArea> swept_area(const std::vector<std::vector<Vec2>>& polylines, double radius_mm,
                                 double chord_tol_mm) {
  ClipperLib::ClipperOffset co;
  for (const auto& pl : polylines) {
    if (pl.empty()) continue;
    ClipperLib::Path p = to_path(pl);
    if (p.size() == 1) p.push_back(p.front());  // a plunge: Clipper rounds a zero-length path into a disk
    co.AddPath(p, ClipperLib::jtRound, ClipperLib::etOpenRound);
  }
  return run_offset(co, radius_mm, chord_tol_mm);
}

std::vector<PolyArea> difference(const std::vector<PolyArea>& a, const std::vector<PolyArea>& b) {
  ClipperLib::Clipper c;
  c.AddPaths(to_paths(a), ClipperLib::ptSubject, true);
  c.AddPaths(to_paths(b), ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  c.Execute(ClipperLib::ctDifference, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<PolyArea> out;
  collect(tree, out);
  return out;
}

double area(const PolyArea& a) {
  double s = std::abs(path_area(a.outer));
  for (const auto& h : a.holes) s -= std::abs(path_area(h));
  return s;
}

double area(const std::vector<PolyArea>& areas) {
  double s = 0;
  for (const PolyArea& a : areas) s += area(a);
  return s;
}

}  // namespace millnet::pocket
