// Drop-cutter (dropcutter.hpp). Every cutter is a torus: R = diameter/2, corner radius r, a = R − r
// (flat: r = 0, a = R; ball: a = 0). With the axis at (x, y) and d(p) the XY distance of a point p
// from the axis, a triangle T alone lets the tip go down to
//     z(T) = max { p.z − h(d(p)) : p ∈ T, d(p) ≤ R },   h = Cutter::profile_height,
// and the CL height is the max of z(T) over all triangles. p.z is linear on T and h∘d is convex
// (h is convex and non-decreasing, d is convex), so the objective is concave on the convex set
// T ∩ disk: its maximum is either the facet's stationary point (the cutter's contact point for the
// facet normal, if it falls inside T), or lies on an edge (a 1-D concave problem, closed form for
// ball and flat, bracketed safeguarded Newton for the bull), or at a vertex. A maximum on the disk's
// rim inside T only happens for the flat cutter, and then it is the facet point.
#include "millnet/finish/dropcutter.hpp"

#include "millnet/core/error.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

namespace millnet::finish {
using tooling::Cutter;
using tooling::CutterType;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Index building runs serially below this many triangles / cells (thread start-up costs more).
constexpr std::int32_t kSerialBelow = 20000;
/// Bounds prune a triangle only when it falls short of the best contact by more than this (mm),
/// so that rounding in a bound never hides a contact: indexed and brute-force drops agree exactly.
constexpr double kPruneSlack = 1e-9;

/// The cutter as numbers used by the kernels.
struct Shape {
  CutterType type = CutterType::Ball;
  double R = 1, R2 = 1, r = 1, a = 0;

  explicit Shape(const Cutter& c) : type(c.shape()), R(c.radius()), R2(R * R) {
    r = c.profile_corner_radius();
    a = type == CutterType::Ball ? 0.0 : R - r;
  }
  /// Profile height for 0 ≤ d ≤ R (callers check d ≤ R).
  [[nodiscard]] double h(double d) const {
    if (d <= a) return 0.0;
    const double u = d - a;
    return r - std::sqrt(std::max(0.0, r * r - u * u));
  }
  /// False only when a point at height ≤ zmax and squared XY distance ≥ d2 from the axis surely
  /// cannot lift the cutter above `best`: zmax − h(√d2) < best − kPruneSlack. Uses h⁻¹(t) =
  /// a + √(2rt − t²), so the ball and flat tests need no square root.
  [[nodiscard]] bool can_beat(double zmax, double d2, double best) const {
    const double t = zmax - best + kPruneSlack;
    if (t <= 0) return false;
    if (t >= r) return true;
    const double w = t * (2 * r - t);
    if (a == 0) return d2 < w;
    const double dl = a + std::sqrt(w);
    return d2 < dl * dl;
  }
};

struct Best {
  double z = -kInf;
  Contact contact = Contact::None;
  double cx = 0, cy = 0, cz = 0;  // contact point
  std::int32_t tri = -1;

