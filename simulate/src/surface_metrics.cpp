// Scoring a machined z-map against the design surface: deviation, gouge, remaining material,
// scallop, and the Ra map with its histogram (definitions in zmap.hpp).
#include "millnet/core/error.hpp"
#include "millnet/simulate/zmap.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace millnet::simulate {

namespace {

// Ra (mm) of the samples e[k] (NaN skipped) at positions k = 0, 1, …: mean |e − LS line|.
// Returns NaN with fewer than 3 samples.
double profile_ra(const double* e, std::size_t n) {
  // Masked sums (a NaN sample weighs 0) so that both passes vectorise.
  double s0 = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  const auto m = static_cast<std::ptrdiff_t>(n);
#pragma omp simd reduction(+ : s0, sx, sy, sxx, sxy)
  for (std::ptrdiff_t k = 0; k < m; ++k) {
    const bool ok = !std::isnan(e[k]);
    const double w = ok ? 1.0 : 0.0, v = ok ? e[k] : 0.0, x = static_cast<double>(k);
    s0 += w;
    sx += w * x;
    sy += v;
    sxx += w * x * x;
    sxy += v * x;
  }
  if (s0 < 3) return std::numeric_limits<double>::quiet_NaN();
  const double den = s0 * sxx - sx * sx;
  const double b = den > 0 ? (s0 * sxy - sx * sy) / den : 0;
  const double a = (sy - b * sx) / s0;
  double acc = 0;
#pragma omp simd reduction(+ : acc)
  for (std::ptrdiff_t k = 0; k < m; ++k) {
    const bool ok = !std::isnan(e[k]);
    const double d = std::abs(e[k] - (a + b * static_cast<double>(k)));
    acc += ok ? d : 0.0;
  }
  return acc / s0;
}

// The design's gradient (dz/dx, dz/dy) at cell i by central differences (one-sided at the grid's
// and the surface's edges; 0 across a NaN neighbour).
std::pair<double, double> gradient(const GridSpec& spec, const std::vector<double>& design, std::size_t i) {
  const std::size_t nx = spec.nx, ny = spec.ny, ix = i % nx, iy = i / nx;
  auto slope = [&](std::size_t lo, std::size_t hi, double span) {
    return std::isnan(design[lo]) || std::isnan(design[hi]) ? 0.0 : (design[hi] - design[lo]) / span;
  };
  const std::size_t xl = ix > 0 ? i - 1 : i, xh = ix + 1 < nx ? i + 1 : i;
  const std::size_t yl = iy > 0 ? i - nx : i, yh = iy + 1 < ny ? i + nx : i;
  const double gx = xh > xl ? slope(xl, xh, static_cast<double>(xh - xl) * spec.cell) : 0.0;
  const double gy = yh > yl ? slope(yl, yh, static_cast<double>((yh - yl) / nx) * spec.cell) : 0.0;
  return {gx, gy};
}

// cos of the design's slope at cell i, for measuring a height difference e above or below the
// design along the surface normal: e·cos. The slope takes, per axis, the steeper of the two
// one-sided differences: on smooth ground the same as central differences to O(cell·curvature),
// and at a crease (a wall's top or foot, where a z-map cell straddles two faces) e·cos is then
// about the distance to the nearer face — not the distance to a blend of the two.
double cos_slope(const GridSpec& spec, const std::vector<double>& design, std::size_t i) {
  const std::size_t nx = spec.nx, ny = spec.ny, ix = i % nx, iy = i / nx;
  auto steeper = [&](bool has_lo, std::size_t lo, bool has_hi, std::size_t hi) {
    double g = 0;
    if (has_lo && !std::isnan(design[lo])) g = std::abs(design[i] - design[lo]);
    if (has_hi && !std::isnan(design[hi])) g = std::max(g, std::abs(design[hi] - design[i]));
    return g / spec.cell;
  };
  const double gx = steeper(ix > 0, i - 1, ix + 1 < nx, i + 1);
  const double gy = steeper(iy > 0, i - nx, iy + 1 < ny, i + nx);
  return 1 / std::sqrt(1 + gx * gx + gy * gy);
}

// Can `cutter` touch the design at cell c without cutting into it anywhere else by more than
// `tol`? The cutter is placed so that its profile passes through (c, design(c)) with its axis
// offset from c down the slope by t: first the contact offset of a smooth surface with the
// design's normal at c (ball R·sinθ, bull (R − rc) + rc·sinθ, flat R on a slope), then 0, R/2, R.
// Each placement is checked against the design sampled every `stride` cells under the cutter.
// O(t's × (R / (stride·cell))²) per call.
bool reachable(const GridSpec& spec, const std::vector<double>& design, const tooling::Cutter& cutter, std::size_t c,
               std::size_t stride, double tol) {
  const double dc = design[c];
  if (std::isnan(dc)) return true;
  const auto [gx, gy] = gradient(spec, design, c);
  const double g = std::hypot(gx, gy), sin_t = g / std::sqrt(1 + g * g);
  const double ux = g > 0 ? -gx / g : 0.0, uy = g > 0 ? -gy / g : 0.0;  // down the slope
  const double R = cutter.radius(), rc = cutter.profile_corner_radius();
  double contact = 0;
  switch (cutter.shape()) {
    case tooling::CutterType::Ball: contact = R * sin_t; break;
    case tooling::CutterType::Bull: contact = (R - rc) + rc * sin_t; break;
    case tooling::CutterType::Flat: contact = g > 0 ? R : 0.0; break;
    // A cone touches a plane with its tip while the plane is flatter than its side, else its rim.
    case tooling::CutterType::Drill: contact = g * R > cutter.point_height() ? R : 0.0; break;
  }
  const double cx = spec.x(c % spec.nx), cy = spec.y(c / spec.nx);
  const auto nx = static_cast<std::ptrdiff_t>(spec.nx), ny = static_cast<std::ptrdiff_t>(spec.ny);
  const auto st = static_cast<std::ptrdiff_t>(stride);
  const auto span = static_cast<std::ptrdiff_t>(std::ceil(R / spec.cell));
  for (const double t : {contact, 0.0, 0.5 * R, R}) {
    const double px = cx + t * ux, py = cy + t * uy;
    const double tip = dc - cutter.profile_height(std::min(t, R));
    const auto pix = static_cast<std::ptrdiff_t>(std::floor((px - spec.x0) / spec.cell));
    const auto piy = static_cast<std::ptrdiff_t>(std::floor((py - spec.y0) / spec.cell));
    bool ok = true;
    for (std::ptrdiff_t a = -span - (-span % st); ok && a <= span; a += st) {
      const std::ptrdiff_t qy = piy + a;
      if (qy < 0 || qy >= ny) continue;
      const double dy = spec.y(static_cast<std::size_t>(qy)) - py;
      for (std::ptrdiff_t b = -span - (-span % st); b <= span; b += st) {
        const std::ptrdiff_t qx = pix + b;
        if (qx < 0 || qx >= nx) continue;
        const double dx = spec.x(static_cast<std::size_t>(qx)) - px;
        const double r = std::hypot(dx, dy);
        if (r > R) continue;
        const double dq = design[static_cast<std::size_t>(qy * nx + qx)];
        if (dq > tip + cutter.profile_height(r) + tol) {
          ok = false;
          break;
        }
      }
    }
    if (ok) return true;
  }
  return false;
}

// Splits the remaining material (cells with e > allowance + tolerance) into rest, scallop and
// uncut (definitions in zmap.hpp). Cells: the rest test once per k × k block that holds material
// left (O((R / (k·cell))²) each), each such cell's walk ≤ 2·R / cell cells. Counts and
// the max are reductions: the same for any thread count.
// `above` is (e − allowance)·cos(slope) per cell (NaN off the surface), computed once by the caller.
void split_remaining(const ZMap& machined, const std::vector<double>& design, const std::vector<double>& above,
                     const MetricsOptions& opt, SurfaceMetrics& out) {
  const GridSpec& spec = machined.spec();
  const tooling::Cutter& cutter = *opt.cutter;
  cutter.check();
  const std::size_t nx = spec.nx, ny = spec.ny, k = opt.reach_every;
  auto left = [&](std::size_t i) { return above[i] > opt.tolerance_mm; };  // false on NaN
  // The rest test runs once per k × k block of cells that holds material left: at the block's
  // such cell nearest to the block's centre (first in row order on a tie), and every cell left in
  // the block takes its answer.
  const std::size_t lx = (nx + k - 1) / k, ly = (ny + k - 1) / k;
  std::vector<std::size_t> probe(lx * ly, SIZE_MAX);
  std::vector<std::size_t> probe_d2(lx * ly, SIZE_MAX);
  for (std::size_t iy = 0; iy < ny; ++iy)
    for (std::size_t ix = 0; ix < nx; ++ix) {
      if (!left(iy * nx + ix)) continue;
      const std::size_t b = iy / k * lx + ix / k;
      const auto dx = static_cast<std::ptrdiff_t>(2 * (ix % k)) - static_cast<std::ptrdiff_t>(k - 1);
      const auto dy = static_cast<std::ptrdiff_t>(2 * (iy % k)) - static_cast<std::ptrdiff_t>(k - 1);
      const auto d2 = static_cast<std::size_t>(dx * dx + dy * dy);
      if (d2 < probe_d2[b]) {
        probe_d2[b] = d2;
        probe[b] = iy * nx + ix;
      }
    }
  std::vector<std::uint8_t> reach(lx * ly, 1);  // 1 = reachable, 0 = rest
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  const auto nl = static_cast<std::ptrdiff_t>(reach.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(nthreads)
  for (std::ptrdiff_t l = 0; l < nl; ++l) {
    const auto ul = static_cast<std::size_t>(l);
    if (probe[ul] != SIZE_MAX) reach[ul] = reachable(spec, design, cutter, probe[ul], k, opt.tolerance_mm) ? 1 : 0;
  }
  const auto steps = static_cast<std::ptrdiff_t>(std::ceil(cutter.radius() / spec.cell));
  // Walks from cell i across the feed to a cell cut to the design, on both sides.
  auto between_passes = [&](std::size_t i) {
    const double x = spec.x(i % nx), y = spec.y(i / nx);
    double ax = 0, ay = 0;
    if (!machined.across_feed(i, x, y, ax, ay)) return false;
    for (const double side : {-1.0, 1.0}) {
      bool met = false;
      for (std::ptrdiff_t s = 1; s <= steps && !met; ++s) {
        const double d = side * static_cast<double>(s) * spec.cell;
        const double qx = std::floor((x + d * ax - spec.x0) / spec.cell),
                     qy = std::floor((y + d * ay - spec.y0) / spec.cell);
        if (qx < 0 || qy < 0 || qx >= static_cast<double>(nx) || qy >= static_cast<double>(ny)) break;
        const std::size_t j = static_cast<std::size_t>(qy) * nx + static_cast<std::size_t>(qx);
        if (std::isnan(design[j])) break;
        met = above[j] <= opt.tolerance_mm;
      }
      if (!met) return false;
    }
    return true;
  };
  std::size_t rest = 0, scallop = 0, uncut = 0;
  double scallop_max = 0;
  const auto rows = static_cast<std::ptrdiff_t>(ny);
#pragma omp parallel for schedule(dynamic, 8) num_threads(nthreads) reduction(+ : rest, scallop, uncut) \
    reduction(max : scallop_max)
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    const auto iy = static_cast<std::size_t>(r);
    for (std::size_t ix = 0; ix < nx; ++ix) {
      const std::size_t i = iy * nx + ix;
      if (!left(i)) continue;
      if (reach[iy / k * lx + ix / k] == 0) {
        ++rest;
      } else if (between_passes(i)) {
        ++scallop;
        scallop_max = std::max(scallop_max, above[i]);
      } else {
        ++uncut;
      }
    }
  }
  const double cell_area = spec.cell * spec.cell;
  out.rest_area_mm2 = static_cast<double>(rest) * cell_area;
  out.scallop_area_mm2 = static_cast<double>(scallop) * cell_area;
  out.uncut_area_mm2 = static_cast<double>(uncut) * cell_area;
  out.scallop_max_mm = scallop_max;
}

}  // namespace

