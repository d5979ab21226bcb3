#include "millnet/ingest/heightfield.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace millnet::ingest {

namespace {

// Rows per band: a band is owned by one thread, so z-buffer writes never race. Fixed (not derived
// from the thread count) so that the work split — and anything that could depend on it — is the
// same for any number of threads; max() is order-independent anyway.
constexpr int kBandRows = 16;
constexpr double kEps = tol::raster_edge_eps;

struct Frame {
  double x0, y0, sx, sy;
  int nx, ny;
};

// The z-buffer restricted to one band of rows [row_lo, row_hi].
struct BandBuffer {
  double* z;
  std::uint8_t* hit;
  int nx, row_lo, row_hi;
  void put(int i, int j, double zv) const {
    const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j);
    if (zv > z[k]) z[k] = zv;
    hit[k] = 1;
  }
};

struct P {
  double u, v, z;
};

// A segment's top in XY (a vertical triangle's edge): raster points within kEps of the segment
// take the segment's z at their projection. Walks the dominant axis: O(segment length in steps).
void raster_segment(const P& a, const P& b, const BandBuffer& buf, int ncols, int nrows) {
  const double du = b.u - a.u, dv = b.v - a.v;
  const double len2 = du * du + dv * dv;
  auto try_point = [&](int i, int j) {
    if (i < buf.row_lo || i > buf.row_hi || j < 0 || j >= ncols || i >= nrows) return;
    const double pu = j - a.u, pv = i - a.v;
    double t = len2 > 0 ? (pu * du + pv * dv) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double eu = pu - t * du, ev = pv - t * dv;
    if (eu * eu + ev * ev > kEps * kEps) return;
    const double zv = len2 > 0 ? a.z + t * (b.z - a.z) : std::max(a.z, b.z);
    buf.put(i, j, std::clamp(zv, std::min(a.z, b.z), std::max(a.z, b.z)));
  };
  if (len2 <= kEps * kEps) {  // the edge is vertical itself: one raster point at most
    try_point(static_cast<int>(std::lround(a.v)), static_cast<int>(std::lround(a.u)));
    return;
  }
  if (std::abs(du) >= std::abs(dv)) {
    const int j0 = std::max(0, static_cast<int>(std::ceil(std::min(a.u, b.u) - kEps)));
    const int j1 = std::min(ncols - 1, static_cast<int>(std::floor(std::max(a.u, b.u) + kEps)));
    for (int j = j0; j <= j1; ++j) {
      const double t = std::clamp((j - a.u) / du, 0.0, 1.0);
      try_point(static_cast<int>(std::lround(a.v + t * dv)), j);
    }
  } else {
    const int i0 = std::max(buf.row_lo, static_cast<int>(std::ceil(std::min(a.v, b.v) - kEps)));
    const int i1 = std::min(buf.row_hi, static_cast<int>(std::floor(std::max(a.v, b.v) + kEps)));
    for (int i = i0; i <= i1; ++i) {
      const double t = std::clamp((i - a.v) / dv, 0.0, 1.0);
      try_point(i, static_cast<int>(std::lround(a.u + t * du)));
    }
  }
}

