// The remaining material split into rest, scallop and uncut (SurfaceMetrics in zmap.hpp): a rest
// test per block of cells (can the cutter touch the design there at all?), then a walk across the
// feed from each cell left (is it a cusp between passes?).
#include "metrics_internal.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

namespace millnet::simulate::metrics {

namespace {

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

// The cutter's profile f(d) for 0 ≤ d ≤ R with the arithmetic of tooling::Cutter::profile_height
// (the same bits), inlined: the test below evaluates it (R / (stride·cell))² times per placement.
struct Profile {
  explicit Profile(const tooling::Cutter& c)
      : drill(c.shape() == tooling::CutterType::Drill),
        r(c.profile_corner_radius()),
        a(c.radius() - r),
        tan_half(std::tan(0.5 * c.point_angle_deg * std::numbers::pi / 180)) {}
  [[nodiscard]] double at(double d) const {
    if (drill) return d / tan_half;
    if (d <= a) return 0.0;
    const double u = d - a;
    return r - std::sqrt(std::max(0.0, r * r - u * u));
  }
  bool drill;
  double r, a, tan_half;
};

// Can `cutter` touch the design at cell c without cutting into it anywhere else by more than
// `tol`? The cutter is placed so that its profile passes through (c, design(c)) with its axis
// offset from c down the slope by t: first the contact offset of a smooth surface with the
// design's normal at c (ball R·sinθ, bull (R − rc) + rc·sinθ, flat R on a slope), then 0, R/2, R.
// Each placement is checked against the design sampled every `stride` cells under the cutter.
// O(t's × (R / (stride·cell))²) per call.
bool reachable(const GridSpec& spec, const std::vector<double>& design, const tooling::Cutter& cutter, std::size_t c,
               std::size_t stride, double tol) {
  const Profile f(cutter);
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
    const double tip = dc - f.at(std::min(t, R));
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
        const double r2 = dx * dx + dy * dy;  // (not std::hypot: no overflow to guard against here, 3× faster)
        if (r2 > R * R) continue;
        const double r = std::sqrt(r2);
        const double dq = design[static_cast<std::size_t>(qy * nx + qx)];
        if (dq > tip + f.at(r) + tol) {
          ok = false;
          break;
        }
      }
    }
    if (ok) return true;
  }
  return false;
}

// Per k × k block of cells that holds material left (above > tol), the block's probe: its cell with
// a design height nearest the block's centre (first in row order on a tie); SIZE_MAX for the other
// blocks. The probe depends on the design only, never on the program, so every program machined on
// one design asks the rest test the same questions (ReachMemo answers them once) and the rest
// material is the same for every strategy, as SurfaceMetrics says. Blocks are numbered row by
// row, ⌈nx / k⌉ per row. O(cells), no division per cell.
std::vector<std::size_t> block_probes(const GridSpec& spec, const std::vector<double>& design, const CellValues& above,
                                      double tol, std::size_t k, int nthreads) {
  const std::size_t nx = spec.nx, ny = spec.ny;
  const std::size_t lx = (nx + k - 1) / k, ly = (ny + k - 1) / k;
  std::vector<std::size_t> probe(lx * ly, SIZE_MAX);
  std::vector<std::size_t> probe_d2(lx * ly, SIZE_MAX);
  std::vector<std::uint8_t> left(lx * ly, 0);
  const auto half = static_cast<std::ptrdiff_t>(k - 1);
  // A row of blocks per iteration (its blocks are its own): the same for any thread count.
#pragma omp parallel for schedule(dynamic, 4) num_threads(nthreads)
  for (std::ptrdiff_t bl = 0; bl < static_cast<std::ptrdiff_t>(ly); ++bl) {
    const auto by = static_cast<std::size_t>(bl);
    for (std::size_t ry = 0, iy = by * k; ry < k && iy < ny; ++ry, ++iy) {
      const std::ptrdiff_t dy = 2 * static_cast<std::ptrdiff_t>(ry) - half;
      for (std::size_t ix = 0, bx = 0, rx = 0; ix < nx; ++ix) {
        const std::size_t i = iy * nx + ix, b = by * lx + bx;
        if (above[i] > tol) left[b] = 1;
        if (!std::isnan(design[i])) {
          const std::ptrdiff_t dx = 2 * static_cast<std::ptrdiff_t>(rx) - half;
          const auto d2 = static_cast<std::size_t>(dx * dx + dy * dy);
          if (d2 < probe_d2[b]) {
            probe_d2[b] = d2;
            probe[b] = i;
          }
        }
        if (++rx == k) {
          rx = 0;
          ++bx;
        }
      }
    }
  }
  for (std::size_t b = 0; b < probe.size(); ++b)  // O(blocks)
    if (left[b] == 0) probe[b] = SIZE_MAX;
  return probe;
}

