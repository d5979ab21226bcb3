// The branch-free rows of the two common kernels, ball and flat lines with an XY direction:
// written without branches so that the compiler vectorises them (the same closed forms as
// env_line_ball and env_line_flat in sweep_kernels.cpp; ternaries select among the candidates).
// They are most of the simulator's time (bench/bench_zmap.cpp).
#include "sweep_internal.hpp"

#include <algorithm>
#include <vector>

namespace millnet::simulate::sweep {

namespace {

// Clip a row span of a ball line to the part of its shadow where env_line_ball can be finite.
// With skip_start the line does not descend (m ≥ 0); at a point behind a (axial coordinate
// s < 0) ζ ≤ 0, so s* = (s + mζ)/(1 + m²) < 0: every term has the sign of s, in floating point
// too, and the start sphere is the previous primitive's. With skip_end (m ≤ 0) a point beyond b
// (s > L) has s* ≥ s > L and the end sphere is the next one's. Either way the kernel yields +∞
// there and changes nothing, so those cells need not be visited: for the short chords of a
// finishing path (0.1–0.3 mm against a Ø2 ball) that is about a third of the end disk's cells.
// The clip keeps a margin of tol::live_band_margin_mm beyond the exact line s = 0 (or s = L).
bool clip_to_live_band(const Seg& g, double y, Span& sp) {
  auto keep_side = [&](double px, double py, double sign) {
    // Keep the points with sign · ((x − px)·ux + (y − py)·uy) ≤ tol::live_band_margin_mm.
    const double c = sign * (y - py) * g.uy;
    const double a = sign * g.ux;
    if (a > 0) {
      sp.hi = std::min(sp.hi, px + (tol::live_band_margin_mm - c) / a);
    } else if (a < 0) {
      sp.lo = std::max(sp.lo, px + (tol::live_band_margin_mm - c) / a);
    } else if (c > tol::live_band_margin_mm) {
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

/// Whether one of the kPadCells cells from zr[i] stands above `floor`: a block at once (vectorised).
bool block_above(const double* zr, std::size_t i, double floor) {
  unsigned above = 0;
#pragma omp simd reduction(| : above)
  for (std::size_t k = 0; k < kPadCells; ++k) above |= zr[i + k] <= floor ? 0U : 1U;
  return above != 0;
}

/// The first cell of [i0, i1] that stands above `floor` (i1 + 1 if none): the row's bounds' blocks
/// (tr, nullable) first, then kPadCells cells at a time, then one by one. Where a pass leaves a
/// span below the next move's floor, this scan was a quarter of the kernel's time, one cell a step.
std::size_t first_above(const double* zr, const double* tr, std::size_t i0, std::size_t i1, double floor) {
  if (tr != nullptr)  // whole blocks of the row's bounds first
    while (i0 <= i1 && tr[i0 / RowTops::kCells] <= floor) i0 = (i0 / RowTops::kCells + 1) * RowTops::kCells;
  while (i0 + kPadCells <= i1 + 1 && !block_above(zr, i0, floor)) i0 += kPadCells;
  while (i0 <= i1 && zr[i0] <= floor) ++i0;
  return i0;
}

/// The last cell of [i0, i1] that stands above `floor`, given that zr[i0] does; as first_above.
std::size_t last_above(const double* zr, const double* tr, std::size_t i0, std::size_t i1, double floor) {
  if (tr != nullptr)  // the block of i0 stands above the floor
    while (tr[i1 / RowTops::kCells] <= floor) i1 = (i1 / RowTops::kCells) * RowTops::kCells - 1;
  while (i1 >= i0 + kPadCells && !block_above(zr, i1 + 1 - kPadCells, floor)) i1 -= kPadCells;
  while (zr[i1] <= floor) --i1;
  return i1;
}

/// The heights of the row's cells [i0, i1] before the line g lowers them, kept (per thread: the
/// chunks run in parallel) only where it may cut more than the cutter's radius there — the stock
/// above its lowest tip by more than that; elsewhere (nullptr) the engagement is the height removed.
const double* kept_heights(const Seg& g, const Profile& P, const double* zr, std::size_t i0, std::size_t i1) {
  double top = -kInf;
  const int j0 = static_cast<int>(i0), j1 = static_cast<int>(i1);
#pragma omp simd reduction(max : top)
  for (int ix = j0; ix <= j1; ++ix) top = top > zr[ix] ? top : zr[ix];
  if (!(top - g.zmin > P.R)) return nullptr;
  thread_local std::vector<double> buffer;
  buffer.assign(zr + i0, zr + i1 + 1);
  return buffer.data();
}

/// The lowest a ball swept along g can reach on the row at y, less tol::envelope_skip_margin_mm:
/// its lowest tip raised by its profile at the row's distance from the move's Y extent (every point
/// of the move is at least that far from every cell of the row); −∞ on a row R or more from it.
double row_floor(const Seg& g, const Profile& P, double y) {
  const double dy = std::max({std::min(g.ay, g.by) - y, y - std::max(g.ay, g.by), 0.0});
  if (!(dy < P.R)) return -kInf;
  return g.zmin + P.R - std::sqrt(P.R2 - dy * dy) - tol::envelope_skip_margin_mm;
}

/// The highest cell of block b of a row of nx cells.
double block_top(const double* zr, std::size_t b, std::size_t nx) {
  const int j0 = static_cast<int>(b * RowTops::kCells), j1 = static_cast<int>(std::min(nx, (b + 1) * RowTops::kCells));
  double top = -kInf;
#pragma omp simd reduction(max : top)
  for (int ix = j0; ix < j1; ++ix) top = top > zr[ix] ? top : zr[ix];
  return top;
}

}  // namespace

void RowTops::fill(const double* z, const GridSpec& spec, std::size_t r0, std::size_t r1) {
  row0 = r0;
  blocks = (spec.nx + kCells - 1) / kCells;
  top.resize((r1 - r0 + 1) * blocks);
  for (std::size_t iy = r0; iy <= r1; ++iy)  // O(cells of the rows)
    for (std::size_t b = 0; b < blocks; ++b) row(iy)[b] = block_top(z + iy * spec.nx, b, spec.nx);
}

double line_engagement(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, std::size_t i0,
                       std::size_t i1, const double* old, const double* z) {
  const double y = spec.y(iy), wy = y - g.ay;
  double out = 0;
  for (std::size_t ix = i0; ix <= i1; ++ix) {  // O(cells)
    const double before = old[ix - i0], removed = before - z[ix];
    if (!(removed > 0)) continue;
    // The first t at which the cutter's disk covers the cell: the tip's height there.
    const double wx = spec.x(ix) - g.ax;
    const double wd = wx * g.dx + wy * g.dy, w2 = wx * wx + wy * wy;
    const double disc = wd * wd - g.L2 * (w2 - P.R2);
    const double t = disc > 0 ? std::clamp((wd - std::sqrt(disc)) / g.L2, 0.0, 1.0) : 0.0;
    const double met = before - (g.az + g.dz * t);
    out = std::max(out, std::max(std::min(removed, met), std::min(removed, P.R)));
  }
  return out;
}

// The ball/line kernel, written without branches so that the compiler vectorises it (same closed
// form as env_line_ball; the ternaries select among the three candidates).
void ball_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited, RowTops* tops) {
  const double y = spec.y(iy);
  const double floor_row = row_floor(g, P, y);
  double* zr = z + iy * spec.nx;
  double* tr = tops != nullptr ? tops->row(iy) : nullptr;
  if (tr != nullptr) {  // every cell under the shadow below the floor: the row is left as it is
    double top = -kInf;
    for (std::size_t b = g.ix0 / RowTops::kCells; b <= g.ix1 / RowTops::kCells; ++b) top = std::max(top, tr[b]);
    if (top <= floor_row) {
      ++tops->rows_left;
      return;
    }
  }
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
    // The span's ends that stand below the row's floor cannot be lowered: left out (a pass on a
    // slope leaves most of the span behind it below the next move's floor). Exact: those cells keep
    // their heights and stamps, and their negative cuts count for nothing.
    i0 = first_above(zr, tr, i0, i1, floor_row);
    if (i0 > i1) continue;
    i1 = last_above(zr, tr, i0, i1, floor_row);
    pad_to_vector(i0, i1, spec.nx);
    visited += i1 - i0 + 1;
    std::uint32_t* sr = stamp + iy * spec.nx;
    double mx = item_cut, row_cut = 0;
    const int j0 = static_cast<int>(i0), j1 = static_cast<int>(i1);
    const double* old_z = kept_heights(g, P, zr, i0, i1);
#pragma omp simd reduction(max : mx, row_cut)
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
      row_cut = row_cut > d ? row_cut : d;
    }
    item_cut = mx;
    // Up to the cutter's radius the engagement is the height removed; above it, refined.
    const double e = old_z != nullptr && row_cut > P.R ? line_engagement(g, P, spec, iy, i0, i1, old_z, zr) : row_cut;
    item_engage = std::max(item_engage, e);
    if (tr != nullptr)
      for (std::size_t b = i0 / RowTops::kCells; b <= i1 / RowTops::kCells; ++b) tr[b] = block_top(zr, b, spec.nx);
  }
}

// The flat/line kernel, branch-free like ball_line_row (same closed form as env_line_flat).
void flat_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited) {
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
    double mx = item_cut, row_cut = 0;
    const int j0 = static_cast<int>(i0), j1 = static_cast<int>(i1);
    const double* old_z = kept_heights(g, P, zr, i0, i1);
#pragma omp simd reduction(max : mx, row_cut)
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
      row_cut = row_cut > d ? row_cut : d;
    }
    item_cut = mx;
    // Up to the cutter's radius the engagement is the height removed; above it, refined.
    const double e = old_z != nullptr && row_cut > P.R ? line_engagement(g, P, spec, iy, i0, i1, old_z, zr) : row_cut;
    item_engage = std::max(item_engage, e);
  }
}

}  // namespace millnet::simulate::sweep
