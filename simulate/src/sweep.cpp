// The swept-cutter material removal: every move of a program becomes one or more swept primitives
// (a line segment of the tool tip, or a planar arc); each primitive lowers the cells under its XY
// shadow to the lower envelope of the cutter swept along it.
//
// Lower envelope at a cell p of a cutter whose tip moves c(t), t ∈ [0, 1]:
//     h(p) = min_t  c_z(t) + f(|p − c_xy(t)|)
// with f the cutter profile (convex, nondecreasing, +inf beyond R). Closed forms:
//  * ball, line: the swept solid is a capsule (sphere centres on a segment): min of the two end
//    spheres and of the lower surface of the tilted cylinder around the segment (when its contact
//    lies within the segment);
//  * flat, line: the disk covers p on an interval [t0, t1] of t (a quadratic), z is linear in t:
//    the lower end of that interval;
//  * bull, line: h(t) is convex on [t0, t1] (f convex nondecreasing, |p − c_xy(t)| convex), so a
//    golden-section search (64 steps, bracket shrunk by 0.618^64 ≈ 4e-14) plus the interval ends;
//  * any cutter, planar arc (constant Z): h = z + f(d) with d the XY distance from p to the arc,
//    exact (the nearest point of the arc is the radial projection when it lies in the sweep, else
//    an end point);
//  * helical arcs: chords with sagitta ≤ SweepOptions::helix_chord_tol_mm, each swept exactly.
#include "millnet/simulate/zmap.hpp"

#include "millnet/core/error.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace millnet::simulate {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr std::size_t kChunkRows = 8;  // rows per parallel work unit

struct Profile {
  tooling::CutterType type = tooling::CutterType::Ball;  // the cutter's shape()
  double R = 1;                                          // radius
  double R2 = 1;
  double rc = 1;    // corner radius (ball: R, flat and drill: 0)
  double a = 0;     // flat part of the bottom: R − rc
  double cone = 0;  // drill: 1 / tan(point angle / 2)

  // f(r) for 0 ≤ r ≤ R (callers ensure r ≤ R).
  [[nodiscard]] double f(double r) const {
    switch (type) {
      case tooling::CutterType::Flat: return 0;
      case tooling::CutterType::Ball: return R - std::sqrt(std::max(0.0, R2 - r * r));
      case tooling::CutterType::Bull: {
        if (r <= a) return 0;
        const double u = r - a;
        return rc - std::sqrt(std::max(0.0, rc * rc - u * u));
      }
      case tooling::CutterType::Drill: return r * cone;
    }
    return 0;
  }
};

// The kernels' form of a cutter that passed tooling::Cutter::check (the one owner of the checks).
Profile make_profile(const tooling::Cutter& c) {
  c.check();
  Profile p;
  p.type = c.shape();
  p.R = c.diameter / 2;
  p.R2 = p.R * p.R;
  p.rc = c.profile_corner_radius();
  p.a = p.R - p.rc;
  if (p.type == tooling::CutterType::Drill) p.cone = c.point_height() / p.R;
  return p;
}

enum class SegType : std::uint8_t { Line, Arc };

struct Seg {
  SegType type = SegType::Line;
  std::uint8_t kind = kLineKind;
  double ax = 0, ay = 0, az = 0, bx = 0, by = 0, bz = 0;
  // line: derived
  double dx = 0, dy = 0, dz = 0, L2 = 0, L = 0, ux = 0, uy = 0, m = 0, sq1m = 1, inv1m2 = 1;
  // The sphere at an end is applied by the neighbouring primitive (see link_caps).
  bool skip_start = false, skip_end = false;
  // planar arc
  double cx = 0, cy = 0, rho0 = 0, th0 = 0, sweep = 0, dir = 1;
  double zmin = 0;          // lowest tip height (no cell under it is lowered below it)
  double xlo = 0, xhi = 0;  // XY shadow bounding box
  double ylo = 0, yhi = 0;
  std::size_t item = 0;
  std::uint32_t serial = 0;
  std::size_t iy0 = 0, iy1 = 0;  // rows, inclusive
};

