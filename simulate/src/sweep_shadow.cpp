// The XY shadow of a swept primitive on one row of the z-map: the X intervals a kernel visits.
// A line's shadow is its band (a rectangle of half-width R along it) plus the disks at the ends
// it sweeps itself; an arc's is the ring |ρ − ρ0| ≤ R clipped to the arc's bounding box.
#include "sweep_internal.hpp"

namespace millnet::simulate::sweep {

namespace {

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

int line_spans(const Seg& g, double R, double y, Span out[2]) {
  Span s{0, 0};
  bool any = false;
  if (!g.skip_start) disk_span(g.ax, g.ay, R, y, s, any);
  if (!g.skip_end) disk_span(g.bx, g.by, R, y, s, any);
  if (g.L > tol::xy_length_mm) {  // the rectangle a ± R n, b ± R n (convex: its row cut is one interval)
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

int arc_spans(const Seg& g, double R, double y, Span out[2]) {
  const double dy = y - g.cy;
  const double ro = g.rho0 + R + tol::arc_shadow_margin_mm;
  if (dy * dy > ro * ro) return 0;
  const double wo = std::sqrt(ro * ro - dy * dy);
  const double ri = g.rho0 - R - tol::arc_shadow_margin_mm;
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

}  // namespace

int row_spans(const Seg& g, double R, double y, Span out[2]) {
  if (y < g.ylo || y > g.yhi) return 0;
  return g.type == SegType::Line ? line_spans(g, R, y, out) : arc_spans(g, R, y, out);
}

}  // namespace millnet::simulate::sweep
