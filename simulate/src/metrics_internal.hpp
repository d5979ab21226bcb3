#pragma once
// Private to the surface metrics (surface_metrics() in zmap.hpp), one file per pass:
//   surface_metrics.cpp  surface_metrics, the table of contents; deviation, gouge and remaining
//                        material in one pass over the cells
//   rest_material.cpp    the remaining material split into rest, scallop and uncut
//   roughness.cpp        the Ra map and its statistics
#include "millnet/simulate/zmap.hpp"

#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace millnet::simulate::metrics {

/// An allocator that leaves a value-initialised element as it is: a vector of one value per cell
/// (`CellValues`) sized with resize() is then written once by the parallel pass that fills it,
/// not zeroed first by one thread (on a 0.025 mm grid of a 115 mm part, 166 MB per strategy).
template <class T>
struct Uninit : std::allocator<T> {
  Uninit() = default;
  template <class U>
  explicit Uninit(const Uninit<U>& /*other*/) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};
using CellValues = std::vector<double, Uninit<double>>;

/// cos of the design's slope at cell i (the steeper one-sided difference per axis), for measuring
/// a height difference e along the surface normal: e·cos. O(1).
[[nodiscard]] double cos_slope(const GridSpec& spec, const std::vector<double>& design, std::size_t i);

/// Splits the remaining material (cells with (e − allowance)·cos(slope) > tolerance) into rest,
/// scallop and uncut (definitions in zmap.hpp): fills out's rest, scallop and uncut areas and
/// scallop_max_mm. `above` is (e − allowance)·cos(slope) per cell (NaN off the surface);
/// opt.cutter must be set. The same for any thread count.
/// When `rest` is not empty (sized to the cells), each cell it finds to be rest material is set to 1.
void split_remaining(const ZMap& machined, const std::vector<double>& design, const CellValues& above,
                     const MetricsOptions& opt, SurfaceMetrics& out, std::vector<std::uint8_t>& rest);

/// The Ra map, µm per cell (NaN off the surface, where a profile has fewer than 3 samples, and
/// between the cells of the ra_every lattice); rows in parallel, bit-identical for any thread count.
[[nodiscard]] std::vector<float> ra_map(const ZMap& machined, const std::vector<double>& design,
                                        const MetricsOptions& opt, std::size_t& not_machined);

/// The statistics of out.ra_um (ra_map's, on the grid `spec`): cells with an Ra, share per bin
/// (out.ra_share sized to the bins), mean, nearest-rank median and p90.
void ra_statistics(const GridSpec& spec, const MetricsOptions& opt, SurfaceMetrics& out);

}  // namespace millnet::simulate::metrics