  // The highest contact; of equal ones, the lowest triangle's (within a triangle, the first
  // found): the answer does not depend on the order triangles are evaluated in, so a hint or the
  // index's visiting order never changes it (ties are never pruned: kPruneSlack).
  void consider(double z_, Contact c, double x, double y, double zc, std::int32_t t) {
    if (z_ > z || (z_ == z && t < tri)) {
      z = z_;
      contact = c;
      cx = x;
      cy = y;
      cz = zc;
      tri = t;
    }
  }
};

struct P3 {
  double x, y, z;
};

/// Bull edge: maximise f(s) = m·s − h(√(dp2 + s²)) on [lo, hi]. f is concave, so its derivative
/// g(s) = m − h'(d)·s/d is non-increasing; a sign change of g is bracketed and closed in on with
/// Newton steps that fall back to bisection whenever they leave the bracket; s to ≈1e-13 mm.
/// Concavity also gives f ≤ f(s) + g(s)·(s* − s) at every iterate: as soon as that bound keeps
/// f below `floor`, the edge cannot win and the search stops (returns false).
bool bull_edge_argmax(double m, double dp2, double lo, double hi, double r, double a, double floor, double& s_out) {
  // g at s; *f = f(s), *dg = g'(s).
  const auto g = [&](double s, double* f, double* dg) {
    const double d = std::sqrt(dp2 + s * s);
    if (d <= a) {
      *f = m * s;
      *dg = 0;
      return m;
    }
    const double u = d - a;
    const double w = r * r - u * u;
    if (w <= 0) {
      *f = m * s - r;
      *dg = -kInf;
      return s > 0 ? -kInf : kInf;
    }
    const double sw = std::sqrt(w);
    const double hp = u / sw;             // h'(d)
    const double hpp = r * r / (w * sw);  // h''(d)
    *f = m * s - (r - sw);
    *dg = -(hpp * (s / d) * (s / d) + hp * dp2 / (d * d * d));
    return m - hp * s / d;
  };
  double f = 0, dg = 0;
  s_out = lo;
  if (!(hi > lo)) return true;
  if (g(lo, &f, &dg) <= 0) return true;
  s_out = hi;
  if (g(hi, &f, &dg) >= 0) return true;
  // Start from the exact answer for dp = 0 (the section is then two circles of radius r centred
  // at s = ±a), adapted to dp: usually within a few Newton steps of the root.
  const double ex = dp2 < a * a ? 0.0 : std::sqrt(dp2) - a;
  const double guess = std::copysign(std::sqrt(std::max(0.0, a * a - dp2)), m) +
                       m * std::sqrt(std::max(0.0, r * r - ex * ex) / (1 + m * m));
  double s = guess > lo && guess < hi ? guess : 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double gs = g(s, &f, &dg);
    s_out = s;
    if (gs == 0) return true;
    if (std::isfinite(gs) && f + (gs > 0 ? gs * (hi - s) : gs * (lo - s)) < floor) return false;
    if (gs > 0)
      lo = s;
    else
      hi = s;
    if (hi - lo <= 1e-13) {
      s_out = 0.5 * (lo + hi);
      return true;
    }
    double sn = (dg < 0 && std::isfinite(dg)) ? s - gs / dg : lo - 1;
    if (!(sn > lo && sn < hi)) sn = 0.5 * (lo + hi);
    if (std::abs(sn - s) <= 1e-15 * std::max(1.0, std::abs(s))) {
      s_out = sn;
      return true;
    }
    s = sn;
  }
  return true;
}