Seg make_line(const gcode::Point3& s, const gcode::Point3& e, double R) {
  Seg g;
  g.type = SegType::Line;
  g.ax = s[0];
  g.ay = s[1];
  g.az = s[2];
  g.bx = e[0];
  g.by = e[1];
  g.bz = e[2];
  g.dx = e[0] - s[0];
  g.dy = e[1] - s[1];
  g.dz = e[2] - s[2];
  g.L2 = g.dx * g.dx + g.dy * g.dy;
  g.L = std::sqrt(g.L2);
  if (g.L > 1e-9) {
    g.ux = g.dx / g.L;
    g.uy = g.dy / g.L;
    g.m = g.dz / g.L;
    g.sq1m = std::sqrt(1 + g.m * g.m);
    g.inv1m2 = 1 / (1 + g.m * g.m);
  }
  g.zmin = std::min(g.az, g.bz);
  g.xlo = std::min(g.ax, g.bx) - R;
  g.xhi = std::max(g.ax, g.bx) + R;
  g.ylo = std::min(g.ay, g.by) - R;
  g.yhi = std::max(g.ay, g.by) + R;
  return g;
}

// Angle in [0, 2π).
double wrap(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

bool in_sweep(const Seg& g, double phi) { return wrap(g.dir * (phi - g.th0)) <= g.sweep; }

// ---- envelopes --------------------------------------------------------------------------------

double env_line_ball(const Seg& g, const Profile& P, double px, double py) {
  const double wx = px - g.ax, wy = py - g.ay;
  if (g.L > 1e-9) {
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

// The t-interval on which the cutter's disk covers p; false when it never does.
bool cover_interval(const Seg& g, const Profile& P, double wx, double wy, double& t0, double& t1) {
  const double w2 = wx * wx + wy * wy;
  if (g.L2 <= 1e-18) {
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
  if (rho < 1e-12) {
    d = g.rho0;
  } else if (in_sweep(g, std::atan2(ry, rx))) {
    d = std::abs(rho - g.rho0);
  } else {
    d = std::min(std::hypot(px - g.ax, py - g.ay), std::hypot(px - g.bx, py - g.by));
  }
  if (d > P.R) return kInf;
  return g.az + P.f(d);
}

// ---- the XY shadow of a primitive on one row ------------------------------------------------

struct Span {
  double lo, hi;
};

void hull(Span& s, bool& any, double lo, double hi) {
  if (!any) {
    s = {lo, hi};
    any = true;
  } else {
    s.lo = std::min(s.lo, lo);
    s.hi = std::max(s.hi, hi);
  }
}

void disk_span(double cx, double cy, double R, double y, Span& s, bool& any) {
  const double dy = y - cy;
  if (dy * dy > R * R) return;
  const double w = std::sqrt(R * R - dy * dy);
  hull(s, any, cx - w, cx + w);
}

// Up to two X intervals of the row y covered by the primitive's shadow (a superset for arcs).
int row_spans(const Seg& g, double R, double y, Span out[2]) {
  if (y < g.ylo || y > g.yhi) return 0;
  if (g.type == SegType::Line) {
    Span s{0, 0};
    bool any = false;
    if (!g.skip_start) disk_span(g.ax, g.ay, R, y, s, any);
    if (!g.skip_end) disk_span(g.bx, g.by, R, y, s, any);
    if (g.L > 1e-9) {  // the rectangle a ± R n, b ± R n (convex: its row cut is one interval)
      const double nx = -g.uy * R, ny = g.ux * R;
      const double px[4] = {g.ax + nx, g.bx + nx, g.bx - nx, g.ax - nx};
      const double py[4] = {g.ay + ny, g.by + ny, g.by - ny, g.ay - ny};
      for (int i = 0; i < 4; ++i) {
        const int j = (i + 1) & 3;
        const double yi = py[i], yj = py[j];
        if ((y - yi) * (y - yj) > 0) continue;
        if (yi == yj) {
          hull(s, any, std::min(px[i], px[j]), std::max(px[i], px[j]));
        } else {
          const double x = px[i] + (y - yi) * (px[j] - px[i]) / (yj - yi);
          hull(s, any, x, x);
        }
      }
    }
    if (!any) return 0;
    out[0] = s;
    return 1;
  }
  // Planar arc: the ring |ρ − ρ0| ≤ R clipped to the shadow's bounding box.
  const double dy = y - g.cy;
  const double ro = g.rho0 + R + 1e-9;
  if (dy * dy > ro * ro) return 0;
  const double wo = std::sqrt(ro * ro - dy * dy);
  const double ri = g.rho0 - R - 1e-9;
  int n = 0;
  auto push = [&](double lo, double hi) {
    lo = std::max(lo, g.xlo);
    hi = std::min(hi, g.xhi);
    if (lo <= hi) out[n++] = {lo, hi};
  };
  if (ri > 0 && dy * dy < ri * ri) {
    const double wi = std::sqrt(ri * ri - dy * dy);
    push(g.cx - wo, g.cx - wi);
    push(g.cx + wi, g.cx + wo);
  } else {
    push(g.cx - wo, g.cx + wo);
  }
  return n;
}

std::size_t clamp_index(double v, std::size_t n) {
  if (v < 0) return 0;
  if (v >= static_cast<double>(n)) return n;  // caller treats n as "past the end"
  return static_cast<std::size_t>(v);
}

// Index range [first, last] of the cell centres within [lo, hi]; false when empty.
bool cell_range(double lo, double hi, double origin, double cell, std::size_t n, std::size_t& first,
                std::size_t& last) {
  const double a = std::ceil((lo - origin) / cell - 0.5 - 1e-9);
  const double b = std::floor((hi - origin) / cell - 0.5 + 1e-9);
  if (b < 0 || a > static_cast<double>(n) - 1 || a > b) return false;
  first = clamp_index(a, n);
  last = std::min(clamp_index(b, n), n - 1);
  return first <= last;
}

std::uint8_t kind_of(gcode::Motion m) {
  switch (m) {
    case gcode::Motion::Rapid: return kRapidKind;
    case gcode::Motion::Line: return kLineKind;
    default: return kArcKind;
  }
}

std::string where(const gcode::Program& p, std::size_t item) {
  if (item < p.source_line.size() && p.source_line[item] > 0) return "line " + std::to_string(p.source_line[item]);
  return "item " + std::to_string(item);
}

template <class Env>
void sweep_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z, std::uint32_t* stamp,
               double& item_cut, std::uint64_t& visited, Env env) {
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
      }
    }
  }
}

