// Raster passes (strategy 2) and their scallop-height spacing (strategy 3).
#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::finish::detail {
using tooling::Cutter;
using tooling::CutterType;
namespace {

/// The pass frame: u along the passes, v across them.
struct PassFrame {
  Eigen::Vector2d u, v;
  double umin = 0, umax = 0, vmin = 0, vmax = 0;
};

PassFrame pass_frame(const Box& box, double angle_deg) {
  const double a = angle_deg * std::numbers::pi / 180.0;
  PassFrame f;
  f.u = Eigen::Vector2d(std::cos(a), std::sin(a));
  f.v = Eigen::Vector2d(-std::sin(a), std::cos(a));
  f.umin = f.vmin = std::numeric_limits<double>::infinity();
  f.umax = f.vmax = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(box.x0, box.y0), Eigen::Vector2d(box.x1, box.y0),
                                   Eigen::Vector2d(box.x1, box.y1), Eigen::Vector2d(box.x0, box.y1)}) {
    f.umin = std::min(f.umin, c.dot(f.u)), f.umax = std::max(f.umax, c.dot(f.u));
    f.vmin = std::min(f.vmin, c.dot(f.v)), f.vmax = std::max(f.vmax, c.dot(f.v));
  }
  return f;
}

/// The line v = const clipped to the box (Liang–Barsky); false when it misses the box.
bool clip(const PassFrame& f, const Box& box, double v, Eigen::Vector2d* a, Eigen::Vector2d* b) {
  const Eigen::Vector2d p0 = f.v * v + f.u * f.umin;
  const Eigen::Vector2d d = f.u * (f.umax - f.umin);
  double t0 = 0, t1 = 1;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {p0.x() - box.x0, box.x1 - p0.x(), p0.y() - box.y0, box.y1 - p0.y()};
  for (int i = 0; i < 4; ++i) {
    if (std::abs(p[i]) < 1e-15) {
      if (q[i] < -1e-9) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
  }
  if (t1 - t0 < 1e-12) return false;
  *a = p0 + t0 * d;
  *b = p0 + t1 * d;
  return true;
}

/// Largest XY spacing to the next pass whose 3D distance to this one (at equal u) stays within
/// d_max everywhere, a few secant-like shrink steps from d_max itself.
/// `here` holds the heights of the pass at v (every h0 along u; NaN off the box) and is replaced
/// by those of the pass chosen, so each pass is sampled once more, not twice.
double next_spacing(const Sampler& s, const PassFrame& f, const Box& box, double v, double d_max, double p_min,
                    double h0, std::vector<double>& here) {
  const auto nu = static_cast<std::ptrdiff_t>(std::ceil((f.umax - f.umin) / h0)) + 1;
  auto line = [&](double vv) {
    std::vector<double> z(static_cast<std::size_t>(nu), std::numeric_limits<double>::quiet_NaN());
#pragma omp parallel for schedule(dynamic, 64)
    for (std::ptrdiff_t j = 0; j < nu; ++j) {
      const Eigen::Vector2d q = f.v * vv + f.u * std::min(f.umax, f.umin + static_cast<double>(j) * h0);
      if (box.contains(q.x(), q.y())) z[static_cast<std::size_t>(j)] = s.z(q.x(), q.y());
    }
    return z;
  };
  if (here.empty()) here = line(v);
  double p = d_max;
  for (int iter = 0; iter < 8; ++iter) {
    std::vector<double> next = line(v + p);
    double worst = p;
    for (std::size_t j = 0; j < here.size(); ++j)
      if (!std::isnan(here[j]) && !std::isnan(next[j])) worst = std::max(worst, std::hypot(p, next[j] - here[j]));
    if (worst <= d_max * (1 + 1e-9) || p <= p_min || iter == 7) {
      here = std::move(next);
      return p;
    }
    p = std::max(p_min, p * d_max / worst * 0.98);
  }
  return p;
}

}  // namespace

double scallop_spacing(const Cutter& c, double h) {
  const double rc = c.corner_radius;
  const double flat = 2 * (c.radius() - rc);
  if (!(rc > 0)) return c.diameter;
  const double hh = std::min(h, rc);
  return flat + 2 * std::sqrt(hh * (2 * rc - hh));
}

std::vector<std::vector<Sample>> raster_lines(const Sampler& s, const Box& box, const FinishParams& p,
                                              bool adaptive_spacing) {
  const PassFrame f = pass_frame(box, p.raster_angle_deg);
  const double h0 = std::min(tol::initial_sample_mm, s.cutter().radius() / 4);
  // Pass positions across the box.
  std::vector<double> vs;
  if (!adaptive_spacing) {
    const auto n = static_cast<std::size_t>(std::ceil((f.vmax - f.vmin) / p.stepover_mm - 1e-9));
    for (std::size_t k = 0; k <= n; ++k)
      vs.push_back(std::min(f.vmax, f.vmin + static_cast<double>(k) * p.stepover_mm));
  } else {
    const double d_max = scallop_spacing(s.cutter(), p.scallop_mm);
    const double p_min = p.stepover_mm * tol::scallop_min_spacing_rel;
    double v = f.vmin;
    vs.push_back(v);
    std::vector<double> here;
    while (v < f.vmax - 1e-9) {
      const double step = next_spacing(s, f, box, v, d_max, p_min, h0, here);
      if (v + step > f.vmax) here.clear();  // the last pass sits on the edge, not where sampled
      v = std::min(f.vmax, v + step);
      vs.push_back(v);
    }
  }
  std::vector<std::vector<Sample>> lines(vs.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(vs.size()); ++k) {
    Eigen::Vector2d a, b;
    if (!clip(f, box, vs[static_cast<std::size_t>(k)], &a, &b)) continue;
    if (k % 2 == 1) std::swap(a, b);  // zigzag
    lines[static_cast<std::size_t>(k)] = sample_segment(s, a, b, h0, p.chord_tolerance_mm);
  }
  std::erase_if(lines, [](const auto& l) { return l.size() < 2; });
  return lines;
}

}  // namespace millnet::finish::detail