/// All contacts of one triangle; coordinates relative to the axis (the axis is at x = y = 0).
void eval_triangle(const Shape& sh, const P3& A, const P3& B, const P3& C, std::int32_t id, Best& best) {
  const double zmax = std::max({A.z, B.z, C.z});
  if (zmax <= best.z - kPruneSlack) return;
  // Facet: the cutter point whose normal is −n touches the triangle's plane. Its value is the
  // maximum over the whole plane ∩ disk, so it bounds every contact of the triangle; when the
  // point lies inside the triangle it is the triangle's maximum (the objective is concave).
  {
    const double ux = B.x - A.x, uy = B.y - A.y, uz = B.z - A.z;
    const double vx = C.x - A.x, vy = C.y - A.y, vz = C.z - A.z;
    double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (nz < 0) {
      nx = -nx;
      ny = -ny;
      nz = -nz;
    }
    if (len > 0 && nz > 1e-12 * len) {
      nx /= len;
      ny /= len;
      nz /= len;
      double px = 0, py = 0;
      if (sh.a == 0) {  // ball
        px = -sh.r * nx;
        py = -sh.r * ny;
      } else {
        const double nxy = std::sqrt(nx * nx + ny * ny);
        if (nxy > 1e-15) {
          const double k = sh.a / nxy + sh.r;
          px = -k * nx;
          py = -k * ny;
        }
      }
      const double zc = A.z - (nx * (px - A.x) + ny * (py - A.y)) / nz;
      const double zf = zc - sh.r * (1 - nz);
      if (zf <= best.z - kPruneSlack) return;
      const double e0 = (B.x - A.x) * (py - A.y) - (B.y - A.y) * (px - A.x);
      const double e1 = (C.x - B.x) * (py - B.y) - (C.y - B.y) * (px - B.x);
      const double e2 = (A.x - C.x) * (py - C.y) - (A.y - C.y) * (px - C.x);
      if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0)) {
        best.consider(zf, Contact::Facet, px, py, zc, id);
        return;
      }
    }
  }
  // Vertices.
  for (const P3* v : {&A, &B, &C}) {
    const double d2 = v->x * v->x + v->y * v->y;
    if (d2 > sh.R2 || !sh.can_beat(v->z, d2, best.z)) continue;
    best.consider(v->z - sh.h(std::sqrt(d2)), Contact::Vertex, v->x, v->y, v->z, id);
  }
  // Edges: in the edge's vertical plane, s is the XY distance along the edge from the foot of the
  // perpendicular from the axis; the objective is zf + m·s − h(√(dp² + s²)).
  const std::array<std::pair<const P3*, const P3*>, 3> edges{{{&A, &B}, {&B, &C}, {&C, &A}}};
  for (const auto& [P, Q] : edges) {
    const double ex = Q->x - P->x, ey = Q->y - P->y;
    const double L2 = ex * ex + ey * ey;
    if (L2 < 1e-24) continue;  // vertical edge: its top vertex is the contact
    const double cr = P->x * ey - P->y * ex;
    const double dp2 = cr * cr / L2;  // squared distance of the axis from the edge's line
    if (dp2 > sh.R2) continue;
    // Where the foot of the perpendicular lies off the edge, the distance to the axis grows
    // monotonically along it: if the nearer end is also the higher one, that vertex is the edge's
    // maximum; otherwise the nearer end's distance bounds h from below.
    const double proj = -(P->x * ex + P->y * ey);  // foot at proj / L2 along P→Q
    double dmin2 = dp2;
    if (proj <= 0) {
      if (P->z >= Q->z) continue;
      dmin2 = P->x * P->x + P->y * P->y;
    } else if (proj >= L2) {
      if (Q->z >= P->z) continue;
      dmin2 = Q->x * Q->x + Q->y * Q->y;
    }
    if (dmin2 > sh.R2 || !sh.can_beat(std::max(P->z, Q->z), dmin2, best.z)) continue;
    const double L = std::sqrt(L2);
    const double ux = ex / L, uy = ey / L;
    const double t0 = -(P->x * ux + P->y * uy);
    const double S = std::sqrt(std::max(0.0, sh.R2 - dp2));
    const double lo = std::max(-t0, -S), hi = std::min(L - t0, S);
    if (lo > hi) continue;
    const double m = (Q->z - P->z) / L;
    const double zf = P->z + m * t0;
    double s = 0, z = 0;
    switch (sh.type) {
      case CutterType::Flat:
        s = m > 0 ? hi : (m < 0 ? lo : std::clamp(0.0, lo, hi));
        z = zf + m * s;
        break;
      case CutterType::Ball: {
        const double rho2 = std::max(0.0, sh.r * sh.r - dp2);
        s = std::clamp(m * std::sqrt(rho2 / (1 + m * m)), lo, hi);
        z = zf + m * s - sh.r + std::sqrt(std::max(0.0, rho2 - s * s));
        break;
      }
      case CutterType::Bull:
        if (!bull_edge_argmax(m, dp2, lo, hi, sh.r, sh.a, best.z - kPruneSlack - zf, s)) continue;
        z = zf + m * s - sh.h(std::min(sh.R, std::sqrt(dp2 + s * s)));
        break;
    }
    if (s == -t0 || s == L - t0) continue;  // an end point: the vertex contact covers it
    const double t = t0 + s;
    best.consider(z, Contact::Edge, P->x + t * ux, P->y + t * uy, P->z + m * t, id);
  }
}