// At a joint where primitive A ends exactly where B starts (both feeds or both rapids), the
// sphere (cutter) at the joint is applied by one of them only, and the other skips the half of
// its end disk that lies outside its band. Exact: behind the start of a line that does not
// descend (dz ≥ 0) the distance and the height both grow with t, so the minimum there is at the
// joint; likewise beyond the end of a line that does not ascend. Only the visited cells shrink
// (by up to πR²/2 per primitive, a lot for the short chords of a finishing path).
void link_caps(std::vector<Seg>& segs) {
  for (std::size_t i = 0; i + 1 < segs.size(); ++i) {
    Seg& a = segs[i];
    Seg& b = segs[i + 1];
    if ((a.kind == kRapidKind) != (b.kind == kRapidKind)) continue;
    if (a.bx != b.ax || a.by != b.ay || a.bz != b.az) continue;
    if (b.type == SegType::Line && b.L > 1e-9 && b.dz >= 0) {
      b.skip_start = true;
    } else if (a.type == SegType::Line && a.L > 1e-9 && a.dz <= 0 && (b.type == SegType::Arc || b.L > 1e-9)) {
      // (never onto a vertical move: a retract would then be charged with the joint's cut)
      a.skip_end = true;
    }
  }
}

// Clip a row span of a ball line to the part of its shadow where env_line_ball can be finite.
// With skip_start the line does not descend (m ≥ 0); at a point behind a (axial coordinate
// s < 0) ζ ≤ 0, so s* = (s + mζ)/(1 + m²) < 0: every term has the sign of s, in floating point
// too, and the start sphere is the previous primitive's. With skip_end (m ≤ 0) a point beyond b
// (s > L) has s* ≥ s > L and the end sphere is the next one's. Either way the kernel yields +∞
// there and changes nothing, so those cells need not be visited: for the short chords of a
// finishing path (0.1–0.3 mm against a Ø2 ball) that is about a third of the end disk's cells.
// The clip keeps a margin of kClipMarginMm beyond the exact line s = 0 (or s = L).
constexpr double kClipMarginMm = 1e-6;

