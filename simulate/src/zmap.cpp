// ZMap storage: grid checks, the memory estimate and refusal, stock initialisation, move stamps.
#include "millnet/simulate/zmap.hpp"

#include "millnet/core/error.hpp"
#include "millnet/simulate/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace millnet::simulate {

namespace {
std::string mib(std::size_t bytes) { return std::to_string((bytes + (std::size_t{1} << 20) - 1) >> 20) + " MiB"; }
}  // namespace

void GridSpec::check() const {
  if (!std::isfinite(cell) || cell <= 0) throw Error("z-map: cell must be a finite size > 0 mm");
  if (!std::isfinite(x0) || !std::isfinite(y0)) throw Error("z-map: grid corner must be finite");
  if (nx == 0 || ny == 0) throw Error("z-map: grid needs at least one cell in X and in Y");
  if (nx >= (std::size_t{1} << 31) || ny >= (std::size_t{1} << 31))
    throw Error("z-map: at most 2^31 - 1 cells per row or column");
}

std::size_t ZMap::bytes_needed(const GridSpec& spec) {
  constexpr std::size_t kPerCell = sizeof(double) + sizeof(std::uint32_t);
  if (spec.nx != 0 && spec.ny > SIZE_MAX / spec.nx / kPerCell) return SIZE_MAX;
  return spec.cells() * kPerCell;
}

WorkEstimate zmap_work(const GridSpec& spec, double extra_bytes_per_cell) {
  const double cells = static_cast<double>(spec.nx) * static_cast<double>(spec.ny);
  WorkEstimate e{"cell_mm " + format_size(spec.cell) + " mm over a " +
                     format_size(spec.cell * static_cast<double>(spec.nx)) + " × " +
                     format_size(spec.cell * static_cast<double>(spec.ny)) + " mm z-map",
                 cells, "z-map cells",
                 cells * (static_cast<double>(sizeof(double) + sizeof(std::uint32_t)) + extra_bytes_per_cell)};
  e.memory_only = true;
  return e;
}

namespace {
void check_size(const GridSpec& spec, std::size_t max_bytes) {
  spec.check();
  const std::size_t need = ZMap::bytes_needed(spec);
  if (need > max_bytes)
    throw Error("z-map: " + std::to_string(spec.nx) + " x " + std::to_string(spec.ny) + " cells at " +
                std::to_string(spec.cell) + " mm need " + mib(need) + ", above the limit of " + mib(max_bytes) +
                " (use a coarser cell or a smaller region)");
}
}  // namespace

ZMap ZMap::flat(const GridSpec& spec, double top, std::size_t max_bytes) {
  if (!std::isfinite(top)) {
    spec.check();
    throw Error("z-map: stock top must be finite");
  }
  check_size(spec, max_bytes);
  ZMap m;
  m.spec_ = spec;
  m.z_.assign(spec.cells(), top);
  m.stamp_.assign(spec.cells(), 0);
  return m;
}

ZMap ZMap::from_heights(const GridSpec& spec, const std::vector<double>& heights, double offset, double nan_fill,
                        std::size_t max_bytes) {
  return from_heights(spec, heights, offset, nan_fill, max_bytes, ZMap{});
}

ZMap ZMap::from_heights(const GridSpec& spec, const std::vector<double>& heights, double offset, double nan_fill,
                        std::size_t max_bytes, ZMap&& reuse) {
  spec.check();
  if (heights.size() != spec.cells())
    throw Error("z-map: height field has " + std::to_string(heights.size()) + " values, the grid " +
                std::to_string(spec.cells()));
  check_size(spec, max_bytes);
  ZMap m;
  m.spec_ = spec;
  m.z_ = std::move(reuse.z_);  // its capacity (the new values are all written below)
  m.stamp_ = std::move(reuse.stamp_);
  m.z_.resize(spec.cells());
  m.stamp_.resize(spec.cells());
  const auto n = static_cast<std::int64_t>(heights.size());
#pragma omp parallel for schedule(static) if (n > 65536)
  for (std::int64_t k = 0; k < n; ++k) {  // O(cells)
    const auto i = static_cast<std::size_t>(k);
    m.z_[i] = std::isnan(heights[i]) ? nan_fill : heights[i] + offset;
    m.stamp_[i] = 0;
  }
  return m;
}

bool ZMap::origin(std::size_t index, MoveRef& out) const {
  const std::uint32_t s = stamp_[index];
  if (s == 0 || passes_.empty()) return false;
  // The pass whose first serial is the last one ≤ s.
  auto it = std::upper_bound(passes_.begin(), passes_.end(), s,
                             [](std::uint32_t v, const Pass& p) { return v < p.first_serial; });
  if (it == passes_.begin()) return false;
  --it;
  const std::size_t item = s - it->first_serial;
  if (item >= it->items) return false;
  out.pass = static_cast<std::size_t>(it - passes_.begin());
  out.item = item;
  out.line = item < it->source_line.size() ? it->source_line[item] : 0;
  return true;
}

bool ZMap::across_feed(std::size_t index, double x, double y, double& nx, double& ny) const {
  MoveRef ref;
  if (!origin(index, ref)) return false;
  const auto& a = passes_[ref.pass].across;
  if (ref.item >= a.size()) return false;
  const auto& d = a[ref.item];
  if (d[2] < 0) return false;
  if (d[2] > 0) {  // arc: radial from the centre
    const double rx = x - d[0], ry = y - d[1];
    const double r = std::hypot(rx, ry);
    if (r < tol::at_centre_mm) return false;
    nx = rx / r;
    ny = ry / r;
    return true;
  }
  nx = d[0];
  ny = d[1];
  return true;
}

}  // namespace millnet::simulate