P3 rel(const ingest::Mesh& mesh, std::int32_t v, double x, double y) {
  const auto i = static_cast<Eigen::Index>(v);
  return {mesh.V(i, 0) - x, mesh.V(i, 1) - y, mesh.V(i, 2)};
}

void eval_face(const Shape& sh, const ingest::Mesh& mesh, std::int32_t f, double x, double y, Best& best) {
  const auto fi = static_cast<Eigen::Index>(f);
  eval_triangle(sh, rel(mesh, mesh.F(fi, 0), x, y), rel(mesh, mesh.F(fi, 1), x, y), rel(mesh, mesh.F(fi, 2), x, y), f,
                best);
}

CLPoint to_cl(const Best& b, double x, double y) {
  CLPoint p;
  p.x = x;
  p.y = y;
  p.z = b.z;
  p.contact = b.contact;
  p.triangle = b.tri;
  if (b.contact != Contact::None) p.cc = Eigen::Vector3d(b.cx + x, b.cy + y, b.cz);
  return p;
}

/// float bounds that contain the double value.
float round_down(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

struct CellBox {
  float x0, y0, x1, y1, zmax;
};

/// A triangle as listed in a cell: its box is copied next to its id so that a query streams
/// through one contiguous array and touches the mesh only for the triangles it evaluates.
/// With its plane bound: the facet formula against the triangle's whole plane, an upper bound of
/// every contact of the triangle, is zp + gx·(x − box.x0) + gy·(y − box.y0) for the axis at (x, y)
/// (zp = +inf for vertical triangles).
struct FaceEntry {
  CellBox box;
  std::int32_t tri;
  double zp, gx, gy;
};

}  // namespace

// The index is a uniform grid of square cells (side ≥ R/2) over the mesh's XY extent. A triangle
// whose XY box fits in a cell is listed once, in the cell of its box centre; a bigger one in every
// cell its box overlaps. A query visits the cells within R + half a cell of the axis — every
// triangle whose box grown by R contains the axis is found — and handles a big triangle once, in
// the cell holding the lower-left corner of (its box ∩ the query square of side 2R). Each cell
// keeps the union of its boxes and their top z, and its list is sorted by top z, descending.
// Upper bounds prune: per cell and per triangle zmax − h(distance to the box), per triangle also
// the facet formula on its whole plane; cells are visited by descending bound, and a query stops as
// soon as nothing left can lift the cutter above the best contact so far. Batches start each
// query from the previous point's contact triangle, which usually gives the answer at once.
// At most 7×7 cells are visited per query (cell side ≥ R/2).
struct DropCutter::Impl {
  Cutter cutter;
  Shape shape;
  ingest::Mesh mesh;
  double x0 = 0, y0 = 0, cs = 1, inv_cs = 1;
  int nx = 1, ny = 1;
  std::vector<std::int32_t> start;  // nx·ny + 1
  std::vector<FaceEntry> entries;   // per cell, by descending top z
  std::vector<CellBox> cells;       // per cell: union of boxes, max top z

  Impl(const ingest::Mesh& m, const Cutter& c) : cutter(c), shape(c), mesh(m) {}

  // Cell of a coordinate, clamped to the grid (truncation is floor for the positive values).
  [[nodiscard]] int cell_x(double x) const {
    const double t = (x - x0) * inv_cs;
    if (!(t > 0)) return 0;
    return t >= nx - 1 ? nx - 1 : static_cast<int>(t);
  }
  [[nodiscard]] int cell_y(double y) const {
    const double t = (y - y0) * inv_cs;
    if (!(t > 0)) return 0;
    return t >= ny - 1 ? ny - 1 : static_cast<int>(t);
  }