// One triangle into the band: every raster point of its XY bounding box (clipped to the band) is
// tested against the three edge functions, inclusive with kEps (in raster units) so that points
// on shared edges/vertices are never missed whatever the rounding. O(bbox points in the band).
void raster_triangle(P a, P b, P c, const BandBuffer& buf, int ncols, int nrows) {
  double area2 = (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
  const double lab2 = (b.u - a.u) * (b.u - a.u) + (b.v - a.v) * (b.v - a.v);
  const double lbc2 = (c.u - b.u) * (c.u - b.u) + (c.v - b.v) * (c.v - b.v);
  const double lca2 = (a.u - c.u) * (a.u - c.u) + (a.v - c.v) * (a.v - c.v);
  const double lmax2 = std::max({lab2, lbc2, lca2});
  if (std::abs(area2) <= tol::vertical_triangle_rel * lmax2 || lmax2 == 0.0) {
    // Vertical in XY: its top over the projected segment is the highest of its edges there.
    raster_segment(a, b, buf, ncols, nrows);
    raster_segment(b, c, buf, ncols, nrows);
    raster_segment(c, a, buf, ncols, nrows);
    return;
  }
  if (area2 < 0) {  // make it counter-clockwise: the edge functions are then ≥ 0 inside
    std::swap(b, c);
    area2 = -area2;
  }
  const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
  const int j0 = std::max(0, static_cast<int>(std::ceil(std::min({a.u, b.u, c.u}) - kEps)));
  const int j1 = std::min(ncols - 1, static_cast<int>(std::floor(std::max({a.u, b.u, c.u}) + kEps)));
  const int i0 = std::max(buf.row_lo, static_cast<int>(std::ceil(std::min({a.v, b.v, c.v}) - kEps)));
  const int i1 = std::min({buf.row_hi, nrows - 1, static_cast<int>(std::floor(std::max({a.v, b.v, c.v}) + kEps))});
  if (j0 > j1 || i0 > i1) return;
  // Edge k opposite vertex k: w_k(p) = cross(edge, p − edge start); inside ⇔ w_k ≥ −kEps·|edge|.
  const double e0u = c.u - b.u, e0v = c.v - b.v;  // b → c, opposite a
  const double e1u = a.u - c.u, e1v = a.v - c.v;  // c → a, opposite b
  const double e2u = b.u - a.u, e2v = b.v - a.v;  // a → b, opposite c
  const double t0 = -kEps * std::sqrt(lbc2), t1 = -kEps * std::sqrt(lca2), t2 = -kEps * std::sqrt(lab2);
  const double inv = 1.0 / area2;
  // Edge functions at the row's first column, then stepped by −e·v per column (the values differ
  // from a direct evaluation by rounding only, far below kEps).
  for (int i = i0; i <= i1; ++i) {
    const double pv = i, pu0 = j0;
    double w0 = e0u * (pv - b.v) - e0v * (pu0 - b.u);
    double w1 = e1u * (pv - c.v) - e1v * (pu0 - c.u);
    double w2 = e2u * (pv - a.v) - e2v * (pu0 - a.u);
    for (int j = j0; j <= j1; ++j, w0 -= e0v, w1 -= e1v, w2 -= e2v) {
      if (w0 < t0 || w1 < t1 || w2 < t2) continue;
      const double zv = (w0 * a.z + w1 * b.z + w2 * c.z) * inv;
      // Clamped: slightly outside points (within kEps) of steep triangles must not extrapolate.
      buf.put(i, j, std::clamp(zv, zlo, zhi));
    }
  }
}

// One triangle into the band, cell-max: every raster point whose cell (the square of one step
// centred on it, closed, widened by kEps) meets the triangle's XY projection takes the triangle's
// highest z over that square. The triangle is clipped in 3D by the cell's four vertical planes
// (Sutherland–Hodgman; a vertical triangle clips as well as any other) and the highest vertex of
// what is left is the maximum of the plane over it. O(cells under the widened bounding box).
void cell_triangle(const P& a, const P& b, const P& c, const BandBuffer& buf, int ncols, int nrows) {
  const double h = 0.5 + kEps;
  const int j0 = std::max(0, static_cast<int>(std::ceil(std::min({a.u, b.u, c.u}) - h)));
  const int j1 = std::min(ncols - 1, static_cast<int>(std::floor(std::max({a.u, b.u, c.u}) + h)));
  const int i0 = std::max(buf.row_lo, static_cast<int>(std::ceil(std::min({a.v, b.v, c.v}) - h)));
  const int i1 = std::min({buf.row_hi, nrows - 1, static_cast<int>(std::floor(std::max({a.v, b.v, c.v}) + h))});
  const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
  // A triangle clipped by 4 half-planes has at most 7 vertices.
  P poly[8], tmp[8];
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      int n = 3;
      poly[0] = a;
      poly[1] = b;
      poly[2] = c;
      // Keep the side where s·(coord − bound) ≤ 0, for u ≤ j+h, u ≥ j−h, v ≤ i+h, v ≥ i−h.
      for (int k = 0; k < 4 && n > 0; ++k) {
        const bool on_u = k < 2;
        const double bound = (on_u ? j : i) + (k % 2 == 0 ? h : -h);
        const double s = k % 2 == 0 ? 1.0 : -1.0;
        int m = 0;
        for (int e = 0; e < n; ++e) {
          const P& p = poly[e];
          const P& q = poly[(e + 1) % n];
          const double dp = s * ((on_u ? p.u : p.v) - bound), dq = s * ((on_u ? q.u : q.v) - bound);
          if (dp <= 0) tmp[m++] = p;
          if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
            const double t = dp / (dp - dq);
            tmp[m++] = P{p.u + t * (q.u - p.u), p.v + t * (q.v - p.v), p.z + t * (q.z - p.z)};
          }
        }
        n = m;
        std::copy(tmp, tmp + m, poly);
      }
      if (n == 0) continue;
      double zv = poly[0].z;
      for (int e = 1; e < n; ++e) zv = std::max(zv, poly[e].z);
      buf.put(i, j, std::clamp(zv, zlo, zhi));  // interpolation stays in range but for rounding
    }
}

