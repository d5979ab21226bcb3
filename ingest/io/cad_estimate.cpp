// The tessellation's estimate (cad_estimate.hpp): Open CASCADE's mesher measured, then predicted from
// the faces' curvatures and the edges' lengths before it runs.
#include "cad_estimate.hpp"

#if MILLNET_HAVE_CAD
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepLProp_CLProps.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace millnet::ingest::detail {

namespace {

// Open CASCADE's mesher (BRepMesh_IncrementalMesh) was measured on this project's reference machine
// (2 cores) at chord 0.005 mm, 0.2 rad and coarser: a sphere of radius R makes 6.3 · A / ℓ²
// triangles (A its area, ℓ the chord whose sagitta is the chord tolerance, capped by the angle:
// 19,952 for R 10, 201,198 for R 100), a torus 5.7 · A / ℓ₁ℓ₂, the same surfaces as B-splines
// 17 · A / ℓ₁ℓ₂ (Open CASCADE's NURBS splitter refines more); planes and cylinders only their
// boundary's segments (1.4 triangles per segment: the 294-face plate of bench_ingest, 44,364).
// Time per face grows faster than its triangles (0.45 s for 20 k, 6.2 s for 100 k, 17.7 s for
// 200 k in one face; 3.5 s for the plate's 44 k over 294 faces): counted as n · (20 + √n / 5)
// "mesher steps" of ≈ 1 µs for a face of n triangles. Peak memory ≈ 1.3–3.7 kB per triangle:
// 4 kB is charged. The curvatures come from 8 × 8 samples per face and 16 per edge.

constexpr double kTrianglesPerAnalyticArea = 6.5;  ///< sphere, torus, cone: × A / (ℓ₁ ℓ₂)
constexpr double kTrianglesPerFreeformArea = 17;   ///< B-spline, Bézier, offset, swept surfaces
constexpr double kTrianglesPerBoundarySegment = 1.4;

/// The chord of a curve of curvature κ (1/mm) whose sagitta is `chord` mm and whose angle is at
/// most `angle` rad; +inf on a straight curve.
double chord_step(double kappa, double chord, double angle) {
  if (!(kappa > 1e-12)) return std::numeric_limits<double>::infinity();
  const double r = 1 / kappa;
  const double by_sagitta = chord < r ? 2 * std::sqrt(2 * r * chord - chord * chord) : 2 * r;
  return std::min(by_sagitta, 2 * r * std::sin(std::min(angle, std::numbers::pi) / 2));
}

/// Segments Open CASCADE's mesher cuts an edge into. O(16 curve evaluations).
double edge_segments(const TopoDS_Edge& edge, double chord, double angle) {
  if (BRep_Tool::Degenerated(edge)) return 0;
  double segments = 0;
  try {
    BRepAdaptor_Curve c(edge);
    const double t0 = c.FirstParameter(), t1 = c.LastParameter();
    if (!std::isfinite(t0) || !std::isfinite(t1)) return std::numeric_limits<double>::infinity();
    constexpr int kSamples = 16;
    const double dt = (t1 - t0) / kSamples;
    for (int i = 0; i < kSamples; ++i) {
      BRepLProp_CLProps p(c, t0 + (i + 0.5) * dt, 2, 1e-9);
      const double length = p.D1().Magnitude() * std::abs(dt);
      const double kappa = p.IsTangentDefined() ? std::abs(p.Curvature()) : 0;
      const double step = chord_step(kappa, chord, angle);
      if (std::isfinite(step)) segments += length / step;
    }
  } catch (const Standard_Failure&) {
    return 1;
  }
  return std::max(1.0, std::ceil(segments));
}

/// Triangles inside a face, from its curvatures. O(64 surface evaluations).
double face_interior(const TopoDS_Face& face, double chord, double angle) {
  double sum = 0;
  try {
    BRepAdaptor_Surface s(face, Standard_True);
    const GeomAbs_SurfaceType type = s.GetType();
    if (type == GeomAbs_Plane || type == GeomAbs_Cylinder) return 0;  // boundary segments only
    const bool analytic = type == GeomAbs_Sphere || type == GeomAbs_Torus || type == GeomAbs_Cone;
    const bool straight_one_way_is_gridded = type == GeomAbs_Cone || !analytic;
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    if (!std::isfinite(u0) || !std::isfinite(u1) || !std::isfinite(v0) || !std::isfinite(v1))
      return std::numeric_limits<double>::infinity();
    constexpr int kSamples = 8;
    const double du = (u1 - u0) / kSamples, dv = (v1 - v0) / kSamples;
    for (int i = 0; i < kSamples; ++i)
      for (int j = 0; j < kSamples; ++j) {
        BRepLProp_SLProps p(s, u0 + (i + 0.5) * du, v0 + (j + 0.5) * dv, 2, 1e-9);
        if (!p.IsCurvatureDefined()) continue;
        const double area = p.D1U().Crossed(p.D1V()).Magnitude() * std::abs(du * dv);
        const double l1 = chord_step(std::abs(p.MaxCurvature()), chord, angle);
        double l2 = chord_step(std::abs(p.MinCurvature()), chord, angle);
        if (!std::isfinite(l1) && !std::isfinite(l2)) continue;
        if (!std::isfinite(l2)) {
          if (!straight_one_way_is_gridded) continue;
          l2 = 3 * l1;  // a cone's (and a swept surface's) rows along its straight direction
        }
        sum += area / (std::min(l1, l2) * std::max(l1, l2));
      }
    return sum * (analytic ? kTrianglesPerAnalyticArea : kTrianglesPerFreeformArea);
  } catch (const Standard_Failure&) {
    return sum;
  }
}

}  // namespace

/// The mesher's triangles and steps for `shape` (each distinct face and edge once), and the
/// triangles of the mesh returned. O(faces · 64 + edges · 16) evaluations.
TessellationEstimate estimate_tessellation(const TopoDS_Shape& shape, double chord, double angle) {
  TessellationEstimate e;
  std::unordered_map<const void*, double> edge_cache, face_cache;
  for (TopExp_Explorer x(shape, TopAbs_FACE); x.More(); x.Next()) {
    const TopoDS_Face& face = TopoDS::Face(x.Current());
    const auto [known, fresh_face] = face_cache.try_emplace(face.TShape().get(), 0.0);
    if (!fresh_face) {  // meshed once, whatever its placements
      e.placed += known->second;
      continue;
    }
    ++e.faces;
    double n = face_interior(face, chord, angle);
    TopTools_IndexedMapOfShape edges;
    TopExp::MapShapes(face, TopAbs_EDGE, edges);
    for (int i = 1; i <= edges.Extent(); ++i) {
      const TopoDS_Edge& edge = TopoDS::Edge(edges(i));
      const auto [it, fresh] = edge_cache.try_emplace(edge.TShape().get(), 0.0);
      if (fresh) it->second = edge_segments(edge, chord, angle);
      n += kTrianglesPerBoundarySegment * it->second;
    }
    known->second = n;
    e.triangles += n;
    e.placed += n;
    e.steps += n * (20 + std::sqrt(n) / 5);
  }
  return e;
}

}  // namespace millnet::ingest::detail
#endif
