// The exact lower envelopes of a cutter swept along one primitive, at one cell, per cutter shape
// (the closed forms are listed in sweep.cpp), the scalar row loop over them, and the choice of
// kernel per primitive and cutter: the branch-free rows of sweep_vector_rows.cpp for ball and
// flat lines, the scalar envelopes for the rest.
#include "sweep_internal.hpp"

namespace millnet::simulate::sweep {

namespace {

double env_line_ball(const Seg& g, const Profile& P, double px, double py) {
  const double wx = px - g.ax, wy = py - g.ay;
  if (g.L > tol::xy_length_mm) {
    // h(t) is convex: when the infinite cylinder's contact lies within the segment it is the
    // minimum, otherwise the end sphere on the side of the contact is (its disk then reaches p).
    const double q = wx * g.uy - wy * g.ux;
    const double q2 = q * q;
    if (q2 > P.R2) return kInf;
    const double s = wx * g.ux + wy * g.uy;
    const double zeta = g.m * s - g.sq1m * std::sqrt(P.R2 - q2);  // sphere-centre line frame
    const double sstar = (s + g.m * zeta) * g.inv1m2;             // contact along the axis
    if (sstar >= 0 && sstar <= g.L) return g.az + P.R + zeta;
    if (sstar < 0) {
      if (g.skip_start) return kInf;  // the previous primitive applied this sphere
      const double w2 = wx * wx + wy * wy;
      return w2 <= P.R2 ? g.az + P.R - std::sqrt(P.R2 - w2) : kInf;
    }
    if (g.skip_end) return kInf;  // the next primitive applies this sphere
    const double vx = px - g.bx, vy = py - g.by;
    const double v2 = vx * vx + vy * vy;
    return v2 <= P.R2 ? g.bz + P.R - std::sqrt(P.R2 - v2) : kInf;
  }
  const double w2 = wx * wx + wy * wy;  // vertical move: the lower end
  return w2 <= P.R2 ? g.zmin + P.R - std::sqrt(P.R2 - w2) : kInf;
}

// The t-interval on which the cutter's disk covers p; false when it never does. Out of line, as
// the compiler chose when the kernels shared one file with the driver: inlined, it changes where
// GCC contracts a·b + c into FMAs in env_line_generic, and so the last bit of the heights a bull
// or drill line leaves (issue 36: the split kept every output byte-identical).
[[gnu::noinline]] bool cover_interval(const Seg& g, const Profile& P, double wx, double wy, double& t0, double& t1) {
  const double w2 = wx * wx + wy * wy;
  if (g.L2 <= tol::xy_length_mm * tol::xy_length_mm) {
    if (w2 > P.R2) return false;
    t0 = 0;
    t1 = 1;
    return true;
  }
  const double wd = wx * g.dx + wy * g.dy;
  const double disc = wd * wd - g.L2 * (w2 - P.R2);
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  t0 = (wd - sq) / g.L2;
  t1 = (wd + sq) / g.L2;
  if (t1 < 0 || t0 > 1) return false;
  t0 = std::max(t0, 0.0);
  t1 = std::min(t1, 1.0);
  return true;
}

double env_line_flat(const Seg& g, const Profile& P, double px, double py) {
  double t0 = 0, t1 = 0;
  if (!cover_interval(g, P, px - g.ax, py - g.ay, t0, t1)) return kInf;
  return g.dz > 0 ? g.az + g.dz * t0 : g.az + g.dz * t1;
}

double env_line_generic(const Seg& g, const Profile& P, double px, double py) {
  const double wx = px - g.ax, wy = py - g.ay;
  double t0 = 0, t1 = 0;
  if (!cover_interval(g, P, wx, wy, t0, t1)) return kInf;
  const auto h = [&](double t) {
    const double ex = wx - t * g.dx, ey = wy - t * g.dy;
    return g.az + g.dz * t + P.f(std::min(std::sqrt(ex * ex + ey * ey), P.R));
  };
  double best = std::min(h(t0), h(t1));
  constexpr double kG = 0.6180339887498949;
  double lo = t0, hi = t1;
  double x1 = hi - kG * (hi - lo), x2 = lo + kG * (hi - lo);
  double f1 = h(x1), f2 = h(x2);
  for (int k = 0; k < 64; ++k) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kG * (hi - lo);
      f1 = h(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kG * (hi - lo);
      f2 = h(x2);
    }
  }
  return std::min({best, f1, f2});
}

double env_arc(const Seg& g, const Profile& P, double px, double py) {
  const double rx = px - g.cx, ry = py - g.cy;
  const double rho = std::sqrt(rx * rx + ry * ry);
  double d;
  if (rho < tol::at_centre_mm) {
    d = g.rho0;
  } else if (in_sweep(g, std::atan2(ry, rx))) {
    d = std::abs(rho - g.rho0);
  } else {
    d = std::min(std::hypot(px - g.ax, py - g.ay), std::hypot(px - g.bx, py - g.by));
  }
  if (d > P.R) return kInf;
  return g.az + P.f(d);
}

/// The axial engagement at a cell (px, py) whose stock `before` the primitive lowers by `removed`:
/// the stock above the tip where the cutter's disk first covers the cell (planar arcs: the tip's
/// constant height), at least the height removed up to the cutter's radius, at most the height removed.
double cell_engagement(const Seg& g, const Profile& P, double px, double py, double before, double removed) {
  double t = 0, t1 = 0;
  if (g.type != SegType::Arc && !cover_interval(g, P, px - g.ax, py - g.ay, t, t1)) t = 0;
  const double tip = g.type == SegType::Arc ? g.az : g.az + g.dz * t;
  return std::max(std::min(removed, before - tip), std::min(removed, P.R));
}

template <class Env>
void sweep_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z, std::uint32_t* stamp,
               double& item_cut, double& item_engage, std::uint64_t& visited, Env env) {
  const double y = spec.y(iy);
  Span spans[2];
  const int n = row_spans(g, P.R, y, spans);
  for (int k = 0; k < n; ++k) {
    std::size_t i0 = 0, i1 = 0;
    if (!cell_range(spans[k].lo, spans[k].hi, spec.x0, spec.cell, spec.nx, i0, i1)) continue;
    visited += i1 - i0 + 1;
    double* zr = z + iy * spec.nx;
    std::uint32_t* sr = stamp + iy * spec.nx;
    for (std::size_t ix = i0; ix <= i1; ++ix) {
      const double old = zr[ix];
      if (old <= g.zmin) continue;  // the cutter never reaches below its lowest tip height
      const double h = env(g, P, spec.x(ix), y);
      if (h < old) {
        zr[ix] = h;
        sr[ix] = g.serial;
        item_cut = std::max(item_cut, old - h);
        if (old - h > item_engage)
          item_engage = std::max(item_engage, cell_engagement(g, P, spec.x(ix), y, old, old - h));
      }
    }
  }
}

}  // namespace

void sweep_rows(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t row0, std::size_t row1, double* z,
                std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited, RowTops* tops) {
  for (std::size_t iy = row0; iy <= row1; ++iy) {
    if (g.type == SegType::Arc) {
      sweep_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited, env_arc);
    } else if (P.type == tooling::CutterType::Ball && g.L > tol::xy_length_mm) {
      ball_line_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited, tops);
    } else if (P.type == tooling::CutterType::Ball) {
      sweep_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited, env_line_ball);
    } else if (P.type == tooling::CutterType::Flat && g.L > tol::xy_length_mm) {
      flat_line_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited);
    } else if (P.type == tooling::CutterType::Flat) {
      sweep_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited, env_line_flat);
    } else {
      sweep_row(g, P, spec, iy, z, stamp, item_cut, item_engage, visited, env_line_generic);
    }
  }
}

}  // namespace millnet::simulate::sweep
