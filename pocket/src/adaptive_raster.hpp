#pragma once
// The adaptive planner's cleared-area raster (planner_adaptive.cpp): which cells are uncut, cut or
// outside the region, and the material sense the passes, rides and links steer by: the uncut cells
// a step would cut (a disk, or the crescent beyond the last disk), the uncut target cells near a
// position and their centroid. The out-of-line members are in adaptive_raster.cpp.
#include "millnet/pocket/geometry.hpp"

#include "raster_internal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace millnet::pocket::adaptive {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

using raster::lin;

/// The cleared-area raster: 0 = no material (centre outside the region), 1 = uncut, 2 = cut; a
/// cell is cut when its centre lies within R of a tool centre (the feed map's rule). Blocks of
/// kB × kB cells count their uncut cells (all, and those of the clearing's target) so that the
/// lattice's queries skip cleared blocks.
class Raster {
public:
  static constexpr int kB = 4;

  Raster(const Region& region, double h, double margin) : h_(h), inv_h_(1 / h) {
    const raster::Grid g = raster::grid_of(region, h, margin, "adaptive planner");
    lo_ = g.lo;
    nx_ = g.nx;
    ny_ = g.ny;
    st_ = raster::material(region, g);  // 1 = uncut material
    target_.assign(st_.size(), 0);
    bx_ = (nx_ + kB - 1) / kB;
    by_ = (ny_ + kB - 1) / kB;
  }

  [[nodiscard]] int nx() const { return nx_; }
  [[nodiscard]] int ny() const { return ny_; }
  [[nodiscard]] double h() const { return h_; }
  /// Changes whenever mark() is called (a cache key for counts of uncut cells).
  [[nodiscard]] std::uint64_t version() const { return version_; }
  [[nodiscard]] std::size_t idx(int x, int y) const { return lin(x, y, nx_); }
  [[nodiscard]] Vec2 centre(int x, int y) const { return lo_ + Vec2((x + 0.5) * h_, (y + 0.5) * h_); }
  [[nodiscard]] const std::vector<std::uint8_t>& states() const { return st_; }
  std::vector<std::uint8_t>& target() { return target_; }

  /// Call once target() is filled.
  void count_blocks();

  /// The columns (or rows, o = lo_.y()) whose centres lie within w of coordinate v, unclamped:
  /// [first, last], empty when first > last.
  [[nodiscard]] std::pair<int, int> run(double v, double w, double o) const {
    return {static_cast<int>(std::ceil((v - w - o) * inv_h_ - 0.5)),
            static_cast<int>(std::floor((v + w - o) * inv_h_ - 0.5))};
  }

  /// Calls g(y, x0, x1) for every row of the cells whose centre lies within r of c, with the row's
  /// run of such cells (clamped to the raster, non-empty or not); rows where keep(y) is false are
  /// skipped before their run is computed.
  template <class G, class K = bool (*)(int)>
  void rows(
      const Vec2& c, double r, G&& g, K&& keep = [](int) { return true; }) const {
    const auto [ya, yb] = run(c.y(), r, lo_.y());
    for (int y = std::max(0, ya); y <= std::min(ny_ - 1, yb); ++y) {
      if (!keep(y)) continue;
      const double dy = lo_.y() + (y + 0.5) * h_ - c.y();
      const double w2 = r * r - dy * dy;
      if (w2 < 0) continue;
      const auto [xa, xb] = run(c.x(), std::sqrt(w2), lo_.x());
      g(y, std::max(0, xa), std::min(nx_ - 1, xb));
    }
  }

  /// Calls f(i) for every cell whose centre lies within r of c. O((2r/h)²).
  template <class F>
  void disk(const Vec2& c, double r, F&& f) const {
    rows(c, r, [&](int y, int x0, int x1) {
      for (int x = x0; x <= x1; ++x) f(idx(x, y));
    });
  }

  /// Uncut cells within r of c (what a tool there would cut).
  [[nodiscard]] int fresh(const Vec2& c, double r) const;

  /// fresh(c, r) for a tool whose disk of radius r about p holds no uncut cell: only the crescent
  /// of cells within r of c and not within r of p is visited (per row, the disk's run minus p's
  /// run, by the same rounding as disk): O(r·|c − p|/h² + r/h) instead of O((r/h)²).
  [[nodiscard]] int fresh_beyond(const Vec2& p, const Vec2& c, double r) const;

