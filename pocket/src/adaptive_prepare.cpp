// The adaptive planner's preparation (adaptive_internal.hpp): the cells its passes must cut (the
// target), the components of the area the tool centre may reach and the entry of each (the point
// farthest from the walls), and the lattice of positions the links may pass through.
#include "millnet/pocket/tolerances.hpp"

#include "adaptive_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace millnet::pocket::adaptive {

namespace {

using raster::edt;

/// A row's run of allowed cells.
struct RunOf {
  int y, x0, x1;
};

/// The rows' runs of allowed cells in raster order, and the index of each row's first run
/// (row_first[ny] = the number of runs).
void allowed_runs(const std::vector<std::uint8_t>& allowed, int nx, int ny, std::vector<RunOf>& arun,
                  std::vector<std::size_t>& row_first) {
  row_first.assign(static_cast<std::size_t>(ny) + 1, 0);
  for (int y = 0; y < ny; ++y) {
    row_first[static_cast<std::size_t>(y)] = arun.size();
    for (int x = 0; x < nx;) {
      if (!allowed[lin(x, y, nx)]) {
        ++x;
        continue;
      }
      const int x0 = x;
      while (x < nx && allowed[lin(x, y, nx)]) ++x;
      arun.push_back({y, x0, x - 1});
    }
  }
  row_first[static_cast<std::size_t>(ny)] = arun.size();
}

/// Union–find over the runs, joined where runs of neighbouring rows overlap or touch diagonally
/// (8-connected); returns each run's root, which is its component's first run. O(runs).
std::vector<std::size_t> join_runs(const std::vector<RunOf>& arun, const std::vector<std::size_t>& row_first, int ny) {
  std::vector<std::size_t> parent(arun.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int y = 1; y < ny; ++y) {
    std::size_t j = row_first[static_cast<std::size_t>(y) - 1];
    const std::size_t j_end = row_first[static_cast<std::size_t>(y)];
    for (std::size_t i = j_end; i < row_first[static_cast<std::size_t>(y) + 1]; ++i) {
      // Runs of the row below that touch run i (8-connected: up to one cell beyond its ends).
      while (j < j_end && arun[j].x1 < arun[i].x0 - 1) ++j;
      for (std::size_t k = j; k < j_end && arun[k].x0 <= arun[i].x1 + 1; ++k) {
        const std::size_t ri = find(i), rk = find(k);
        if (ri != rk) parent[std::max(ri, rk)] = std::min(ri, rk);  // the root is the first run
      }
    }
  }
  std::vector<std::size_t> root(arun.size());
  for (std::size_t i = 0; i < arun.size(); ++i) root[i] = find(i);
  return root;
}

}  // namespace

Planner::Planner(const Region& region, const CutParams& cut, const AdaptiveParams& prm, double target_deg)
    : region_(region),
      cut_(cut),
      R_(cut.tool.diameter / 2),
      climb_(prm.climb),
      both_(prm.both_ways),
      pass_climb_(prm.climb),
      step_(prm.step_mm > 0 ? prm.step_mm : cut.tool.diameter / 40),
      raster_(region, adaptive_raster_mm(region, cut, prm), cut.tool.diameter),
      walls_(region, cut.clearance() + tol::contour_margin_mm),
      exact_(region, cut.clearance()),
      link_walls_(region, cut.clearance() + tol::contour_margin_mm + kLinkMarginMm) {
  const double h = raster_.h();
  const double width = R_ * (1 - std::cos(target_deg * kPi / 180));  // engaged width a_e
  target_deg_ = target_deg;
  // Below kPassesTakeTheWallBandBelowDeg the passes must take every remnant (the wall pass would
  // take a corner's at once, over the target): there the raster's own 4 cells.
  min_work_ = target_deg < kPassesTakeTheWallBandBelowDeg
                  ? 4
                  : std::max(4, static_cast<int>(std::lround(kMinWorkCellsD40 * (cut.tool.diameter / 40) *
                                                             (cut.tool.diameter / 40) / (h * h))));
  max_cells_ = prm.safety * width * step_ / (h * h);
  prepare();
}

void Planner::prepare() {
  const auto& st = raster_.states();
  std::vector<std::uint8_t> empty(st.size());
  for (std::size_t i = 0; i < st.size(); ++i) empty[i] = st[i] == 0;
  const std::vector<double> wall_d2 =
      edt(empty, raster_.nx(), raster_.ny());  // squared cells to the nearest cell outside the region
  const std::vector<std::uint8_t> allowed = allowed_centres(wall_d2);
  mark_target(allowed);
  raster_.count_blocks();
  find_entries(allowed, wall_d2);
  stats_.components = entries_.size();
  make_lattice();
}