/// The mesh's vertices in raster units (column u, row v, z in mm). O(#V).
std::vector<P> raster_points(const Mesh& mesh, const Frame& fr) {
  const auto nv = static_cast<std::ptrdiff_t>(mesh.V.rows());
  std::vector<P> pts(static_cast<std::size_t>(nv));
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < nv; ++k) {
    const auto ek = static_cast<Eigen::Index>(k);
    pts[static_cast<std::size_t>(k)] =
        P{(mesh.V(ek, 0) - fr.x0) / fr.sx, (mesh.V(ek, 1) - fr.y0) / fr.sy, mesh.V(ek, 2)};
  }
  return pts;
}

/// The triangles binned into bands of kBandRows raster rows (a triangle in every band its rows
/// meet, in index order): band b holds entries[offset[b] … offset[b + 1]).
struct Bands {
  std::vector<std::size_t> offset;
  std::vector<std::int32_t> entries;
};

Bands bin_triangles(const Mesh& mesh, const std::vector<P>& pts, const Frame& fr, bool cells) {
  // Row range of each triangle (−1 = covers no raster point): O(#F), each slot written once.
  const auto nf = static_cast<std::ptrdiff_t>(mesh.F.rows());
  std::vector<std::int32_t> rlo(static_cast<std::size_t>(nf)), rhi(static_cast<std::size_t>(nf));
  const std::int32_t* F = mesh.F.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t t = 0; t < nf; ++t) {
    const auto tu = static_cast<std::size_t>(t);
    const P& a = pts[static_cast<std::size_t>(F[3 * tu])];
    const P& b = pts[static_cast<std::size_t>(F[3 * tu + 1])];
    const P& c = pts[static_cast<std::size_t>(F[3 * tu + 2])];
    const double umin = std::min({a.u, b.u, c.u}), umax = std::max({a.u, b.u, c.u});
    const double vmin = std::min({a.v, b.v, c.v}), vmax = std::max({a.v, b.v, c.v});
    const double w = cells ? 0.5 + kEps : kEps;  // a cell reaches half a step beyond its point
    const double j0 = std::max(0.0, std::ceil(umin - w)), j1 = std::min(fr.nx - 1.0, std::floor(umax + w));
    const double i0 = std::max(0.0, std::ceil(vmin - w)), i1 = std::min(fr.ny - 1.0, std::floor(vmax + w));
    if (j0 > j1 || i0 > i1) {
      rlo[tu] = -1;
      rhi[tu] = -1;
    } else {
      rlo[tu] = static_cast<std::int32_t>(i0);
      rhi[tu] = static_cast<std::int32_t>(i1);
    }
  }
  // Counting sort, serial: O(#F + entries).
  const int nbands = (fr.ny + kBandRows - 1) / kBandRows;
  Bands bands;
  std::vector<std::size_t>& offset = bands.offset;
  offset.assign(static_cast<std::size_t>(nbands) + 1, 0);
  for (std::ptrdiff_t t = 0; t < nf; ++t) {
    const auto tu = static_cast<std::size_t>(t);
    if (rlo[tu] < 0) continue;
    for (int b = rlo[tu] / kBandRows; b <= rhi[tu] / kBandRows; ++b) ++offset[static_cast<std::size_t>(b) + 1];
  }
  for (std::size_t b = 0; b < static_cast<std::size_t>(nbands); ++b) offset[b + 1] += offset[b];
  bands.entries.resize(offset.back());
  std::vector<std::size_t> fill(offset.begin(), offset.end() - 1);
  for (std::ptrdiff_t t = 0; t < nf; ++t) {
    const auto tu = static_cast<std::size_t>(t);
    if (rlo[tu] < 0) continue;
    for (int b = rlo[tu] / kBandRows; b <= rhi[tu] / kBandRows; ++b)
      bands.entries[fill[static_cast<std::size_t>(b)]++] = static_cast<std::int32_t>(t);
  }
  return bands;
}