  /// Uncut cells of row y from x0 to x1.
  [[nodiscard]] int uncut_in(int y, int x0, int x1) const {
    int n = 0;
    const std::uint8_t* row = st_.data() + idx(0, y);
    for (int x = x0; x <= x1; ++x) n += row[x] == 1;
    return n;
  }

  /// The run of the disk of radius r about p on row y, unclamped; {1, 0} (empty) when the row misses it.
  [[nodiscard]] std::pair<int, int> row_run(const Vec2& p, double r, int y) const {
    const double dy = lo_.y() + (y + 0.5) * h_ - p.y();
    const double v2 = r * r - dy * dy;
    return v2 >= 0 ? run(p.x(), std::sqrt(v2), lo_.x()) : std::pair<int, int>{1, 0};
  }

  /// Calls g(y, first, last) for the runs (possibly empty) of the cells within r of c (disk's
  /// rounding) outside the other disk, whose run on row y is other(y) (row_run's convention).
  template <class P, class G, class K = bool (*)(int)>
  void crescent(
      const Vec2& c, double r, P&& other, G&& g, K&& keep = [](int) { return true; }) const {
    rows(
        c, r,
        [&](int y, int x0, int x1) {
          minus({x0, x1}, other(y), [&](int a, int b) { g(y, a, b); });
        },
        keep);
  }

  /// Calls g(first, last) for the (possibly empty) pieces of run a outside run b (empty runs:
  /// first > last).
  template <class G>
  static void minus(std::pair<int, int> a, std::pair<int, int> b, G&& g) {
    if (a.first > a.second) return;
    if (b.first > b.second) {
      g(a.first, a.second);
      return;
    }
    g(a.first, std::min(a.second, b.first - 1));
    g(std::max(a.first, b.second + 1), a.second);
  }

  /// A disk's runs on a band of rows (unclamped; empty when first > last), for the counts that
  /// use one disk many times: a position's candidate steps (runs), the material sense (sensed).
  struct DiskRuns {
    Vec2 c{kInf, kInf};
    double r = -1;
    int y0 = 0;
    std::vector<std::pair<int, int>> x;
    /// The run on row y; empty beyond the band.
    [[nodiscard]] std::pair<int, int> at(int y) const {
      const auto k = static_cast<std::size_t>(y - y0);
      return y >= y0 && k < x.size() ? x[k] : std::pair<int, int>{1, 0};
    }
    [[nodiscard]] int rows_end() const { return y0 + static_cast<int>(x.size()); }
  };
  /// The runs of the disk of radius r about c on the rows within r + pad of c.y, into `out` (its
  /// buffer reused); with pad 0, the rows of rows(c, r).
  void disk_runs(const Vec2& c, double r, DiskRuns& out, double pad = 0) const;

  /// A position's disk runs for fresh_beyond's many candidate steps from it, and per row whether
  /// any uncut cell lies in the band the crescent of such a step can reach (within r + pad + h of
  /// p, outside p's run).
  struct Runs {
    DiskRuns disk;
    std::vector<std::uint8_t> live;
  };
  /// The runs of the disk of radius r about p on the rows within r + pad of p.y, into `out` (its
  /// buffers reused). O((r + pad)/h · (pad/h + 1)).
  void runs(const Vec2& p, double r, double pad, Runs& out) const;

  /// fresh_beyond(p, c, r) with p's runs from runs(p, r, pad), |c − p| ≤ pad: rows without an
  /// uncut cell in p's band are skipped.
  [[nodiscard]] int fresh_beyond(const Runs& pr, const Vec2& c, double r) const;

  /// Cuts the cells within r of c; returns how many were uncut.
  /// After a mark(p, r), every cell within r of p is no longer uncut, so the next mark within r
  /// of p visits only the crescent beyond p's disk (by the same rounding): O(r·|c − p|/h² + r/h)
  /// instead of O((r/h)²), the same cells cut.
  int mark(const Vec2& c, double r);

  /// No uncut cell within r of c (block-pruned).
  [[nodiscard]] bool clear_within(const Vec2& c, double r) const;

  /// No uncut cell centre within r (+ tol::on_curve_mm) of the segment a–b (block-pruned): then no disk of
  /// radius r about a point of it holds one, whatever the rounding of disk().
  [[nodiscard]] bool capsule_clear(const Vec2& a, const Vec2& b, double r) const;