// Per cell: kOff off the surface (NaN design), kCut cut to the design (above ≤ tol), kLeft
// material left (above > tol), kNone neither (NaN above on the surface). One byte instead of two doubles: the walk below crosses rows at random, and 1
// byte a cell keeps what it reads in cache (the answers are those of the doubles). O(cells).
enum CellClass : std::uint8_t { kOff = 0, kCut = 1, kLeft = 2, kNone = 3 };
std::vector<std::uint8_t> cell_classes(const std::vector<double>& design, const CellValues& above, double tol,
                                       int nthreads) {
  std::vector<std::uint8_t> cls(design.size());
  const auto n = static_cast<std::ptrdiff_t>(design.size());
#pragma omp parallel for schedule(static) num_threads(nthreads)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    cls[i] = std::isnan(design[i]) ? kOff : above[i] <= tol ? kCut : above[i] > tol ? kLeft : kNone;
  }
  return cls;
}

// The cells a walk across the feed visits, as offsets from the cell it starts at, per across-feed
// direction (a, b). The walk starts at a cell's centre, and its k-th sample on side σ = ±1 lies
// σ·k·cell along (a, b): column floor((x + σ·k·cell·a − x0) / cell), that is the start's column
// plus floor(0.5 + σ·k·a), and the same in rows, whatever the start — unless 0.5 + σ·k·a comes
// within the rounding error of that arithmetic of an integer. Such a step is kExact: the walk
// computes it from the coordinates, as it always did. So a walk visits the same cells bit for bit,
// with one load and one add a step instead of two divisions and two floors. Per thread, a
// direct-mapped cache of the last 256 directions, each step filled when a walk first takes it
// (lines share their direction along the move; an arc's changes per cell and misses, costing the
// floors the walk took before).
class WalkOffsets {
public:
  static constexpr std::int32_t kExact = INT32_MIN;
  struct Step {
    std::int32_t dx, dy;
  };

  WalkOffsets(const GridSpec& spec, std::ptrdiff_t steps) : steps_(steps) {
    // The rounding error of (x + σ·k·cell·a − x0) / cell, in cells, is below 8ε·(M / cell) for M the
    // largest coordinate the arithmetic meets (x0, x, the step); 0.5 + σ·k·a's own below 2ε·(k + 1).
    const double eps = std::numeric_limits<double>::epsilon();
    const double m =
        std::max({std::abs(spec.x0), std::abs(spec.y0), std::abs(spec.x0 + spec.cell * static_cast<double>(spec.nx)),
                  std::abs(spec.y0 + spec.cell * static_cast<double>(spec.ny))}) +
        spec.cell * static_cast<double>(steps + 1);
    margin_ = 16 * eps * (m / spec.cell + static_cast<double>(steps) + 1);
    key_.assign(kSlots, {std::numeric_limits<std::uint64_t>::max(), std::numeric_limits<std::uint64_t>::max(), {0, 0}});
    table_.resize(kSlots * 2 * static_cast<std::size_t>(steps));
  }

  // The slot of direction (a, b): its steps 1 … steps on side −1, then on side +1, filled in order
  // as walks first take them (a walk stops after a few steps, and a miss must not cost more than
  // the walk it serves).
  std::size_t of(double a, double b) {
    const auto ka = std::bit_cast<std::uint64_t>(a), kb = std::bit_cast<std::uint64_t>(b);
    const std::size_t slot = ((ka * 0x9E3779B97F4A7C15ull) ^ (kb * 0xC2B2AE3D27D4EB4Full)) >> 56;
    Key& key = key_[slot];
    if (key.a != ka || key.b != kb) key = {ka, kb, {0, 0}};
    return slot;
  }

