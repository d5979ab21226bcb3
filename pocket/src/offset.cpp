// Offsets and booleans through Clipper 6 (integer coordinates at tol::clipper_resolution_mm).
#include "offset.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "clipper_bridge.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>

namespace millnet::pocket {

namespace {
using ClipperLib::cInt;
constexpr double kScale = 1.0 / tol::clipper_resolution_mm;

ClipperLib::Path to_path(const std::vector<Vec2>& pts) { return clipper_bridge::to_path(pts, kScale); }
void collect(const ClipperLib::PolyNode& node, std::vector<PolyArea>& out) {
  clipper_bridge::collect(node, out, kScale);
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

/// Douglas–Peucker on a closed polygon: keeps the vertices that lie more than eps_mm from the chord
/// replacing them (at least 3). A boundary of 100,000 vertices 3 µm apart made every offset spend
/// ~15 s in Clipper (issue 15); with eps below Clipper's own rounding the offsets do not change.
/// O(n log n) typical (iterative, no recursion).
std::vector<Vec2> simplify_closed(const std::vector<Vec2>& p, double eps_mm) {
  const std::size_t n = p.size();
  if (n <= 8) return p;
  std::size_t far = 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((p[k] - p[0]).squaredNorm() > (p[far] - p[0]).squaredNorm()) far = k;
  if (far == 0) return p;
  std::vector<char> keep(n + 1, 0);
  keep[0] = keep[far] = keep[n] = 1;
  auto at = [&](std::size_t k) -> const Vec2& { return p[k % n]; };
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, far}, {far, n}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    const Vec2 a = at(i), d = at(j) - a;
    const double len = d.norm();
    double worst = -1;
    std::size_t w = i;
    for (std::size_t k = i + 1; k < j; ++k) {
      const Vec2 v = at(k) - a;
      const double dist = len > 0 ? std::abs(d.x() * v.y() - d.y() * v.x()) / len : v.norm();
      if (dist > worst) {
        worst = dist;
        w = k;
      }
    }
    if (worst > eps_mm) {
      keep[w] = 1;
      stack.push_back({i, w});
      stack.push_back({w, j});
    }
  }
  std::vector<Vec2> out;
  for (std::size_t k = 0; k < n; ++k)
    if (keep[k]) out.push_back(p[k]);
  return out.size() >= 3 ? out : p;
}

/// Vertices this close to the chord that replaces them are dropped before offsetting: half of
/// Clipper's integer grid, so below the rounding Clipper applies anyway.
constexpr double kSimplifyMm = 0.5 * tol::clipper_resolution_mm;

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
  ClipperLib::Path outer = to_path(simplify_closed(flatten(region.boundary, chord_tol_mm), kSimplifyMm));
  if (!ClipperLib::Orientation(outer)) ClipperLib::ReversePath(outer);
  co.AddPath(outer, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  for (const Loop& isl : region.islands) {
    ClipperLib::Path h = to_path(simplify_closed(flatten(isl, chord_tol_mm), kSimplifyMm));
    if (ClipperLib::Orientation(h)) ClipperLib::ReversePath(h);
    co.AddPath(h, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  }
  return run_offset(co, -delta_mm, chord_tol_mm);
}

PolyArea simplified(const PolyArea& a, double eps_mm) {
  PolyArea out;
  out.outer = simplify_closed(a.outer, eps_mm);
  for (const auto& h : a.holes) out.holes.push_back(simplify_closed(h, eps_mm));
  return out;
}

std::vector<PolyArea> offset_areas(const std::vector<PolyArea>& areas, double delta_mm, double chord_tol_mm) {
  ClipperLib::ClipperOffset co;
  co.AddPaths(to_paths(areas), ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  return run_offset(co, delta_mm, chord_tol_mm);
}

std::vector<PolyArea> swept_area(const std::vector<std::vector<Vec2>>& polylines, double radius_mm,
                                 double chord_tol_mm) {
  // Each polyline is cut into pieces of kPiece segments (neighbours share a vertex), each piece's
  // swept outline made on its own, and the outlines united pairwise, level by level. One offset of
  // a whole long path is one outline crossing itself wherever passes overlap, and Clipper's sweep
  // over it is quadratic in the overlapping edges (a 20,000-vertex adaptive path: 25 s); a union
  // of two halves keeps only their outer boundary, so each level handles the boundary of what is
  // cut so far. The union is exact on Clipper's integer grid whatever the grouping.
  constexpr std::size_t kPiece = 64;
  std::vector<ClipperLib::Paths> parts;
  auto offset_piece = [&](const std::vector<Vec2>& pts) {
    ClipperLib::Path p = to_path(pts);
    if (p.size() == 1) p.push_back(p.front());  // a plunge: Clipper rounds a zero-length path into a disk
    ClipperLib::ClipperOffset co;
    co.ArcTolerance = std::max(chord_tol_mm, tol::clipper_resolution_mm) * kScale;
    co.AddPath(p, ClipperLib::jtRound, ClipperLib::etOpenRound);
    ClipperLib::Paths out;
    co.Execute(out, radius_mm * kScale);
    parts.push_back(std::move(out));
  };
  for (const auto& pl : polylines) {  // O(vertices)
    if (pl.empty()) continue;
    for (std::size_t a = 0;; a += kPiece) {
      const std::size_t b = std::min(a + kPiece, pl.size() - 1);
      offset_piece(std::vector<Vec2>(pl.begin() + static_cast<std::ptrdiff_t>(a),
                                     pl.begin() + static_cast<std::ptrdiff_t>(b) + 1));
      if (b + 1 >= pl.size()) break;
    }
  }
  auto unite = [](const ClipperLib::Paths& x, const ClipperLib::Paths& y) {
    ClipperLib::Clipper c;
    c.AddPaths(x, ClipperLib::ptSubject, true);
    c.AddPaths(y, ClipperLib::ptClip, true);
    ClipperLib::Paths out;
    c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
  };
  while (parts.size() > 1) {  // O(log pieces) levels
    std::vector<ClipperLib::Paths> next;
    for (std::size_t i = 0; i + 1 < parts.size(); i += 2) next.push_back(unite(parts[i], parts[i + 1]));
    if (parts.size() % 2 == 1) next.push_back(std::move(parts.back()));
    parts = std::move(next);
  }
  std::vector<PolyArea> out;
  if (parts.empty()) return out;
  ClipperLib::Clipper c;
  c.AddPaths(parts.front(), ClipperLib::ptSubject, true);
  ClipperLib::PolyTree tree;
  c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  collect(tree, out);
  return out;
}

std::vector<std::vector<Vec2>> wall_loops(const Region& region, double clearance_mm) {
  std::vector<std::vector<Vec2>> loops;
  for (PolyArea& a : offset_inward(region, clearance_mm + tol::contour_margin_mm, tol::contour_chord_mm)) {
    if (a.outer.size() >= 3) loops.push_back(std::move(a.outer));
    for (auto& h : a.holes)
      if (h.size() >= 3) loops.push_back(std::move(h));
  }
  return loops;
}

namespace {
std::vector<PolyArea> boolean(const std::vector<PolyArea>& a, const std::vector<PolyArea>& b, ClipperLib::ClipType op) {
  ClipperLib::Clipper c;
  c.AddPaths(to_paths(a), ClipperLib::ptSubject, true);
  c.AddPaths(to_paths(b), ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  c.Execute(op, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<PolyArea> out;
  collect(tree, out);
  return out;
}
}  // namespace

std::vector<Region> intersect(const Region& region, const std::vector<PolyArea>& keep) {
  ClipperLib::Paths subject;
  subject.push_back(to_path(flatten(region.boundary, tol::arc_chord_mm)));
  if (!ClipperLib::Orientation(subject.back())) ClipperLib::ReversePath(subject.back());
  for (const Loop& isl : region.islands) {
    subject.push_back(to_path(flatten(isl, tol::arc_chord_mm)));
    if (ClipperLib::Orientation(subject.back())) ClipperLib::ReversePath(subject.back());
  }
  ClipperLib::Clipper c;
  c.AddPaths(subject, ClipperLib::ptSubject, true);
  c.AddPaths(to_paths(keep), ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  c.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<PolyArea> pieces;
  collect(tree, pieces);
  const auto to_loop = [](const std::vector<Vec2>& pts) {
    Loop l;
    l.reserve(pts.size());
    for (const Vec2& v : pts) l.push_back({v.x(), v.y(), 0.0});
    return l;
  };
  std::vector<Region> out;
  for (const PolyArea& a : pieces) {  // O(pieces)
    if (a.outer.size() < 3) continue;
    Region r;
    r.boundary = to_loop(a.outer);
    for (const auto& h : a.holes)
      if (h.size() >= 3) r.islands.push_back(to_loop(h));
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<PolyArea> difference(const std::vector<PolyArea>& a, const std::vector<PolyArea>& b) {
  return boolean(a, b, ClipperLib::ctDifference);
}

double area(const PolyArea& a) {
  double s = std::abs(shoelace_area(a.outer));
  for (const auto& h : a.holes) s -= std::abs(shoelace_area(h));
  return s;
}

double area(const std::vector<PolyArea>& areas) {
  double s = 0;
  for (const PolyArea& a : areas) s += area(a);
  return s;
}

}  // namespace millnet::pocket