HeightField rasterize(const Mesh& mesh, const Frame& fr, bool cells) {
  validate(mesh, "rasterize_top");
  if (!(fr.sx > 0) || !(fr.sy > 0) || !std::isfinite(fr.sx) || !std::isfinite(fr.sy) || !std::isfinite(fr.x0) ||
      !std::isfinite(fr.y0))
    throw Error("rasterize_top: the raster step and origin must be finite and the step > 0");
  if (fr.nx < 1 || fr.ny < 1) throw Error("rasterize_top: the raster needs at least 1×1 points");
  const double npts = static_cast<double>(fr.nx) * static_cast<double>(fr.ny);
  if (npts > 4.0e8)
    throw Error("height-field raster: " + std::to_string(fr.nx) + " × " + std::to_string(fr.ny) +
                " points is more than 4e8; choose a coarser raster step (--raster, raster_mm)");

  HeightField f;
  f.x0 = fr.x0;
  f.y0 = fr.y0;
  f.step_x = fr.sx;
  f.step_y = fr.sy;
  f.nx = fr.nx;
  f.ny = fr.ny;
  const Box3 box = bounds(mesh);
  f.z_min = box.min.z();
  f.z_max = box.max.z();
  const std::size_t n = static_cast<std::size_t>(fr.nx) * static_cast<std::size_t>(fr.ny);
  f.z.assign(n, -std::numeric_limits<double>::infinity());
  f.hit.assign(n, 0);

  const std::vector<P> pts = raster_points(mesh, fr);
  const Bands bands = bin_triangles(mesh, pts, fr, cells);
  const std::int32_t* F = mesh.F.data();
  const int nbands = static_cast<int>(bands.offset.size()) - 1;
  // Each band is rasterized by one thread, its triangles in index order: O(Σ bbox points).
#pragma omp parallel for schedule(dynamic, 1)
  for (int b = 0; b < nbands; ++b) {
    const BandBuffer buf{f.z.data(), f.hit.data(), fr.nx, b * kBandRows, std::min(fr.ny, (b + 1) * kBandRows) - 1};
    for (std::size_t e = bands.offset[static_cast<std::size_t>(b)]; e < bands.offset[static_cast<std::size_t>(b) + 1];
         ++e) {
      const auto tu = static_cast<std::size_t>(bands.entries[e]);
      const P& pa = pts[static_cast<std::size_t>(F[3 * tu])];
      const P& pb = pts[static_cast<std::size_t>(F[3 * tu + 1])];
      const P& pc = pts[static_cast<std::size_t>(F[3 * tu + 2])];
      if (cells)
        cell_triangle(pa, pb, pc, buf, fr.nx, fr.ny);
      else
        raster_triangle(pa, pb, pc, buf, fr.nx, fr.ny);
    }
  }
  // Unhit points: the part's lowest z (documented fill value). O(raster points).
#pragma omp parallel for schedule(static) if (n > 65536)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n); ++k)
    if (!f.hit[static_cast<std::size_t>(k)]) f.z[static_cast<std::size_t>(k)] = f.z_min;
  return f;
}

}  // namespace

