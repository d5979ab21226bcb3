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

  SurfaceMetrics out;
  const auto& z = machined.heights();
  const auto& stamps = machined.stamps();
  const std::size_t n = spec.cells();
  const double cell_area = spec.cell * spec.cell;
  double min_e = std::numeric_limits<double>::infinity();
  double max_e = -std::numeric_limits<double>::infinity();
  double scallop = -std::numeric_limits<double>::infinity();
  std::size_t uncut = 0;
  std::uint32_t first_gouge_stamp = std::numeric_limits<std::uint32_t>::max();
  std::size_t first_gouge_cell = SIZE_MAX;
  // A gouge is measured along the surface normal: e·cos(slope) = e / √(1 + |∇design|²), the
  // gradient by central differences of the design (one-sided at its edges). On a steep wall a
  // vertical e overstates the cut by 1/cos(slope) (19× at 87°), which is not how a surface
  // deviation is measured (nor what a chord tolerance bounds).
  const std::size_t gnx = spec.nx, gny = spec.ny;
  auto normal_e = [&](std::size_t i, double e) {
    const std::size_t ix = i % gnx, iy = i / gnx;
    auto slope = [&](std::size_t lo, std::size_t hi, double span) {
      return std::isnan(design[lo]) || std::isnan(design[hi]) ? 0.0 : (design[hi] - design[lo]) / span;
    };
    const std::size_t xl = ix > 0 ? i - 1 : i, xh = ix + 1 < gnx ? i + 1 : i;
    const std::size_t yl = iy > 0 ? i - gnx : i, yh = iy + 1 < gny ? i + gnx : i;
    const double gx = xh > xl ? slope(xl, xh, static_cast<double>(xh - xl) * spec.cell) : 0.0;
    const double gy = yh > yl ? slope(yl, yh, static_cast<double>((yh - yl) / gnx) * spec.cell) : 0.0;
    return e / std::sqrt(1 + gx * gx + gy * gy);
  };
  double min_en = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(design[i])) continue;
    ++out.surface_cells;
    const double e = z[i] - design[i];
    min_e = std::min(min_e, e);
    max_e = std::max(max_e, e);
    if (e > opt.allowance_mm + opt.tolerance_mm) ++uncut;
    if (stamps[i] != 0) scallop = std::max(scallop, e - opt.allowance_mm);
    if (!(e < 0)) continue;
    const double en = normal_e(i, e);
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
  out.uncut_area_mm2 = static_cast<double>(uncut) * cell_area;
  out.scallop_max_mm = std::isfinite(scallop) ? std::max(0.0, scallop) : 0;
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
