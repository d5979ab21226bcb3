// Roughness: Ra per cell over one sampling length across the feed (definition in zmap.hpp), and
// the statistics of the Ra map. Cells no move lowered are not machined: no Ra, counted apart.
#include "metrics_internal.hpp"

#include "millnet/simulate/tolerances.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace millnet::simulate::metrics {

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

// A profile of `len` samples in `store`, starting on a 64-byte boundary in every thread, so that
// the vectorised sums in profile_ra group their terms the same way whatever the thread
// (bit-identical Ra maps).
double* aligned_profile(std::vector<double>& store, std::size_t len) {
  if (store.size() < len + 8) store.resize(len + 8);
  const auto misalign = reinterpret_cast<std::uintptr_t>(store.data()) % 64 / sizeof(double);
  return store.data() + (misalign == 0 ? 0 : 8 - misalign);
}

// Ra (mm) at the surface cell (ix, iy): its profile of e across the feed of the move that last cut
// it (along Y when none did), one sampling length long (zmap.hpp); NaN with fewer than 3 samples.
// `store` is the calling thread's profile buffer.
double cell_ra(const ZMap& machined, const std::vector<double>& design, const MetricsOptions& opt, std::ptrdiff_t ix,
               std::ptrdiff_t iy, std::vector<double>& store) {
  const GridSpec& spec = machined.spec();
  const auto& z = machined.heights();
  const auto nx = static_cast<std::ptrdiff_t>(spec.nx), ny = static_cast<std::ptrdiff_t>(spec.ny);
  const auto i = static_cast<std::size_t>(iy * nx + ix);
  const auto ux = static_cast<std::size_t>(ix), uy = static_cast<std::size_t>(iy);
  double ax = 0, ay = 1;  // across-feed direction; profile along Y by default
  if (!machined.across_feed(i, spec.x(ux), spec.y(uy), ax, ay)) {
    ax = 0;
    ay = 1;
  }
  const bool along_x = std::abs(ax) >= std::abs(ay);
  const double cosang = std::max(along_x ? std::abs(ax) : std::abs(ay), tol::min_profile_cos);
  const auto hw = static_cast<std::ptrdiff_t>(std::lround(opt.sampling_length_mm / cosang / (2 * spec.cell)));
  const auto len = static_cast<std::size_t>(2 * hw + 1);
  double* prof = aligned_profile(store, len);
  std::fill(prof, prof + len, std::numeric_limits<double>::quiet_NaN());
  for (std::ptrdiff_t k = -hw; k <= hw; ++k) {
    const std::ptrdiff_t jx = along_x ? ix + k : ix, jy = along_x ? iy : iy + k;
    if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) continue;
    const auto j = static_cast<std::size_t>(jy * nx + jx);
    if (std::isnan(design[j])) continue;
    prof[static_cast<std::size_t>(k + hw)] = z[j] - design[j];
  }
  return profile_ra(prof, len);
}

}  // namespace

// The Ra map, µm per cell (NaN off the surface, on cells no move lowered, and between the ra_every
// lattice's cells), rows in parallel; `not_machined` counts the lattice's surface cells no move
// lowered.
std::vector<float> ra_map(const ZMap& machined, const std::vector<double>& design, const MetricsOptions& opt,
                          std::size_t& not_machined) {
  const GridSpec& spec = machined.spec();
  std::vector<float> ra_um(spec.cells(), std::numeric_limits<float>::quiet_NaN());
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  const auto nx = static_cast<std::ptrdiff_t>(spec.nx), ny = static_cast<std::ptrdiff_t>(spec.ny);
  const auto every = static_cast<std::ptrdiff_t>(opt.ra_every), first = every / 2;
  const std::ptrdiff_t rows = ny > first ? (ny - first + every - 1) / every : 0;
  const std::vector<std::uint32_t>& stamps = machined.stamps();
  std::size_t untouched = 0;
#pragma omp parallel num_threads(nthreads) reduction(+ : untouched)
  {
    std::vector<double> prof_store;
#pragma omp for schedule(dynamic, 4)
    for (std::ptrdiff_t row = 0; row < rows; ++row) {
      const std::ptrdiff_t iy = first + row * every;
      for (std::ptrdiff_t ix = first; ix < nx; ix += every) {
        const auto i = static_cast<std::size_t>(iy * nx + ix);
        if (std::isnan(design[i])) continue;
        if (stamps[i] == 0) {  // left at the stock: not machined, no Ra
          ++untouched;
          continue;
        }
        const double ra = cell_ra(machined, design, opt, ix, iy, prof_store);
        if (!std::isnan(ra)) ra_um[i] = static_cast<float>(ra * 1000);
      }
    }
  }
  not_machined = untouched;
  return ra_um;
}

// The Ra map's statistics: cells with an Ra, share per bin, mean, nearest-rank median and p90.
void ra_statistics(const GridSpec& spec, const MetricsOptions& opt, SurfaceMetrics& out) {
  // The cells with an Ra, in cell order: ra_map gave one only to the ra_every lattice's cells, so
  // only those are read (one in ra_every² of the map).
  const std::size_t every = std::max<std::size_t>(1, opt.ra_every), first = every / 2;
  std::vector<float> vals;
  vals.reserve(((spec.nx + every - 1) / every) * ((spec.ny + every - 1) / every));
  for (std::size_t iy = first; iy < spec.ny; iy += every)
    for (std::size_t ix = first; ix < spec.nx; ix += every)
      if (const float v = out.ra_um[iy * spec.nx + ix]; !std::isnan(v)) vals.push_back(v);
  out.ra_cells = vals.size();
  const double sampled = static_cast<double>(vals.size() + out.not_machined_cells);
  if (sampled > 0) out.ra_not_machined_share = static_cast<double>(out.not_machined_cells) / sampled;
  if (!std::isnan(opt.ra_target_um))  // not machined counts as outside the target
    out.ra_target_share =
        static_cast<double>(std::count_if(vals.begin(), vals.end(),
                                          [&](float v) { return static_cast<double>(v) <= opt.ra_target_um; })) /
        sampled;
  if (vals.empty()) return;
  double sum = 0;
  for (const float v : vals) {
    sum += static_cast<double>(v);
    const auto it = std::upper_bound(opt.ra_bins_um.begin(), opt.ra_bins_um.end(), static_cast<double>(v));
    const std::size_t b = it == opt.ra_bins_um.begin() ? 0 : static_cast<std::size_t>(it - opt.ra_bins_um.begin()) - 1;
    out.ra_share[b] += 1;
  }
  for (double& s : out.ra_share) s /= sampled;
  out.ra_mean_um = sum / static_cast<double>(vals.size());
  const auto rank = [&](double p) {
    const auto r = static_cast<std::size_t>(std::ceil(p * static_cast<double>(vals.size())));
    const std::size_t k = std::min(vals.size() - 1, r == 0 ? 0 : r - 1);
    std::nth_element(vals.begin(), vals.begin() + static_cast<std::ptrdiff_t>(k), vals.end());
    return static_cast<double>(vals[k]);
  };
  out.ra_median_um = rank(0.5);
  out.ra_p90_um = rank(0.9);
}

}  // namespace millnet::simulate::metrics