bool clip_to_live_band(const Seg& g, double y, Span& sp) {
  auto keep_side = [&](double px, double py, double sign) {
    // Keep the points with sign · ((x − px)·ux + (y − py)·uy) ≤ kClipMarginMm.
    const double c = sign * (y - py) * g.uy;
    const double a = sign * g.ux;
    if (a > 0) {
      sp.hi = std::min(sp.hi, px + (kClipMarginMm - c) / a);
    } else if (a < 0) {
      sp.lo = std::max(sp.lo, px + (kClipMarginMm - c) / a);
    } else if (c > kClipMarginMm) {
      sp.hi = sp.lo - 1;  // the whole row is outside
    }
  };
  if (g.skip_start) keep_side(g.ax, g.ay, -1);  // s ≥ −margin
  if (g.skip_end) keep_side(g.bx, g.by, +1);    // s − L ≤ margin
  return sp.lo <= sp.hi;
}

// Widen [i0, i1] to a whole number of kPadCells cells inside the row [0, nx), so that the kernel's
// vector loop has no scalar remainder (a fifth of the kernel's time for the 50–100 cell rows of a
// Ø2 ball at 0.02 mm). The kernel is the exact envelope at every cell, +∞ beyond the shadow, so
// the extra cells are evaluated and left as they are. (The cells a remainder loop used to take now
// go through the vector body, whose FMA contraction may round the last bit differently: the same
// for any thread count, not always the bits of before.)
constexpr std::size_t kPadCells = 8;  // doubles in an AVX-512 vector (two AVX2 vectors)

void pad_to_vector(std::size_t& i0, std::size_t& i1, std::size_t nx) {
  const std::size_t n = i1 - i0 + 1;
  std::size_t extra = (kPadCells - n % kPadCells) % kPadCells;
  const std::size_t right = std::min(extra, nx - 1 - i1);
  i1 += right;
  extra -= right;
  i0 -= std::min(extra, i0);
}

// The ball/line kernel of sweep_row, written without branches so that the compiler vectorises
// it (same closed form as env_line_ball; the ternaries select among the three candidates).
void ball_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, std::uint64_t& visited) {
  const double y = spec.y(iy);
  Span spans[2];
  int n = row_spans(g, P.R, y, spans);
  if (n == 1 && !clip_to_live_band(g, y, spans[0])) n = 0;
  // Locals: the stores below cannot alias them (keeps the loop vectorisable).
  const double ax = g.ax, bx = g.bx, az = g.az, bz = g.bz, ux = g.ux, uy = g.uy, m = g.m, sq1m = g.sq1m;
  const double inv = g.inv1m2, L = g.L, R = P.R, R2 = P.R2, x0 = spec.x0, cell = spec.cell;
  const double wy = y - g.ay, vy = y - g.by;
  const double qy = -wy * ux, sy = wy * uy;
  const bool use_a = !g.skip_start, use_b = !g.skip_end;
  const std::uint32_t serial = g.serial;
  for (int k = 0; k < n; ++k) {
    std::size_t i0 = 0, i1 = 0;
    if (!cell_range(spans[k].lo, spans[k].hi, spec.x0, spec.cell, spec.nx, i0, i1)) continue;
    pad_to_vector(i0, i1, spec.nx);
    visited += i1 - i0 + 1;
    double* zr = z + iy * spec.nx;
    std::uint32_t* sr = stamp + iy * spec.nx;
    double mx = item_cut;
    const int j0 = static_cast<int>(i0), j1 = static_cast<int>(i1);
#pragma omp simd reduction(max : mx)
    for (int ix = j0; ix <= j1; ++ix) {
      const double x = x0 + (static_cast<double>(ix) + 0.5) * cell;
      const double wx = x - ax, vx = x - bx;
      const double q = wx * uy + qy;
      const double s = wx * ux + sy;
      const double q2 = q * q;
      const double zeta = m * s - sq1m * std::sqrt(std::max(R2 - q2, 0.0));
      const double sstar = (s + m * zeta) * inv;
      const double w2 = wx * wx + wy * wy, v2 = vx * vx + vy * vy;
      // Off the cylinder the contact is the end sphere on its side: one square root for
      // whichever end that is.
      const bool behind = sstar < 0;
      const double e2 = behind ? w2 : v2;
      const double ez = behind ? az : bz;
      const double he = ez + R - std::sqrt(std::max(R2 - e2, 0.0));
      // Bitwise & on bools: no short-circuit control flow in the loop.
      const bool reach = q2 <= R2;
      const bool cyl = reach & (sstar >= 0) & (sstar <= L);
      const bool cap = reach & ((behind & use_a) | ((sstar > L) & use_b)) & (e2 <= R2);
      const double hc = az + R + zeta;
      const double h1 = cap ? he : kInf;
      const double h = cyl ? hc : h1;
      const double old = zr[ix];
      const bool lower = h < old;
      zr[ix] = lower ? h : old;
      sr[ix] = lower ? serial : sr[ix];
      const double d = old - h;
      mx = mx > d ? mx : d;
    }
    item_cut = mx;
  }
}

