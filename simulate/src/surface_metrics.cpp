// Scoring a machined z-map against the design surface: deviation, gouge, remaining material,
// scallop, and the Ra map with its histogram (definitions in zmap.hpp). The passes beyond the
// first are in rest_material.cpp and roughness.cpp (metrics_internal.hpp).
#include "metrics_internal.hpp"

#include "millnet/core/error.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace millnet::simulate {

namespace {

void check_inputs(const GridSpec& spec, const std::vector<double>& design, const MetricsOptions& opt) {
  if (design.size() != spec.cells())
    throw Error("simulate: design surface has " + std::to_string(design.size()) + " values, the z-map " +
                std::to_string(spec.cells()));
  if (!(opt.tolerance_mm >= 0) || !std::isfinite(opt.allowance_mm))
    throw Error("simulate: tolerance must be >= 0 and the allowance finite");
  if (!(opt.sampling_length_mm > 0)) throw Error("simulate: Ra sampling length must be > 0 mm");
  if (opt.ra_bins_um.empty() || !std::is_sorted(opt.ra_bins_um.begin(), opt.ra_bins_um.end()))
    throw Error("simulate: Ra bin edges must be a non-empty ascending list (um)");
  if (!std::isnan(opt.spec_limit_mm) && !(opt.spec_limit_mm >= 0))
    throw Error("simulate: the specification's limit must be >= 0 mm");
  if (!std::isnan(opt.ra_target_um) && !(opt.ra_target_um > 0)) throw Error("simulate: the Ra target must be > 0 um");
  if (opt.ra_every < 1) throw Error("simulate: the Ra stride must be >= 1 cell");
  if (opt.reach_every < 1) throw Error("simulate: the rest-material block size must be >= 1 cell");
}

// One Part per fixed chunk of n cells (the same chunks for any thread count), each filled by
// body(part, i0, i1) on `nthreads` threads, returned in cell order: the caller combines them in that
// order with the comparisons a single pass would make, so the figures are the serial pass's.
template <class Part, class Body>
std::vector<Part> in_chunks(std::size_t n, int nthreads, const Part& init, Body body) {
  constexpr std::size_t kChunk = 1 << 16;
  const std::size_t nchunks = (n + kChunk - 1) / kChunk;
  std::vector<Part> parts(nchunks, init);
#pragma omp parallel for schedule(dynamic, 4) num_threads(nthreads)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(nchunks); ++c) {  // O(n)
    const std::size_t i0 = static_cast<std::size_t>(c) * kChunk;
    body(parts[static_cast<std::size_t>(c)], i0, std::min(n, i0 + kChunk));
  }
  return parts;
}