  /// Uncut target cells within r of c (by rows()' rounding): their number, the nearest one and
  /// their centroid (each written only when there is one).
  /// Without `nearest` (the material sense, called at every step of a pass or a ride), the count
  /// and index sums are kept for the last disk: mark() takes its cut cells off them, and a disk
  /// moved by at most kSenseShiftCells cells is counted from the last one by the two crescents
  /// between them, O(r/h + r·|c − c'|/h²) instead of the full walk. The full walk counts a block
  /// whose every cell lies in the disk by its kept count and index sums: O(r²/(kB h)² + r/h · kB).
  /// The index sums are integers: the same disk gives the same figures whichever way it was reached.
  int target_near(const Vec2& c, double r, Vec2* nearest, Vec2* centroid = nullptr) const;

  [[nodiscard]] std::size_t uncut_target_cells() const;

private:
  [[nodiscard]] std::size_t block(int x, int y) const { return lin(x / kB, y / kB, bx_); }

  /// A sensing disk moved by more than this many cells is walked whole, not by crescents (a pass
  /// moves 2 D/80 cells a step, a ride 8: the crescents then visit ≈ 2·shift·2r/h² cells, about
  /// what the block walk visits).
  static constexpr double kSenseShiftCells = 8;

  /// Uncut target cells: their number and index sums.
  struct TargetSums {
    long long n = 0, sx = 0, sy = 0;
  };
  /// Adds (sign +1) or takes off (−1) the uncut target cells of row y from x0 to x1 (clamped).
  void add_target(int y, int x0, int x1, int sign, TargetSums& t) const;
  /// The uncut target cells of disk d, block by block; with `nearest`, every cell is visited and
  /// the nearest to d.c written (the first in raster order of blocks, then of cells, on a tie).
  TargetSums walk_target(const DiskRuns& d, Vec2* nearest) const;

  /// The uncut target cells within r of c, kept for the last disk (target_near).
  TargetSums sensed(const Vec2& c, double r) const;
  static double sq(double v) { return v * v; }

  /// Visits the cells of the blocks within r of c whose count is > 0; f(x, y) returns false to stop.
  template <class F>
  void blocks(const Vec2& c, double r, const std::vector<int>& count, F&& f) const {
    const double bs = kB * h_;
    in_box(c - Vec2(r, r), c + Vec2(r, r), count, [&](int bx, int by, std::size_t) {
      const Vec2 blo = lo_ + Vec2(bx * bs, by * bs);
      const Vec2 q = c.cwiseMax(blo).cwiseMin(blo + Vec2(bs, bs));
      if ((q - c).squaredNorm() > r * r) return true;
      for (int y = by * kB; y < std::min(ny_, (by + 1) * kB); ++y)
        for (int x = bx * kB; x < std::min(nx_, (bx + 1) * kB); ++x)
          if (!f(x, y)) return false;
      return true;
    });
  }

  /// Calls g(bx, by, block index) for the blocks meeting the box [lo, hi] whose count is > 0, while
  /// g returns true; false when g stopped the walk.
  template <class G>
  bool in_box(const Vec2& lo, const Vec2& hi, const std::vector<int>& count, G&& g) const {
    const double bs = kB * h_;
    const int bx0 = std::max(0, static_cast<int>(std::floor((lo.x() - lo_.x()) / bs)));
    const int bx1 = std::min(bx_ - 1, static_cast<int>(std::floor((hi.x() - lo_.x()) / bs)));
    const int by0 = std::max(0, static_cast<int>(std::floor((lo.y() - lo_.y()) / bs)));
    const int by1 = std::min(by_ - 1, static_cast<int>(std::floor((hi.y() - lo_.y()) / bs)));
    for (int by = by0; by <= by1; ++by)
      for (int bx = bx0; bx <= bx1; ++bx) {
        const std::size_t b = lin(bx, by, bx_);
        if (count[b] > 0 && !g(bx, by, b)) return false;
      }
    return true;
  }

  double h_, inv_h_;
  Vec2 lo_;
  int nx_ = 0, ny_ = 0, bx_ = 0, by_ = 0;
  std::vector<std::uint8_t> st_, target_;
  std::vector<int> uncut_, tuncut_;
  std::uint64_t version_ = 1;
  Vec2 marked_{kInf, kInf};  ///< the last mark's centre and radius: its disk holds no uncut cell
  double marked_r_ = -1;
  std::vector<std::array<long long, 2>> tsum_;  ///< per block: sums of the uncut target cells' x and y indices
  mutable DiskRuns sense_, scratch_;            ///< the kept sense disk; a scratch disk
  mutable TargetSums sense_sums_;               ///< the uncut target cells of sense_
  mutable bool sense_valid_ = false;
};

}  // namespace millnet::pocket::adaptive