  /// A small triangle (box no wider than a cell) is listed once, in the cell of its box centre; a
  /// big one in every cell its box overlaps (tagged big: id stored as −id − 1).
  struct CellRange {
    int ix0, ix1, iy0, iy1;
    bool big;
  };
  [[nodiscard]] CellRange cells_of(const CellBox& b) const {
    const double bx0 = static_cast<double>(b.x0), by0 = static_cast<double>(b.y0), bx1 = static_cast<double>(b.x1),
                 by1 = static_cast<double>(b.y1);
    if (bx1 - bx0 <= cs && by1 - by0 <= cs) {
      const int ix = cell_x(0.5 * (bx0 + bx1)), iy = cell_y(0.5 * (by0 + by1));
      return {ix, ix, iy, iy, false};
    }
    return {cell_x(bx0), cell_x(bx1), cell_y(by0), cell_y(by1), true};
  }

  [[nodiscard]] double cell_side(const std::vector<CellBox>& boxes, double W, double H) const;
  void build();
  void query(double x, double y, std::int32_t hint, Best& best) const;
};

// The cell side that makes a query cheapest by a cost model: a query checks the cells of a square of
// side 2R + 2·cs (the search square, its margin and the cells' alignment) and scans their lists; a
// triangle wider than a cell is listed in every cell it overlaps (on a meshed height field of 1 mm
// facets and a Ø2 ball, cells of R/2 listed each facet four times: 104 entries scanned a query
// against 30). Candidates from max(R/2, √(area / triangles)) up by 1.25×, each costed in
// O(triangles): cells a query × (1 + entries a cell / 2) — a cell's check costs about two entry scans.
// The answer never depends on the side (the index only prunes); only the time does.
double DropCutter::Impl::cell_side(const std::vector<CellBox>& boxes, double W, double H) const {
  const double nf = static_cast<double>(boxes.size());
  const double first = std::max(shape.R / 2, std::sqrt(W * H / nf));
  double best = first, best_cost = kInf;
  for (double c = first; c <= 2 * first || c <= 4 * shape.R; c *= 1.25) {  // O(candidates × triangles)
    double listed = 0;
    for (const CellBox& b : boxes) {
      const double w = static_cast<double>(b.x1) - static_cast<double>(b.x0),
                   h = static_cast<double>(b.y1) - static_cast<double>(b.y0);
      listed += w <= c && h <= c ? 1.0 : (w / c + 1) * (h / c + 1);  // the cells it overlaps, on average
    }
    const double cells = (std::floor(W / c) + 1) * (std::floor(H / c) + 1);
    const double per_query = std::pow((2 * shape.R + 2 * c) / c, 2);
    const double cost = per_query * (1 + 0.5 * listed / cells);
    if (cost < best_cost) {
      best_cost = cost;
      best = c;
    }
  }
  return best;
}