// The flat/line kernel, branch-free like ball_line_row (same closed form as env_line_flat).
void flat_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, std::uint64_t& visited) {
  const double y = spec.y(iy);
  Span spans[2];
  const int n = row_spans(g, P.R, y, spans);
  const double ax = g.ax, az = g.az, dx = g.dx, dy = g.dy, dz = g.dz, L2 = g.L2, inv = 1 / g.L2, R2 = P.R2;
  const double x0 = spec.x0, cell = spec.cell, wy = y - g.ay;
  const bool up = dz > 0;
  const std::uint32_t serial = g.serial;
  for (int k = 0; k < n; ++k) {
    std::size_t i0 = 0, i1 = 0;
    if (!cell_range(spans[k].lo, spans[k].hi, spec.x0, spec.cell, spec.nx, i0, i1)) continue;
    visited += i1 - i0 + 1;
    double* zr = z + iy * spec.nx;
    std::uint32_t* sr = stamp + iy * spec.nx;
    double mx = item_cut;
    const int j0 = static_cast<int>(i0), j1 = static_cast<int>(i1);
#pragma omp simd reduction(max : mx)
    for (int ix = j0; ix <= j1; ++ix) {
      const double x = x0 + (static_cast<double>(ix) + 0.5) * cell;
      const double wx = x - ax;
      const double w2 = wx * wx + wy * wy;
      const double wd = wx * dx + wy * dy;
      const double disc = wd * wd - L2 * (w2 - R2);
      const double sq = std::sqrt(std::max(disc, 0.0));
      const double t0 = (wd - sq) * inv, t1 = (wd + sq) * inv;
      const bool valid = (disc >= 0) & (t1 >= 0) & (t0 <= 1);
      const double t = up ? std::max(t0, 0.0) : std::min(t1, 1.0);
      const double hv = az + dz * t;
      const double h = valid ? hv : kInf;
      const double old = zr[ix];
      const bool lower = h < old;
      zr[ix] = lower ? h : old;
      sr[ix] = lower ? serial : sr[ix];
      const double d = old - h;
      mx = mx > d ? mx : d;
    }
    item_cut = mx;
  }
}

}  // namespace

double profile_height(const tooling::Cutter& cutter, double r) {
  const Profile p = make_profile(cutter);
  if (!(r >= 0)) r = std::abs(r);
  if (r > p.R) return kInf;
  return p.f(r);
}

class Sweeper {
public:
  static SweepResult run(ZMap& zm, const gcode::Program& program, const tooling::Cutter& cutter,
                         const SweepOptions& opt);
};