std::vector<double> deviation(const ZMap& machined, const std::vector<double>& design) {
  if (design.size() != machined.heights().size())
    throw Error("simulate: design surface has " + std::to_string(design.size()) + " values, the z-map " +
                std::to_string(machined.heights().size()));
  std::vector<double> e(design.size());
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = machined.heights()[i] - design[i];
  return e;
}

SurfaceMetrics surface_metrics(const ZMap& machined, const std::vector<double>& design, const MetricsOptions& opt) {
  const GridSpec& spec = machined.spec();
  if (design.size() != spec.cells())
    throw Error("simulate: design surface has " + std::to_string(design.size()) + " values, the z-map " +
                std::to_string(spec.cells()));
  if (!(opt.tolerance_mm >= 0) || !std::isfinite(opt.allowance_mm))
    throw Error("simulate: tolerance must be >= 0 and the allowance finite");
  if (!(opt.sampling_length_mm > 0)) throw Error("simulate: Ra sampling length must be > 0 mm");
  if (opt.ra_bins_um.empty() || !std::is_sorted(opt.ra_bins_um.begin(), opt.ra_bins_um.end()))
    throw Error("simulate: Ra bin edges must be a non-empty ascending list (um)");
  if (opt.ra_every < 1) throw Error("simulate: the Ra stride must be >= 1 cell");
  if (opt.reach_every < 1) throw Error("simulate: the rest-material block size must be >= 1 cell");

  SurfaceMetrics out;
  const auto& z = machined.heights();
  const auto& stamps = machined.stamps();
  const std::size_t n = spec.cells();
  const double cell_area = spec.cell * spec.cell;
  double min_e = std::numeric_limits<double>::infinity();
  double max_e = -std::numeric_limits<double>::infinity();
  double scallop = -std::numeric_limits<double>::infinity();
  std::size_t remaining = 0;
  // (e − allowance) along the normal per cell, kept only when split_remaining needs it.
  std::vector<double> above;
  if (opt.cutter) above.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::uint32_t first_gouge_stamp = std::numeric_limits<std::uint32_t>::max();
  std::size_t first_gouge_cell = SIZE_MAX;
  // Gouge, remaining material and scallop are measured along the surface normal: e·cos(slope),
  // the slope from cos_slope (the steeper one-sided difference per axis). On a steep wall a
  // vertical e overstates the cut by 1/cos(slope) (19× at 87°), which is not how a surface
  // deviation is measured (nor what a chord tolerance bounds).
  double min_en = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(design[i])) continue;
    ++out.surface_cells;
    const double e = z[i] - design[i];
    min_e = std::min(min_e, e);
    max_e = std::max(max_e, e);
    const double cs = cos_slope(spec, design, i);
    const double en_left = (e - opt.allowance_mm) * cs;
    if (!above.empty()) above[i] = en_left;
    if (en_left > opt.tolerance_mm) ++remaining;
    if (stamps[i] != 0) scallop = std::max(scallop, en_left);
    if (!(e < 0)) continue;
    const double en = e * cs;
    if (en < min_en) {
      min_en = en;
      out.gouge_cell = i;
    }
    if (en < -opt.tolerance_mm && stamps[i] != 0 && stamps[i] < first_gouge_stamp) {
      first_gouge_stamp = stamps[i];
      first_gouge_cell = i;
    }
  }
  if (out.surface_cells == 0) throw Error("simulate: the design surface has no cell on the z-map");
  out.min_e_mm = min_e;
  out.max_e_mm = max_e;
  out.max_gouge_mm = std::isfinite(min_en) ? -min_en : 0.0;
  out.gouged = min_en < -opt.tolerance_mm;
  out.remaining_area_mm2 = static_cast<double>(remaining) * cell_area;
  out.uncut_area_mm2 = out.remaining_area_mm2;
  out.scallop_max_mm = std::isfinite(scallop) ? std::max(0.0, scallop) : 0;
  if (opt.cutter) split_remaining(machined, design, above, opt, out);
  if (out.gouged) {
    out.gouge_has_move = machined.origin(out.gouge_cell, out.gouge_move);
    if (first_gouge_cell != SIZE_MAX) (void)machined.origin(first_gouge_cell, out.first_gouge_move);
  } else {
    out.gouge_cell = SIZE_MAX;
  }

  // Ra map.
  out.ra_bin_edges_um = opt.ra_bins_um;
  out.ra_share.assign(opt.ra_bins_um.size(), 0);
  if (!opt.ra_map) return out;
  out.ra_um.assign(n, std::numeric_limits<float>::quiet_NaN());
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  const auto nx = static_cast<std::ptrdiff_t>(spec.nx), ny = static_cast<std::ptrdiff_t>(spec.ny);
  const auto every = static_cast<std::ptrdiff_t>(opt.ra_every), first = every / 2;
  const std::ptrdiff_t rows = ny > first ? (ny - first + every - 1) / every : 0;