  // Step k ≥ 1 on side 0 (−1) or 1 (+1) of direction (a, b) in `slot`; a walk asks for k after k − 1.
  Step step(std::size_t slot, int side, std::ptrdiff_t k, double a, double b) {
    Step& e = table_[(slot * 2 + static_cast<std::size_t>(side)) * static_cast<std::size_t>(steps_) +
                     static_cast<std::size_t>(k - 1)];
    std::ptrdiff_t& filled = key_[slot].filled[side];
    if (k > filled) {
      const double sk = (side == 0 ? -1.0 : 1.0) * static_cast<double>(k);
      e = {offset(sk * a), offset(sk * b)};
      filled = k;
    }
    return e;
  }

private:
  static constexpr std::size_t kSlots = 256;
  [[nodiscard]] std::int32_t offset(double along) const {
    const double w = 0.5 + along, f = std::floor(w);
    if (!(std::abs(w) < 1e9) || w - f <= margin_ || f + 1 - w <= margin_) return kExact;
    return static_cast<std::int32_t>(f);
  }
  std::ptrdiff_t steps_;
  double margin_ = 0;
  struct Key {
    std::uint64_t a, b;
    std::ptrdiff_t filled[2];  // steps known per side
  };
  std::vector<Key> key_;
  std::vector<Step> table_;
};

// Whether the cell i with material left lies between passes: walking from it across the feed of
// the move that last cut it, a cell cut to the design comes within `steps` cells on both sides,
// before the grid or the surface ends. A walk from a cell more than steps + 1 cells inside the grid
// cannot leave it (step k lands within k + 1 cells) and skips the grid's bounds. `walks` null:
// every step from its coordinates (the tests' oracle).
bool between_passes(const ZMap& machined, const std::vector<std::uint8_t>& cls, std::ptrdiff_t steps, std::size_t i,
                    WalkOffsets* walks) {
  const GridSpec& spec = machined.spec();
  const auto nx = static_cast<std::ptrdiff_t>(spec.nx), ny = static_cast<std::ptrdiff_t>(spec.ny);
  const auto ix = static_cast<std::ptrdiff_t>(i % spec.nx), iy = static_cast<std::ptrdiff_t>(i / spec.nx);
  const double x = spec.x(static_cast<std::size_t>(ix)), y = spec.y(static_cast<std::size_t>(iy));
  double ax = 0, ay = 0;
  if (!machined.across_feed(i, x, y, ax, ay)) return false;
  // Step s on `side` (0: −1, 1: +1) from its coordinates: false when it leaves the grid.
  auto exact = [&](int side, std::ptrdiff_t s, std::ptrdiff_t& qx, std::ptrdiff_t& qy) {
    const double d = (side == 0 ? -1.0 : 1.0) * static_cast<double>(s) * spec.cell;
    const double fx = std::floor((x + d * ax - spec.x0) / spec.cell),
                 fy = std::floor((y + d * ay - spec.y0) / spec.cell);
    if (fx < 0 || fy < 0 || fx >= static_cast<double>(nx) || fy >= static_cast<double>(ny)) return false;
    qx = static_cast<std::ptrdiff_t>(fx);
    qy = static_cast<std::ptrdiff_t>(fy);
    return true;
  };
  const bool inside = ix > steps && iy > steps && ix + steps + 1 < nx && iy + steps + 1 < ny;
  const std::size_t slot = walks != nullptr ? walks->of(ax, ay) : 0;
  for (int side = 0; side < 2; ++side) {
    bool met = false;
    for (std::ptrdiff_t s = 1; s <= steps; ++s) {
      const WalkOffsets::Step o =
          walks != nullptr ? walks->step(slot, side, s, ax, ay) : WalkOffsets::Step{WalkOffsets::kExact, 0};
      std::ptrdiff_t qx = 0, qy = 0;
      if (o.dx == WalkOffsets::kExact || o.dy == WalkOffsets::kExact) {  // near a cell's edge (or no table)
        if (!exact(side, s, qx, qy)) break;
      } else {
        qx = ix + o.dx;
        qy = iy + o.dy;
        if (!inside && (qx < 0 || qy < 0 || qx >= nx || qy >= ny)) break;
      }
      const std::uint8_t c = cls[static_cast<std::size_t>(qy * nx + qx)];
      if (c == kOff) break;
      if (c == kCut) {
        met = true;
        break;
      }
    }
    if (!met) return false;
  }
  return true;
}

}  // namespace