void DropCutter::Impl::build() {
  const auto nf = static_cast<std::int32_t>(mesh.F.rows());
  std::vector<CellBox> boxes(static_cast<std::size_t>(nf));                 // per triangle
  std::vector<std::array<double, 3>> planes(static_cast<std::size_t>(nf));  // zp, gx, gy
#pragma omp parallel for schedule(static) if (nf > kSerialBelow)
  for (std::int32_t f = 0; f < nf; ++f) {
    const auto fi = static_cast<Eigen::Index>(f);
    double bx0 = kInf, by0 = kInf, bx1 = -kInf, by1 = -kInf, bz = -kInf;
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto v = static_cast<Eigen::Index>(mesh.F(fi, k));
      bx0 = std::min(bx0, mesh.V(v, 0));
      bx1 = std::max(bx1, mesh.V(v, 0));
      by0 = std::min(by0, mesh.V(v, 1));
      by1 = std::max(by1, mesh.V(v, 1));
      bz = std::max(bz, mesh.V(v, 2));
    }
    const CellBox box{round_down(bx0), round_down(by0), round_up(bx1), round_up(by1), round_up(bz)};
    boxes[static_cast<std::size_t>(f)] = box;
    // Plane z = zA + gx·(x − xA) + gy·(y − yA); facet value = plane(axis) + a·|g| + r·(1/nz − 1).
    const Eigen::Vector3d A = mesh.V.row(static_cast<Eigen::Index>(mesh.F(fi, 0))).transpose();
    const Eigen::Vector3d B = mesh.V.row(static_cast<Eigen::Index>(mesh.F(fi, 1))).transpose();
    const Eigen::Vector3d C = mesh.V.row(static_cast<Eigen::Index>(mesh.F(fi, 2))).transpose();
    Eigen::Vector3d n = (B - A).cross(C - A);
    if (n.z() < 0) n = -n;
    const double len = n.norm();
    std::array<double, 3> pl{kInf, 0, 0};
    if (len > 0 && n.z() > 1e-12 * len) {
      const double gx = -n.x() / n.z(), gy = -n.y() / n.z();
      const double k = shape.a * std::hypot(gx, gy) + shape.r * (len / n.z() - 1);
      pl = {A.z() + gx * (static_cast<double>(box.x0) - A.x()) + gy * (static_cast<double>(box.y0) - A.y()) + k, gx,
            gy};
    }
    planes[static_cast<std::size_t>(f)] = pl;
  }
  double X0 = kInf, Y0 = kInf, X1 = -kInf, Y1 = -kInf;
  for (const CellBox& b : boxes) {
    X0 = std::min(X0, static_cast<double>(b.x0));
    Y0 = std::min(Y0, static_cast<double>(b.y0));
    X1 = std::max(X1, static_cast<double>(b.x1));
    Y1 = std::max(Y1, static_cast<double>(b.y1));
  }
  const double W = X1 - X0, H = Y1 - Y0;
  cs = cell_side(boxes, W, H);
  const double max_cells = 2.0 * static_cast<double>(nf) + 64;
  while ((std::floor(W / cs) + 1) * (std::floor(H / cs) + 1) > max_cells) cs *= 1.25;
  x0 = X0;
  y0 = Y0;
  inv_cs = 1 / cs;
  nx = static_cast<int>(std::floor(W / cs)) + 1;
  ny = static_cast<int>(std::floor(H / cs)) + 1;
  const auto ncell = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);

  // Counting sort of (cell, triangle) pairs, in triangle order: deterministic.
  start.assign(ncell + 1, 0);
  for (const CellBox& b : boxes) {
    const CellRange cr = cells_of(b);
    for (int iy = cr.iy0; iy <= cr.iy1; ++iy)
      for (int ix = cr.ix0; ix <= cr.ix1; ++ix) ++start[static_cast<std::size_t>(iy * nx + ix) + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  entries.resize(static_cast<std::size_t>(start[ncell]));
  {
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::int32_t f = 0; f < nf; ++f) {
      const CellBox& b = boxes[static_cast<std::size_t>(f)];
      const CellRange cr = cells_of(b);
      const std::int32_t tag = cr.big ? -f - 1 : f;
      const auto& pl = planes[static_cast<std::size_t>(f)];
      for (int iy = cr.iy0; iy <= cr.iy1; ++iy)
        for (int ix = cr.ix0; ix <= cr.ix1; ++ix)
          entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(iy * nx + ix)]++)] = {b, tag, pl[0], pl[1],
                                                                                               pl[2]};
    }
  }
  cells.assign(ncell, CellBox{0, 0, 0, 0, 0});
  const auto ncell_i = static_cast<std::int64_t>(ncell);