SweepResult Sweeper::run(ZMap& zm, const gcode::Program& program, const tooling::Cutter& cutter,
                         const SweepOptions& opt) {
  const Profile P = make_profile(cutter);
  if (!(opt.helix_chord_tol_mm > 0)) throw Error("simulate: helix chord tolerance must be > 0 mm");
  const GridSpec& spec = zm.spec_;
  const std::size_t nitems = program.items.size();
  if (static_cast<std::uint64_t>(zm.next_serial_) + nitems >= std::numeric_limits<std::uint32_t>::max())
    throw Error("simulate: too many moves on one z-map (move stamps overflow 32 bits)");

  SweepResult res;
  res.pass = zm.passes_.size();
  res.item_max_cut_mm.assign(nitems, 0);

  ZMap::Pass pass;
  pass.first_serial = zm.next_serial_;
  pass.items = nitems;
  pass.source_line = program.source_line;
  pass.across.assign(nitems, {0, 0, -1});

  // 1. Moves → primitives.
  std::vector<Seg> segs;
  gcode::Point3 pos = opt.start;
  const auto known = [](const gcode::Point3& p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  };
  for (std::size_t it = 0; it < nitems; ++it) {
    const auto* mv = std::get_if<gcode::Move>(&program.items[it]);
    if (!mv) continue;
    gcode::Point3 end = pos;
    for (int k = 0; k < 3; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      if (mv->axes & (1u << k)) {
        if (!std::isfinite(mv->to[ku])) throw Error("simulate: non-finite coordinate at " + where(program, it));
        end[ku] = mv->to[ku];
      }
    }
    const std::uint8_t kind = kind_of(mv->motion);
    (kind == kRapidKind ? res.rapid_moves : res.feed_moves) += 1;
    const std::uint32_t serial = pass.first_serial + static_cast<std::uint32_t>(it);
    if (!known(end)) {
      pos = end;
      continue;
    }
    const bool from_known = known(pos);
    const gcode::Point3 start = from_known ? pos : end;
    auto add = [&](Seg g) {
      g.kind = kind;
      g.item = it;
      g.serial = serial;
      segs.push_back(g);
    };
    const bool arc = kind == kArcKind && from_known;
    if (!arc) {
      const Seg g = make_line(start, end, P.R);
      add(g);
      const double len = std::sqrt(g.L2 + g.dz * g.dz);
      (kind == kRapidKind ? res.rapid_length_mm : res.feed_length_mm) += len;
      if (g.L > 1e-12) pass.across[it] = {-g.uy, g.ux, 0};
    } else {
      if (!std::isfinite(mv->center[0]) || !std::isfinite(mv->center[1]))
        throw Error("simulate: non-finite arc centre at " + where(program, it));
      const double cx = mv->center[0], cy = mv->center[1];
      const double rho0 = std::hypot(start[0] - cx, start[1] - cy);
      if (rho0 < 1e-9) throw Error("simulate: arc of zero radius at " + where(program, it));
      const double dir = mv->motion == gcode::Motion::ArcCCW ? 1.0 : -1.0;
      const double th0 = std::atan2(start[1] - cy, start[0] - cx);
      const double th1 = std::atan2(end[1] - cy, end[0] - cx);
      double sweep = wrap(dir * (th1 - th0));
      if (sweep < 1e-12) sweep = kTwoPi;  // same start and end: a full circle
      const double dz = end[2] - start[2];
      res.feed_length_mm += std::hypot(rho0 * sweep, dz);
      pass.across[it] = {cx, cy, 1};
      if (std::abs(dz) <= 1e-12) {
        Seg g;
        g.type = SegType::Arc;
        g.ax = start[0];
        g.ay = start[1];
        g.az = start[2];
        g.bx = end[0];
        g.by = end[1];
        g.bz = start[2];
        g.cx = cx;
        g.cy = cy;
        g.rho0 = rho0;
        g.th0 = th0;
        g.sweep = sweep;
        g.dir = dir;
        g.zmin = start[2];
        // Bounding box: the end points and the axis extremes inside the sweep.
        double xlo = std::min(start[0], end[0]), xhi = std::max(start[0], end[0]);
        double ylo = std::min(start[1], end[1]), yhi = std::max(start[1], end[1]);
        for (int q = 0; q < 4; ++q) {
          const double phi = q * std::numbers::pi / 2;
          if (!in_sweep(g, phi)) continue;
          const double x = cx + rho0 * std::cos(phi), y = cy + rho0 * std::sin(phi);
          xlo = std::min(xlo, x);
          xhi = std::max(xhi, x);
          ylo = std::min(ylo, y);
          yhi = std::max(yhi, y);
        }
        g.xlo = xlo - P.R;
        g.xhi = xhi + P.R;
        g.ylo = ylo - P.R;
        g.yhi = yhi + P.R;
        add(g);
      } else {  // helix: chords of sagitta ≤ tol
        const double tol = std::min(opt.helix_chord_tol_mm, rho0);
        const double max_step = 2 * std::acos(1 - tol / rho0);
        const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(sweep / max_step)));
        gcode::Point3 a = start;
        for (std::size_t k = 1; k <= n; ++k) {
          gcode::Point3 b = end;
          if (k < n) {
            const double f = static_cast<double>(k) / static_cast<double>(n);
            const double th = th0 + dir * sweep * f;
            b = {cx + rho0 * std::cos(th), cy + rho0 * std::sin(th), start[2] + dz * f};
          }
          add(make_line(a, b, P.R));
          a = b;
        }
      }
    }
    pos = end;
  }

  link_caps(segs);
  zm.passes_.push_back(std::move(pass));
  zm.next_serial_ += static_cast<std::uint32_t>(nitems);
  res.segments = segs.size();

  // 2. Rows of each primitive and the per-chunk lists (in program order).
  const std::size_t nchunks = (spec.ny + kChunkRows - 1) / kChunkRows;
  std::vector<std::vector<std::uint32_t>> chunk_segs(nchunks);
  if (segs.size() >= std::numeric_limits<std::uint32_t>::max()) throw Error("simulate: too many swept primitives");
  for (std::size_t s = 0; s < segs.size(); ++s) {
    Seg& g = segs[s];
    std::size_t c0 = 0, c1 = 0, r0 = 0, r1 = 0;
    if (!cell_range(g.xlo, g.xhi, spec.x0, spec.cell, spec.nx, c0, c1)) continue;
    if (!cell_range(g.ylo, g.yhi, spec.y0, spec.cell, spec.ny, r0, r1)) continue;
    g.iy0 = r0;
    g.iy1 = r1;
    for (std::size_t c = r0 / kChunkRows; c <= r1 / kChunkRows; ++c)
      chunk_segs[c].push_back(static_cast<std::uint32_t>(s));
  }

  // 3. Sweep, parallel over row chunks; each cell sees its primitives in program order.
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  std::vector<std::vector<double>> thread_cut(static_cast<std::size_t>(nthreads));
  std::uint64_t visited = 0;
  double* z = zm.z_.data();
  std::uint32_t* stamp = zm.stamp_.data();
  const auto nch = static_cast<std::ptrdiff_t>(nchunks);