std::vector<std::uint8_t> Planner::allowed_centres(const std::vector<double>& wall_d2) const {
  const int nx = raster_.nx(), ny = raster_.ny();
  const double h = raster_.h();
  const auto& st = raster_.states();
  const double cl = walls_.clearance();
  std::vector<std::uint8_t> allowed(st.size(), 0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const std::size_t i = raster_.idx(x, y);
      if (st[i] == 0) continue;
      const double d = std::sqrt(wall_d2[i]) * h;  // within ~h of the wall distance
      if (d < cl - 2 * h) continue;
      allowed[i] = d > cl + 2 * h ? 1 : static_cast<std::uint8_t>(walls_.point_ok(raster_.centre(x, y)));
    }
  return allowed;
}

void Planner::mark_target(const std::vector<std::uint8_t>& allowed) {
  const double h = raster_.h();
  const auto& st = raster_.states();
  const std::vector<double> to_allowed = edt(allowed, raster_.nx(), raster_.ny());
  auto& target = raster_.target();
  // The passes' target: uncut cells within reach of an allowed centre cell. Leaving out the last
  // half cell (R − h/2) leaves the wall pass a sliver about one cell thick along every wall: side
  // on it is a light cut, but where the wall pass turns a convex corner of the centres' region it
  // takes a quarter arc of sliver in under a millimetre of travel, which reads 58–80° (measured
  // on a 60 × 40 rectangle at targets of 45–60°). Below kPassesTakeTheWallBandBelowDeg the
  // passes take that band themselves (R + 3h/4: every cell a disk at an allowed cell's centre
  // reaches, up to the raster), and the wall pass cuts next to nothing (2026-11-25: 45°, 50°,
  // 60° read 45.6°, 53.1°, 60.0° instead of 58.3°, 77.0°, 79.9°, for 3–4 % more time); at
  // 90° the sliver reads under the target and the passes leave it (taking it costs 7–14 %).
  const double reach = (R_ + (target_deg_ < kPassesTakeTheWallBandBelowDeg ? 0.75 : -0.5) * h) / h;
  for (std::size_t i = 0; i < st.size(); ++i) target[i] = st[i] == 1 && to_allowed[i] <= reach * reach;
}

void Planner::find_entries(const std::vector<std::uint8_t>& allowed, const std::vector<double>& wall_d2) {
  // Components of allowed centres (8-connected), numbered in raster order of their first cell:
  // the rows' runs of allowed cells, joined where runs of neighbouring rows overlap or touch
  // diagonally (union–find). O(cells). Each component's entry: its cell farthest from the walls
  // (the first in raster order on a tie).
  const int nx = raster_.nx(), ny = raster_.ny();
  std::vector<RunOf> arun;  // the runs of allowed cells, in raster order
  std::vector<std::size_t> row_first;
  allowed_runs(allowed, nx, ny, arun, row_first);
  const std::vector<std::size_t> root = join_runs(arun, row_first, ny);
  // A root is its component's first run (unions keep the smaller index), so numbering the roots
  // in run order numbers the components in raster order of their first cell.
  std::vector<int> comp_of(arun.size(), -1);
  std::vector<std::size_t> best;
  for (std::size_t i = 0; i < arun.size(); ++i) {
    const std::size_t r = root[i];
    if (comp_of[r] < 0) {
      comp_of[r] = static_cast<int>(best.size());
      best.push_back(raster_.idx(arun[i].x0, arun[i].y));
    }
    std::size_t& bi = best[static_cast<std::size_t>(comp_of[r])];
    for (int x = arun[i].x0; x <= arun[i].x1; ++x) {
      const std::size_t c = raster_.idx(x, arun[i].y);
      if (wall_d2[c] > wall_d2[bi]) bi = c;  // strictly: the first in raster order on a tie
    }
  }
  for (const std::size_t c : best)
    entries_.push_back({raster_.centre(static_cast<int>(c % static_cast<std::size_t>(nx)),
                                       static_cast<int>(c / static_cast<std::size_t>(nx))),
                        false});
}

void Planner::make_lattice() {
  const int nx = raster_.nx(), ny = raster_.ny();
  const double h = raster_.h();
  lat_lo_ = raster_.centre(0, 0);
  lnx_ = static_cast<int>(std::floor((nx - 1) * h / kLatticeMm)) + 1;
  lny_ = static_cast<int>(std::floor((ny - 1) * h / kLatticeMm)) + 1;
  lat_ok_.assign(lin(0, lny_, lnx_), -1);
  dead_.assign(lat_ok_.size(), 0);
  lat_safe_.assign(lat_ok_.size(), 0);
}

}  // namespace millnet::pocket::adaptive