#pragma omp parallel for schedule(dynamic, 256) if (ncell_i > kSerialBelow)
  for (std::int64_t ci = 0; ci < ncell_i; ++ci) {
    const auto c = static_cast<std::size_t>(ci);
    const auto b = entries.begin() + start[c], e = entries.begin() + start[c + 1];
    std::sort(b, e, [](const FaceEntry& p, const FaceEntry& q) {
      return p.box.zmax != q.box.zmax ? p.box.zmax > q.box.zmax : p.tri < q.tri;  // any fixed order
    });
    if (b == e) continue;
    CellBox u = b->box;
    for (auto it = b + 1; it != e; ++it) {
      const CellBox& t = it->box;
      u.x0 = std::min(u.x0, t.x0);
      u.y0 = std::min(u.y0, t.y0);
      u.x1 = std::max(u.x1, t.x1);
      u.y1 = std::max(u.y1, t.y1);
      u.zmax = std::max(u.zmax, t.zmax);
    }
    cells[c] = u;
  }
}

namespace {
double box_dist2(const CellBox& b, double x, double y) {
  const double dx = std::max({static_cast<double>(b.x0) - x, x - static_cast<double>(b.x1), 0.0});
  const double dy = std::max({static_cast<double>(b.y0) - y, y - static_cast<double>(b.y1), 0.0});
  return dx * dx + dy * dy;
}
}  // namespace

void DropCutter::Impl::query(double x, double y, std::int32_t hint, Best& best) const {
  const double R = shape.R;
  const double qx0 = x - R, qx1 = x + R, qy0 = y - R, qy1 = y + R;
  if (hint >= 0 && hint < mesh.F.rows()) eval_face(shape, mesh, hint, x, y, best);
  struct Cand {
    double ub;
    int ix, iy;
  };
  std::array<Cand, 64> cand{};  // ≥ 7×7: see the index comment
  std::size_t nc = 0;
  // Small triangles are listed by their centre, at most half a cell from their box's edges.
  const double m = 0.5 * cs;
  const int ix0 = cell_x(qx0 - m), ix1 = cell_x(qx1 + m), iy0 = cell_y(qy0 - m), iy1 = cell_y(qy1 + m);
  for (int iy = iy0; iy <= iy1; ++iy)
    for (int ix = ix0; ix <= ix1; ++ix) {
      const auto c = static_cast<std::size_t>(iy * nx + ix);
      if (start[c] == start[c + 1]) continue;
      const double d2 = box_dist2(cells[c], x, y);
      if (d2 > shape.R2 || !shape.can_beat(static_cast<double>(cells[c].zmax), d2, best.z)) continue;
      const double ub = static_cast<double>(cells[c].zmax) - shape.h(std::sqrt(d2));
      if (ub <= best.z - kPruneSlack) continue;
      // Insertion by descending bound (ties: row-major order, already the visiting order).
      MILLNET_ASSERT(nc < cand.size(), "drop-cutter query visits more cells than the index allows");
      std::size_t k = nc++;
      while (k > 0 && cand[k - 1].ub < ub) {
        cand[k] = cand[k - 1];
        --k;
      }
      cand[k] = {ub, ix, iy};
    }
  for (std::size_t k = 0; k < nc; ++k) {
    const Cand& cd = cand[k];
    if (cd.ub <= best.z - kPruneSlack) break;
    const auto c = static_cast<std::size_t>(cd.iy * nx + cd.ix);
    for (auto i = start[c]; i < start[c + 1]; ++i) {
      const FaceEntry& en = entries[static_cast<std::size_t>(i)];
      const CellBox& b = en.box;
      if (static_cast<double>(b.zmax) <= best.z - kPruneSlack) break;
      const double bx0 = static_cast<double>(b.x0), by0 = static_cast<double>(b.y0), bx1 = static_cast<double>(b.x1),
                   by1 = static_cast<double>(b.y1);
      if (bx0 > qx1 || bx1 < qx0 || by0 > qy1 || by1 < qy0) continue;
      std::int32_t f = en.tri;
      if (f < 0) {  // big: handled in the cell of the lower-left corner of (box ∩ query square)
        if (cell_x(std::max(bx0, qx0)) != cd.ix || cell_y(std::max(by0, qy0)) != cd.iy) continue;
        f = -f - 1;
      }
      const double d2 = box_dist2(b, x, y);
      if (d2 > shape.R2 || !shape.can_beat(static_cast<double>(b.zmax), d2, best.z)) continue;
      // Plane bound, with room for its rounding (steep planes have large gx, gy).
      const double tx = en.gx * (x - bx0), ty = en.gy * (y - by0);
      if (en.zp + tx + ty + 1e-12 * (std::abs(en.zp) + std::abs(tx) + std::abs(ty)) <= best.z - kPruneSlack) continue;
      eval_face(shape, mesh, f, x, y, best);
    }
  }
}