#pragma omp parallel num_threads(nthreads) reduction(+ : visited)
  {
    auto& cut = thread_cut[static_cast<std::size_t>(omp_get_thread_num())];
    cut.assign(nitems, 0.0);
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t ci = 0; ci < nch; ++ci) {
      const auto c = static_cast<std::size_t>(ci);
      const std::size_t row0 = c * kChunkRows, row1 = std::min(spec.ny, row0 + kChunkRows) - 1;
      for (const std::uint32_t si : chunk_segs[c]) {
        const Seg& g = segs[si];
        const std::size_t a = std::max(row0, g.iy0), b = std::min(row1, g.iy1);
        double& item_cut = cut[g.item];
        for (std::size_t iy = a; iy <= b; ++iy) {
          if (g.type == SegType::Arc) {
            sweep_row(g, P, spec, iy, z, stamp, item_cut, visited, env_arc);
          } else if (P.type == tooling::CutterType::Ball && g.L > 1e-9) {
            ball_line_row(g, P, spec, iy, z, stamp, item_cut, visited);
          } else if (P.type == tooling::CutterType::Ball) {
            sweep_row(g, P, spec, iy, z, stamp, item_cut, visited, env_line_ball);
          } else if (P.type == tooling::CutterType::Flat && g.L > 1e-9) {
            flat_line_row(g, P, spec, iy, z, stamp, item_cut, visited);
          } else if (P.type == tooling::CutterType::Flat) {
            sweep_row(g, P, spec, iy, z, stamp, item_cut, visited, env_line_flat);
          } else {
            sweep_row(g, P, spec, iy, z, stamp, item_cut, visited, env_line_generic);
          }
        }
      }
    }
  }
  res.cells_visited = visited;

  // 4. Per-move depth of cut (max is exact, so the merge is thread-count independent).
  for (const auto& cut : thread_cut)
    for (std::size_t i = 0; i < cut.size(); ++i) res.item_max_cut_mm[i] = std::max(res.item_max_cut_mm[i], cut[i]);
  for (std::size_t i = 0; i < nitems; ++i) {
    const auto* mv = std::get_if<gcode::Move>(&program.items[i]);
    if (!mv) continue;
    const std::uint8_t k = kind_of(mv->motion);
    const double c = res.item_max_cut_mm[i];
    if (c > res.max_cut_mm[k]) {
      res.max_cut_mm[k] = c;
      res.max_cut_item[k] = i;
    }
    if (k == kRapidKind && c > opt.cut_eps_mm) res.cutting_rapids.push_back(i);
  }
  return res;
}

SweepResult machine(ZMap& zmap, const gcode::Program& program, const tooling::Cutter& cutter,
                    const SweepOptions& options) {
  return Sweeper::run(zmap, program, cutter, options);
}

}  // namespace millnet::simulate