// Deviation, gouge and remaining material over the surface cells, in one pass: fills the surface
// cell count, min/max e, the deepest gouge (its cell), the remaining area (all of it uncut until
// split_remaining splits it) and the scallop without a cutter; `above` (when not empty) takes
// (e − allowance)·cos(slope) per cell, NaN off the surface (every cell is written). Returns the cell of the earliest move that gouged (its
// stamp is the lowest), SIZE_MAX when none did. Throws when no cell has a design height.
//
// Gouge, remaining material and scallop are measured along the surface normal: e·cos(slope), the
// slope from cos_slope (the steeper one-sided difference per axis). On a steep wall a vertical e
// overstates the cut by 1/cos(slope) (19× at 87°), which is not how a surface deviation is
// measured (nor what a chord tolerance bounds).
std::size_t measure_deviation(const ZMap& machined, const std::vector<double>& design, const MetricsOptions& opt,
                              SurfaceMetrics& out, metrics::CellValues& above) {
  const GridSpec& spec = machined.spec();
  const auto& z = machined.heights();
  const auto& stamps = machined.stamps();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Per chunk of cells (fixed, whatever the thread count), combined in chunk order with the same
  // strict comparisons as one pass in cell order: the first cell wins every tie, so the figures
  // are those of the serial pass, bit for bit.
  struct Part {
    std::size_t surface = 0, remaining = 0;
    double min_e = kInf, max_e = -kInf, scallop = -kInf, min_en = kInf;
    std::size_t gouge_cell = SIZE_MAX;
    std::uint32_t first_stamp = std::numeric_limits<std::uint32_t>::max();
    std::size_t first_cell = SIZE_MAX;
  };
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  const std::vector<Part> parts =
      in_chunks(spec.cells(), nthreads, Part{}, [&](Part& pt, std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
          if (std::isnan(design[i])) {
            if (!above.empty()) above[i] = std::numeric_limits<double>::quiet_NaN();
            continue;
          }
          ++pt.surface;
          const double e = z[i] - design[i];
          pt.min_e = std::min(pt.min_e, e);
          pt.max_e = std::max(pt.max_e, e);
          const double cs = metrics::cos_slope(spec, design, i);
          const double en_left = (e - opt.allowance_mm) * cs;
          if (!above.empty()) above[i] = en_left;
          if (en_left > opt.tolerance_mm) ++pt.remaining;
          if (stamps[i] != 0) pt.scallop = std::max(pt.scallop, en_left);
          if (!(e < 0)) continue;
          const double en = e * cs;
          if (en < pt.min_en) {
            pt.min_en = en;
            pt.gouge_cell = i;
          }
          if (en < -opt.tolerance_mm && stamps[i] != 0 && stamps[i] < pt.first_stamp) {
            pt.first_stamp = stamps[i];
            pt.first_cell = i;
          }
        }
      });
  Part all;
  for (const Part& pt : parts) {  // O(chunks), in cell order
    all.surface += pt.surface;
    all.remaining += pt.remaining;
    all.min_e = std::min(all.min_e, pt.min_e);
    all.max_e = std::max(all.max_e, pt.max_e);
    all.scallop = std::max(all.scallop, pt.scallop);
    if (pt.min_en < all.min_en) {
      all.min_en = pt.min_en;
      all.gouge_cell = pt.gouge_cell;
    }
    if (pt.first_stamp < all.first_stamp) {
      all.first_stamp = pt.first_stamp;
      all.first_cell = pt.first_cell;
    }
  }
  out.surface_cells += all.surface;
  if (all.gouge_cell != SIZE_MAX) out.gouge_cell = all.gouge_cell;
  if (out.surface_cells == 0) throw Error("simulate: the design surface has no cell on the z-map");
  out.min_e_mm = all.min_e;
  out.max_e_mm = all.max_e;
  out.max_gouge_mm = std::isfinite(all.min_en) ? -all.min_en : 0.0;
  out.gouged = all.min_en < -opt.tolerance_mm;
  const double cell_area = spec.cell * spec.cell;
  out.remaining_area_mm2 = static_cast<double>(all.remaining) * cell_area;
  out.uncut_area_mm2 = out.remaining_area_mm2;
  out.scallop_max_mm = std::isfinite(all.scallop) ? std::max(0.0, all.scallop) : 0;
  return all.first_cell;
}

// The moves that cut the deepest gouge and the earliest one; no gouge cell without a gouge.
void locate_gouges(const ZMap& machined, std::size_t first_gouge_cell, SurfaceMetrics& out) {
  if (out.gouged) {
    out.gouge_has_move = machined.origin(out.gouge_cell, out.gouge_move);
    if (first_gouge_cell != SIZE_MAX) (void)machined.origin(first_gouge_cell, out.first_gouge_move);
  } else {
    out.gouge_cell = SIZE_MAX;
  }
}

// The surface specification's figures (SurfaceMetrics::spec_*): each cell the cutter can reach
// (not rest) in spec, over the limit or not machined. O(cells) in fixed chunks combined in order
// (the first cell wins a tie, as in one pass): the same for any thread count.
void spec_figures(const ZMap& machined, const metrics::CellValues& above, const std::vector<std::uint8_t>& rest,
                  const MetricsOptions& opt, SurfaceMetrics& out) {
  const auto& stamps = machined.stamps();
  out.spec_measured = true;
  struct Part {
    std::size_t cells = 0, not_machined = 0, in_spec = 0, over = 0;
    double over_max = 0;
    std::size_t over_cell = SIZE_MAX;
  };
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  Part init;
  init.over_max = out.over_spec_max_mm;
  const std::vector<Part> parts =
      in_chunks(above.size(), nthreads, init, [&](Part& pt, std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
          if (std::isnan(above[i]) || (!rest.empty() && rest[i] != 0)) continue;
          ++pt.cells;
          if (stamps[i] == 0) {
            ++pt.not_machined;
          } else if (above[i] <= opt.spec_limit_mm) {
            ++pt.in_spec;
          } else {
            ++pt.over;
            if (above[i] > pt.over_max) {
              pt.over_max = above[i];
              pt.over_cell = i;
            }
          }
        }
      });
  for (const Part& pt : parts) {  // O(chunks), in cell order
    out.spec_cells += pt.cells;
    out.spec_not_machined_cells += pt.not_machined;
    out.in_spec_cells += pt.in_spec;
    out.over_spec_cells += pt.over;
    if (pt.over_cell != SIZE_MAX && pt.over_max > out.over_spec_max_mm) {
      out.over_spec_max_mm = pt.over_max;
      out.over_spec_cell = pt.over_cell;
    }
  }
  if (out.spec_cells > 0) out.spec_share = static_cast<double>(out.in_spec_cells) / static_cast<double>(out.spec_cells);
}

}  // namespace

namespace metrics {
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
}  // namespace metrics