void check_finishing_cutter(const Cutter& cutter) {
  cutter.check();
  if (cutter.type == CutterType::Drill)
    throw Error("cutter: " + cutter.describe() +
                " is a drill: a surface is finished with a ball, bull-nose or flat end mill");
}

DropCutter::DropCutter(const ingest::Mesh& mesh, const Cutter& cutter) {
  check_finishing_cutter(cutter);
  ingest::validate(mesh, "drop-cutter mesh");
  impl_ = std::make_unique<Impl>(mesh, cutter);
  impl_->build();
}
DropCutter::~DropCutter() = default;
DropCutter::DropCutter(DropCutter&&) noexcept = default;
DropCutter& DropCutter::operator=(DropCutter&&) noexcept = default;

const Cutter& DropCutter::cutter() const { return impl_->cutter; }

CLPoint DropCutter::drop(double x, double y) const { return drop(x, y, -1); }

CLPoint DropCutter::drop(double x, double y, std::int32_t hint) const {
  Best b;
  impl_->query(x, y, hint, b);
  return to_cl(b, x, y);
}

std::vector<CLPoint> DropCutter::drop(const std::vector<Eigen::Vector2d>& xy) const {
  // Fixed blocks (not per-thread chunks) so that the triangle tried first — the previous point's
  // contact — and thus every result is the same for any number of threads.
  constexpr std::int64_t kBlock = 256;
  const auto n = static_cast<std::int64_t>(xy.size());
  std::vector<CLPoint> out(xy.size());
  const std::int64_t nblocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(dynamic, 1) if (nblocks > 1)
  for (std::int64_t bk = 0; bk < nblocks; ++bk) {
    std::int32_t hint = -1;
    for (std::int64_t i = bk * kBlock; i < std::min(n, (bk + 1) * kBlock); ++i) {
      const auto u = static_cast<std::size_t>(i);
      Best b;
      impl_->query(xy[u].x(), xy[u].y(), hint, b);
      hint = b.tri;
      out[u] = to_cl(b, xy[u].x(), xy[u].y());
    }
  }
  return out;
}

std::vector<double> DropCutter::drop_grid(double x0, double y0, double step, int nx, int ny) const {
  if (nx < 0 || ny < 0 || !std::isfinite(step) || !std::isfinite(x0) || !std::isfinite(y0))
    throw Error("drop_grid: need nx, ny >= 0 and finite x0, y0, step");
  std::vector<double> out(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
#pragma omp parallel for schedule(dynamic, 1) if (static_cast <std::int64_t>(nx) * ny > 512)
  for (int i = 0; i < ny; ++i) {
    std::int32_t hint = -1;
    const double y = y0 + i * step;
    for (int j = 0; j < nx; ++j) {
      Best b;
      impl_->query(x0 + j * step, y, hint, b);
      hint = b.tri;
      out[static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j)] = b.z;
    }
  }
  return out;
}

CLPoint drop_brute_force(const ingest::Mesh& mesh, const Cutter& cutter, double x, double y) {
  check_finishing_cutter(cutter);
  const Shape sh(cutter);
  Best b;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) eval_face(sh, mesh, static_cast<std::int32_t>(f), x, y, b);
  return to_cl(b, x, y);
}

}  // namespace millnet::finish