#pragma omp parallel num_threads(nthreads)
  {
    // The profile buffer starts on a 64-byte boundary in every thread, so the vectorised sums in
    // profile_ra group their terms the same way whatever the thread (bit-identical Ra maps).
    std::vector<double> prof_store;
#pragma omp for schedule(dynamic, 4)
    for (std::ptrdiff_t row = 0; row < rows; ++row) {
      const std::ptrdiff_t iy = first + row * every;
      for (std::ptrdiff_t ix = first; ix < nx; ix += every) {
        const auto i = static_cast<std::size_t>(iy * nx + ix);
        if (std::isnan(design[i])) continue;
        const auto ux = static_cast<std::size_t>(ix), uy = static_cast<std::size_t>(iy);
        double ax = 0, ay = 1;  // across-feed direction; profile along Y by default
        if (!machined.across_feed(i, spec.x(ux), spec.y(uy), ax, ay)) {
          ax = 0;
          ay = 1;
        }
        const bool along_x = std::abs(ax) >= std::abs(ay);
        const double cosang = std::max(along_x ? std::abs(ax) : std::abs(ay), 1e-6);
        const auto hw = static_cast<std::ptrdiff_t>(std::lround(opt.sampling_length_mm / cosang / (2 * spec.cell)));
        const auto len = static_cast<std::size_t>(2 * hw + 1);
        if (prof_store.size() < len + 8) prof_store.resize(len + 8);
        const auto misalign = reinterpret_cast<std::uintptr_t>(prof_store.data()) % 64 / sizeof(double);
        double* prof = prof_store.data() + (misalign == 0 ? 0 : 8 - misalign);
        std::fill(prof, prof + len, std::numeric_limits<double>::quiet_NaN());
        for (std::ptrdiff_t k = -hw; k <= hw; ++k) {
          const std::ptrdiff_t jx = along_x ? ix + k : ix, jy = along_x ? iy : iy + k;
          if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) continue;
          const auto j = static_cast<std::size_t>(jy * nx + jx);
          if (std::isnan(design[j])) continue;
          prof[static_cast<std::size_t>(k + hw)] = z[j] - design[j];
        }
        const double ra = profile_ra(prof, len);
        if (!std::isnan(ra)) out.ra_um[i] = static_cast<float>(ra * 1000);
      }
    }
  }
  std::vector<float> vals;
  vals.reserve(out.surface_cells);
  for (const float v : out.ra_um)
    if (!std::isnan(v)) vals.push_back(v);
  out.ra_cells = vals.size();
  if (vals.empty()) return out;
  double sum = 0;
  for (const float v : vals) {
    sum += static_cast<double>(v);
    const auto it = std::upper_bound(opt.ra_bins_um.begin(), opt.ra_bins_um.end(), static_cast<double>(v));
    const std::size_t b = it == opt.ra_bins_um.begin() ? 0 : static_cast<std::size_t>(it - opt.ra_bins_um.begin()) - 1;
    out.ra_share[b] += 1;
  }
  for (double& s : out.ra_share) s /= static_cast<double>(vals.size());
  out.ra_mean_um = sum / static_cast<double>(vals.size());
  // Nearest-rank percentiles.
  const auto rank = [&](double p) {
    const auto r = static_cast<std::size_t>(std::ceil(p * static_cast<double>(vals.size())));
    const std::size_t k = std::min(vals.size() - 1, r == 0 ? 0 : r - 1);
    std::nth_element(vals.begin(), vals.begin() + static_cast<std::ptrdiff_t>(k), vals.end());
    return static_cast<double>(vals[k]);
  };
  out.ra_median_um = rank(0.5);
  out.ra_p90_um = rank(0.9);
  return out;
}

}  // namespace millnet::simulate