std::vector<double> deviation(const ZMap& machined, const std::vector<double>& design) {
  if (design.size() != machined.heights().size())
    throw Error("simulate: design surface has " + std::to_string(design.size()) + " values, the z-map " +
                std::to_string(machined.heights().size()));
  std::vector<double> e(design.size());
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = machined.heights()[i] - design[i];
  return e;
}

std::vector<std::uint8_t> cells_above(const ZMap& machined, const std::vector<double>& design, double thickness_mm) {
  if (design.size() != machined.heights().size())
    throw Error("simulate: design surface has " + std::to_string(design.size()) + " values, the z-map " +
                std::to_string(machined.heights().size()));
  const GridSpec& spec = machined.spec();
  std::vector<std::uint8_t> out(design.size(), 0);
  for (std::size_t i = 0; i < design.size(); ++i) {  // O(cells)
    if (std::isnan(design[i])) continue;
    const double e = machined.heights()[i] - design[i];
    out[i] = e > thickness_mm && e * metrics::cos_slope(spec, design, i) > thickness_mm ? 1 : 0;
  }
  return out;
}

double area_above_mm2(const ZMap& machined, const std::vector<double>& design, double thickness_mm,
                      const std::vector<std::uint8_t>& only) {
  if (!only.empty() && only.size() != design.size())
    throw Error("simulate: the mask has " + std::to_string(only.size()) + " cells, the design " +
                std::to_string(design.size()));
  const std::vector<std::uint8_t> above = cells_above(machined, design, thickness_mm);
  std::size_t n = 0;
  for (std::size_t i = 0; i < above.size(); ++i) n += above[i] != 0 && (only.empty() || only[i] != 0) ? 1 : 0;
  return static_cast<double>(n) * machined.spec().cell * machined.spec().cell;
}

SurfaceMetrics surface_metrics(const ZMap& machined, const std::vector<double>& design, const MetricsOptions& opt) {
  check_inputs(machined.spec(), design, opt);
  if (!opt.judged.empty()) {  // the judged surface's figures, the whole design's gouge
    if (opt.judged.size() != design.size())
      throw Error("simulate: the judged-surface mask has " + std::to_string(opt.judged.size()) + " cells, the z-map " +
                  std::to_string(design.size()));
    std::vector<double> inside = design;
    for (std::size_t i = 0; i < inside.size(); ++i)  // O(cells)
      if (opt.judged[i] == 0) inside[i] = std::numeric_limits<double>::quiet_NaN();
    MetricsOptions all = opt;
    all.judged.clear();
    SurfaceMetrics out = surface_metrics(machined, inside, all);
    SurfaceMetrics whole;
    metrics::CellValues none;
    const std::size_t first_gouge_cell = measure_deviation(machined, design, all, whole, none);
    locate_gouges(machined, first_gouge_cell, whole);
    out.max_gouge_mm = whole.max_gouge_mm;
    out.gouged = whole.gouged;
    out.gouge_cell = whole.gouge_cell;
    out.gouge_has_move = whole.gouge_has_move;
    out.gouge_move = whole.gouge_move;
    out.first_gouge_move = whole.first_gouge_move;
    out.min_e_mm = std::min(out.min_e_mm, whole.min_e_mm);
    return out;
  }
  SurfaceMetrics out;
  // 1. Deviation, gouge, remaining material. (e − allowance) along the normal per cell is kept
  // only when split_remaining needs it.
  const bool spec = !std::isnan(opt.spec_limit_mm);
  metrics::CellValues above;  // every cell written by measure_deviation
  if (opt.cutter || spec) above.resize(design.size());
  const std::size_t first_gouge_cell = measure_deviation(machined, design, opt, out, above);
  // 2. The remaining material split into rest, scallop and uncut (with the cutter only).
  std::vector<std::uint8_t> rest;
  if (opt.cutter && spec) rest.assign(design.size(), 0);
  if (opt.cutter) metrics::split_remaining(machined, design, above, opt, out, rest);
  locate_gouges(machined, first_gouge_cell, out);
  // 3. The surface specification: in spec, over it, or not machined, over what the cutter reaches.
  if (spec) spec_figures(machined, above, rest, opt, out);
  // 9 B per cell freed before the Ra map is drawn (issue 37 §3: memory). (`v = {}` would keep the
  // capacity: it assigns an empty initializer list.)
  metrics::CellValues().swap(above);
  std::vector<std::uint8_t>().swap(rest);
  // 4. The Ra map and its statistics.
  out.ra_bin_edges_um = opt.ra_bins_um;
  out.ra_share.assign(opt.ra_bins_um.size(), 0);
  if (!opt.ra_map) return out;
  out.ra_um = metrics::ra_map(machined, design, opt, out.not_machined_cells);
  metrics::ra_statistics(machined.spec(), opt, out);
  return out;
}

}  // namespace millnet::simulate