// Splits the remaining material (cells with e > allowance + tolerance) into rest, scallop and
// uncut (definitions in zmap.hpp). Cells: the rest test once per k × k block that holds material
// left (O((R / (k·cell))²) each), each such cell's walk ≤ 2·R / cell cells. Counts and
// the max are reductions: the same for any thread count.
// `above` is (e − allowance)·cos(slope) per cell (NaN off the surface), computed once by the caller.
void split_remaining(const ZMap& machined, const std::vector<double>& design, const CellValues& above,
                     const MetricsOptions& opt, SurfaceMetrics& out, std::vector<std::uint8_t>& rest_cell) {
  const GridSpec& spec = machined.spec();
  const tooling::Cutter& cutter = *opt.cutter;
  cutter.check();
  const std::size_t nx = spec.nx, ny = spec.ny, k = opt.reach_every, lx = (nx + k - 1) / k;
  // The rest test runs once per block that holds material left, at its probe; every cell left in the
  // block takes its answer.
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  const std::vector<std::size_t> probe = block_probes(spec, design, above, opt.tolerance_mm, k, nthreads);
  std::vector<std::uint8_t> reach(probe.size(), 1);  // 1 = reachable, 0 = rest
  // A block another program on this design already tested keeps its answer (ReachMemo): its probe
  // is the same cell; each iteration writes its own block.
  std::vector<std::uint8_t>* memo =
      opt.reach_memo ? &opt.reach_memo->answers(spec, cutter, k, opt.tolerance_mm) : nullptr;
  const auto nl = static_cast<std::ptrdiff_t>(reach.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(nthreads)
  for (std::ptrdiff_t l = 0; l < nl; ++l) {
    const auto ul = static_cast<std::size_t>(l);
    const std::size_t c = probe[ul];
    if (c == SIZE_MAX) continue;
    std::uint8_t known = memo != nullptr ? (*memo)[ul] : 0;
    if (known == 0) {
      known = reachable(spec, design, cutter, c, k, opt.tolerance_mm) ? 1 : 2;
      if (memo != nullptr) (*memo)[ul] = known;
    }
    reach[ul] = known == 1 ? 1 : 0;
  }
  const auto steps = static_cast<std::ptrdiff_t>(std::ceil(cutter.radius() / spec.cell));
  const std::vector<std::uint8_t> cls = cell_classes(design, above, opt.tolerance_mm, nthreads);
  std::size_t rest = 0, scallop = 0, uncut = 0;
  double scallop_max = 0;
  const auto rows = static_cast<std::ptrdiff_t>(ny);
#pragma omp parallel num_threads(nthreads) reduction(+ : rest, scallop, uncut) reduction(max : scallop_max)
  {
    std::optional<WalkOffsets> walks;
    if (opt.walk_tables) walks.emplace(spec, steps);
#pragma omp for schedule(dynamic, 8)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      const auto iy = static_cast<std::size_t>(r);
      for (std::size_t ix = 0; ix < nx; ++ix) {
        const std::size_t i = iy * nx + ix;
        if (cls[i] != kLeft) continue;
        if (reach[iy / k * lx + ix / k] == 0) {
          ++rest;
          if (!rest_cell.empty()) rest_cell[i] = 1;
        } else if (between_passes(machined, cls, steps, i, walks ? &*walks : nullptr)) {
          ++scallop;
          scallop_max = std::max(scallop_max, above[i]);
        } else {
          ++uncut;
        }
      }
    }
  }
  const double cell_area = spec.cell * spec.cell;
  out.rest_area_mm2 = static_cast<double>(rest) * cell_area;
  out.scallop_area_mm2 = static_cast<double>(scallop) * cell_area;
  out.uncut_area_mm2 = static_cast<double>(uncut) * cell_area;
  out.scallop_max_mm = scallop_max;
}

}  // namespace millnet::simulate::metrics

namespace millnet::simulate {

std::vector<std::uint8_t>& ReachMemo::answers(const GridSpec& grid, const tooling::Cutter& cutter,
                                              std::size_t reach_every, double tolerance_mm) {
  const auto same_grid = [&] {
    return grid.x0 == grid_.x0 && grid.y0 == grid_.y0 && grid.cell == grid_.cell && grid.nx == grid_.nx &&
           grid.ny == grid_.ny;
  };
  const auto same_cutter = [&] {
    return cutter.shape() == cutter_.shape() && cutter.diameter == cutter_.diameter &&
           cutter.profile_corner_radius() == cutter_.profile_corner_radius() &&
           cutter.point_angle_deg == cutter_.point_angle_deg;
  };
  const std::size_t blocks = ((grid.nx + reach_every - 1) / reach_every) * ((grid.ny + reach_every - 1) / reach_every);
  if (answers_.size() != blocks || !same_grid() || !same_cutter() || reach_every != reach_every_ ||
      tolerance_mm != tolerance_mm_) {
    grid_ = grid;
    cutter_ = cutter;
    reach_every_ = reach_every;
    tolerance_mm_ = tolerance_mm;
    answers_.assign(blocks, 0);
  }
  return answers_;
}

}  // namespace millnet::simulate