HeightField rasterize_top(const Mesh& mesh, double raster_mm, const WorkLimits& limits) {
  if (!(raster_mm > 0) || !std::isfinite(raster_mm))
    throw Error("height-field raster: the raster step (--raster, raster_mm) must be a finite number > 0, got " +
                format_double(raster_mm));
  validate(mesh, "rasterize_top");
  check_work(raster_work(mesh, raster_mm), limits);
  const Box3 box = bounds(mesh);
  Frame fr{box.min.x(), box.min.y(), raster_mm, raster_mm, 1, 1};
  const double w = box.max.x() - box.min.x(), h = box.max.y() - box.min.y();
  // Enough points that the step does not exceed raster_mm, then shrink the step so the raster
  // spans the footprint corner to corner (the 1e-9 keeps 100.0000000001 steps at 100).
  const double cx = std::ceil(w / raster_mm - 1e-9), cy = std::ceil(h / raster_mm - 1e-9);
  if (cx > 1e6 || cy > 1e6)
    throw Error("height-field raster: a " + format_double(w) + " × " + format_double(h) +
                " mm footprint at a step of " + format_double(raster_mm) +
                " mm makes more than 1e6 points per side; choose a coarser raster step (--raster, raster_mm)");
  if (w > 0) {
    fr.nx = static_cast<int>(cx) + 1;
    fr.sx = w / (fr.nx - 1);
  }
  if (h > 0) {
    fr.ny = static_cast<int>(cy) + 1;
    fr.sy = h / (fr.ny - 1);
  }
  return rasterize(mesh, fr, false);
}

WorkEstimate raster_work(double width_mm, double height_mm, double raster_mm, const std::string& what) {
  const double cx = std::ceil(width_mm / raster_mm - 1e-9), cy = std::ceil(height_mm / raster_mm - 1e-9);
  const double n = (std::max(cx, 0.0) + 1) * (std::max(cy, 0.0) + 1);
  return {"raster_mm " + format_size(raster_mm) + " mm over a " + format_size(width_mm) + " × " +
              format_size(height_mm) + " mm " + what,
          n, "height-field raster points", n * (sizeof(double) + sizeof(std::uint8_t))};
}

WorkEstimate raster_work(const Mesh& mesh, double raster_mm) {
  validate(mesh, "rasterize_top");
  const Box3 box = bounds(mesh);
  return raster_work(box.max.x() - box.min.x(), box.max.y() - box.min.y(), raster_mm, "mesh footprint");
}

HeightField rasterize_top(const Mesh& mesh, double x0, double y0, double step, int nx, int ny) {
  return rasterize(mesh, Frame{x0, y0, step, step, nx, ny}, false);
}

HeightField rasterize_top_cells(const Mesh& mesh, double x0, double y0, double step, int nx, int ny) {
  return rasterize(mesh, Frame{x0, y0, step, step, nx, ny}, true);
}

Grid resample(const HeightField& field, int n) {
  if (n < 2) throw Error("resample: the grid size n must be ≥ 2, got " + std::to_string(n));
  if (field.nx < 1 || field.ny < 1 ||
      field.z.size() != static_cast<std::size_t>(field.nx) * static_cast<std::size_t>(field.ny))
    throw Error("resample: the height field is empty or its z has the wrong size");
  Grid g;
  g.h.resize(n, n);
  g.footprint_x = field.width();
  g.footprint_y = field.height();
  // Fractional raster index of grid line k of n over m raster lines, and its bilinear weights.
  auto locate = [n](int k, int m, int& lo, double& t) {
    if (m == 1) {
      lo = 0;
      t = 0;
      return;
    }
    const double s = static_cast<double>(k) * (m - 1) / (n - 1);
    lo = std::min(static_cast<int>(std::floor(s)), m - 2);
    t = s - lo;
  };
  // O(n²).
  for (int r = 0; r < n; ++r) {
    int i;
    double ty;
    locate(r, field.ny, i, ty);
    const int i2 = field.ny == 1 ? i : i + 1;
    for (int c = 0; c < n; ++c) {
      int j;
      double tx;
      locate(c, field.nx, j, tx);
      const int j2 = field.nx == 1 ? j : j + 1;
      const double z0 = field.at(i, j) * (1 - tx) + field.at(i, j2) * tx;
      const double z1 = field.at(i2, j) * (1 - tx) + field.at(i2, j2) * tx;
      g.h(r, c) = z0 * (1 - ty) + z1 * ty - field.z_min;
    }
  }
  return g;
}

Eigen::MatrixXd height_matrix(const HeightField& field, double offset) {
  Eigen::MatrixXd m(field.ny, field.nx);
  for (int i = 0; i < field.ny; ++i)
    for (int j = 0; j < field.nx; ++j) m(i, j) = field.at(i, j) + offset;
  return m;
}

Grid sample_grid(const Mesh& mesh, double raster_mm, int n, const WorkLimits& limits) {
  return resample(rasterize_top(mesh, raster_mm, limits), n);
}

}  // namespace millnet::ingest
