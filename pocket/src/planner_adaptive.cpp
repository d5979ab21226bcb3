// The adaptive (constant-engagement) planner (planner_adaptive.hpp).
#include "millnet/pocket/planner_adaptive.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "offset.hpp"
#include "raster_internal.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <limits>
#include <utility>
#include <numbers>
#include <optional>
#include <queue>
#include <string>
#include <vector>

namespace millnet::pocket {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Link lattice spacing, mm: positions a link may pass through and passes may start from.
constexpr double kLatticeMm = 1.0;
/// Lattice positions keep this much more than the cutting clearance from the walls, mm: a chord
/// between two of them then cannot dip into the clearance round a convex island (sagitta of a
/// 1.5 mm chord on a 5 mm arc: 0.06 mm).
constexpr double kLinkMarginMm = 0.1;
/// Turn per step while cutting (the first step of a pass searches ±90°), degrees.
constexpr double kMaxTurnDeg = 12;
/// A pass senses uncut material this far beyond the tool's radius, mm; it also ends after R plus
/// this much path that cut nothing.
constexpr double kSenseMm = 3.0;
/// A pass ends when the best step it may take points more than this off the front's tangent, away
/// from the material (it could only back away), degrees.
constexpr double kBlockedDeg = 75;
/// A ride back along the front stops when a step would point more than this away from the material.
constexpr double kRideAwayDeg = 60;
/// Rides back shorter than kRideMinMm gain nothing; none goes beyond kRideMaxMm.
constexpr double kRideMinMm = 1.0;
constexpr double kRideMaxMm = 300.0;
/// A ride steps this many planning steps at a time (it cuts nothing at any of its positions; between
/// two of them 4 steps = D/10 apart, a cell within R of the move but of neither lies at most
/// (D/10)²/(8R) = D/400 beyond R of both, as air_ok allows).
constexpr int kRideStepSteps = 4;
/// A tool with no link out backtracks along its own path, trying a link every kBacktrackMm, at
/// most kBacktrackTries times.
constexpr double kBacktrackMm = 2.0;
constexpr int kBacktrackTries = 60;
/// Wall loops: a possible start every kWallStartMm of straight edge; the kWallStartTries nearest
/// starts are tried in turn.
constexpr double kWallStartMm = 5.0;
constexpr std::size_t kWallStartTries = 40;
/// Below this engagement target the passes also take the wall band (see prepare()), degrees.
constexpr double kPassesTakeTheWallBandBelowDeg = 85;
/// Uncut material worth a pass, in cells of D/40 (less is raster noise); min_work_ is this area in
/// the raster's own cells.
constexpr double kMinWorkCellsD40 = 4;

using raster::lin;

Vec2 rot(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

using raster::edt;

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
  void count_blocks() {
    uncut_.assign(lin(0, by_, bx_), 0);
    tuncut_.assign(uncut_.size(), 0);
    tsum_.assign(uncut_.size(), {0, 0});
    for (int y = 0; y < ny_; ++y)
      for (int x = 0; x < nx_; ++x)
        if (st_[idx(x, y)] == 1) {
          ++uncut_[block(x, y)];
          if (target_[idx(x, y)]) {
            ++tuncut_[block(x, y)];
            tsum_[block(x, y)][0] += x;
            tsum_[block(x, y)][1] += y;
          }
        }
  }

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
  [[nodiscard]] int fresh(const Vec2& c, double r) const {
    int n = 0;
    disk(c, r, [&](std::size_t i) { n += st_[i] == 1; });
    return n;
  }

  /// fresh(c, r) for a tool whose disk of radius r about p holds no uncut cell: only the crescent
  /// of cells within r of c and not within r of p is visited (per row, the disk's run minus p's
  /// run, by the same rounding as disk): O(r·|c − p|/h² + r/h) instead of O((r/h)²).
  [[nodiscard]] int fresh_beyond(const Vec2& p, const Vec2& c, double r) const {
    int n = 0;
    crescent(
        c, r, [&](int y) { return row_run(p, r, y); }, [&](int y, int x0, int x1) { n += uncut_in(y, x0, x1); });
    return n;
  }

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
  void disk_runs(const Vec2& c, double r, DiskRuns& out, double pad = 0) const {
    const auto [ya, yb] = run(c.y(), r + pad, lo_.y());
    out.c = c;
    out.r = r;
    out.y0 = ya;
    out.x.clear();
    for (int y = ya; y <= yb; ++y) out.x.push_back(row_run(c, r, y));
  }

  /// A position's disk runs for fresh_beyond's many candidate steps from it, and per row whether
  /// any uncut cell lies in the band the crescent of such a step can reach (within r + pad + h of
  /// p, outside p's run).
  struct Runs {
    DiskRuns disk;
    std::vector<std::uint8_t> live;
  };
  /// The runs of the disk of radius r about p on the rows within r + pad of p.y, into `out` (its
  /// buffers reused). O((r + pad)/h · (pad/h + 1)).
  void runs(const Vec2& p, double r, double pad, Runs& out) const {
    disk_runs(p, r, out.disk, pad);
    out.live.clear();
    for (int y = out.disk.y0; y < out.disk.rows_end(); ++y) {
      int n = 0;
      if (y >= 0 && y < ny_) {
        // A cell of a disk of radius r about c, |c − p| ≤ pad, lies within r + pad of p; the extra
        // cell covers the rounding of both runs.
        auto [b0, b1] = row_run(p, r + pad + h_, y);
        minus({std::max(0, b0), std::min(nx_ - 1, b1)}, out.disk.at(y),
              [&](int x0, int x1) { n += uncut_in(y, x0, x1); });
      }
      out.live.push_back(n > 0 ? 1 : 0);
    }
  }

  /// fresh_beyond(p, c, r) with p's runs from runs(p, r, pad), |c − p| ≤ pad: rows without an
  /// uncut cell in p's band are skipped.
  [[nodiscard]] int fresh_beyond(const Runs& pr, const Vec2& c, double r) const {
    int n = 0;
    const DiskRuns& d = pr.disk;
    crescent(
        c, r, [&](int y) { return d.at(y); }, [&](int y, int x0, int x1) { n += uncut_in(y, x0, x1); },
        [&](int y) { return y < d.y0 || y >= d.rows_end() || pr.live[static_cast<std::size_t>(y - d.y0)] != 0; });
    return n;
  }

  /// Cuts the cells within r of c; returns how many were uncut.
  /// After a mark(p, r), every cell within r of p is no longer uncut, so the next mark within r
  /// of p visits only the crescent beyond p's disk (by the same rounding): O(r·|c − p|/h² + r/h)
  /// instead of O((r/h)²), the same cells cut.
  int mark(const Vec2& c, double r) {
    int n = 0;
    ++version_;
    const auto cut = [&](int x, int y) {  // true when it cut a target cell
      const std::size_t i = idx(x, y);
      if (st_[i] != 1) return false;
      st_[i] = 2;
      ++n;
      --uncut_[block(x, y)];
      if (target_[i]) {
        --tuncut_[block(x, y)];
        tsum_[block(x, y)][0] -= x;
        tsum_[block(x, y)][1] -= y;
        return true;
      }
      return false;
    };
    const auto cut_run = [&](int y, int x0, int x1) {
      // The kept sense disk (target_near) loses the target cells cut inside it too.
      const auto [s0, s1] = sense_valid_ ? sense_.at(y) : std::pair<int, int>{1, 0};
      for (int x = x0; x <= x1; ++x)
        if (cut(x, y) && s0 <= x && x <= s1) {
          --sense_sums_.n;
          sense_sums_.sx -= x;
          sense_sums_.sy -= y;
        }
    };
    if (r == marked_r_ && (c - marked_).squaredNorm() < r * r)
      crescent(
          c, r, [&](int y) { return row_run(marked_, r, y); }, cut_run);
    else
      rows(c, r, cut_run);
    marked_ = c;
    marked_r_ = r;
    return n;
  }

  /// No uncut cell within r of c (block-pruned).
  [[nodiscard]] bool clear_within(const Vec2& c, double r) const {
    bool ok = true;
    blocks(c, r, uncut_, [&](int x, int y) {
      if (st_[idx(x, y)] == 1 && (centre(x, y) - c).squaredNorm() <= r * r) ok = false;
      return ok;
    });
    return ok;
  }

  /// No uncut cell centre within r (+ 1e-9 mm) of the segment a–b (block-pruned): then no disk of
  /// radius r about a point of it holds one, whatever the rounding of disk().
  [[nodiscard]] bool capsule_clear(const Vec2& a, const Vec2& b, double r) const {
    const double bs = kB * h_, rr = r + 1e-9;
    const Vec2 ab = b - a;
    const double L2 = ab.squaredNorm();
    const auto dist2 = [&](const Vec2& q) {
      const double t = L2 > 0 ? std::clamp((q - a).dot(ab) / L2, 0.0, 1.0) : 0.0;
      return (q - (a + t * ab)).squaredNorm();
    };
    const double half_diag = bs * std::numbers::sqrt2 / 2;
    return in_box(a.cwiseMin(b) - Vec2(rr, rr), a.cwiseMax(b) + Vec2(rr, rr), uncut_, [&](int bx, int by, std::size_t) {
      const Vec2 bc = lo_ + Vec2((bx + 0.5) * bs, (by + 0.5) * bs);
      if (std::sqrt(dist2(bc)) > rr + half_diag) return true;
      for (int y = by * kB; y < std::min(ny_, (by + 1) * kB); ++y)
        for (int x = bx * kB; x < std::min(nx_, (bx + 1) * kB); ++x)
          if (st_[idx(x, y)] == 1 && dist2(centre(x, y)) <= rr * rr) return false;
      return true;
    });
  }

  /// Uncut target cells within r of c (by rows()' rounding): their number, the nearest one and
  /// their centroid (each written only when there is one).
  /// Without `nearest` (the material sense, called at every step of a pass or a ride), the count
  /// and index sums are kept for the last disk: mark() takes its cut cells off them, and a disk
  /// moved by at most kSenseShiftCells cells is counted from the last one by the two crescents
  /// between them, O(r/h + r·|c − c'|/h²) instead of the full walk. The full walk counts a block
  /// whose every cell lies in the disk by its kept count and index sums: O(r²/(kB h)² + r/h · kB).
  /// The index sums are integers: the same disk gives the same figures whichever way it was reached.
  int target_near(const Vec2& c, double r, Vec2* nearest, Vec2* centroid = nullptr) const {
    TargetSums t;
    if (nearest) {
      disk_runs(c, r, scratch_);
      t = walk_target(scratch_, nearest);
    } else {
      t = sensed(c, r);
    }
    if (centroid && t.n > 0)
      *centroid = lo_ + Vec2((static_cast<double>(t.sx) / static_cast<double>(t.n) + 0.5) * h_,
                             (static_cast<double>(t.sy) / static_cast<double>(t.n) + 0.5) * h_);
    return static_cast<int>(t.n);
  }

  [[nodiscard]] std::size_t uncut_target_cells() const {
    std::size_t n = 0;
    for (int v : tuncut_) n += static_cast<std::size_t>(v);
    return n;
  }

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
  void add_target(int y, int x0, int x1, int sign, TargetSums& t) const {
    if (y < 0 || y >= ny_) return;
    x0 = std::max(0, x0);
    x1 = std::min(nx_ - 1, x1);
    const std::uint8_t* s = st_.data() + idx(0, y);
    const std::uint8_t* g = target_.data() + idx(0, y);
    long long n = 0, sx = 0;
    for (int x = x0; x <= x1; ++x)
      if (s[x] == 1 && g[x]) {
        ++n;
        sx += x;
      }
    t.n += sign * n;
    t.sx += sign * sx;
    t.sy += sign * n * y;
  }
  /// The uncut target cells of disk d, block by block; with `nearest`, every cell is visited and
  /// the nearest to d.c written (the first in raster order of blocks, then of cells, on a tie).
  TargetSums walk_target(const DiskRuns& d, Vec2* nearest) const {
    TargetSums t;
    double best = kInf;
    in_box(d.c - Vec2(d.r, d.r), d.c + Vec2(d.r, d.r), tuncut_, [&](int bx, int by, std::size_t b) {
      const int xa = bx * kB, xb = std::min(nx_, xa + kB) - 1;
      const int ya = by * kB, yb = std::min(ny_, ya + kB) - 1;
      if (!nearest) {
        bool whole = true;
        for (int y = ya; y <= yb && whole; ++y) {
          const auto [r0, r1] = d.at(y);
          whole = r0 <= xa && xb <= r1;
        }
        if (whole) {
          t.n += tuncut_[b];
          t.sx += tsum_[b][0];
          t.sy += tsum_[b][1];
          return true;
        }
      }
      for (int y = ya; y <= yb; ++y) {
        const auto [r0, r1] = d.at(y);
        const int x0 = std::max(xa, r0), x1 = std::min(xb, r1);
        if (!nearest) {
          add_target(y, x0, x1, 1, t);
          continue;
        }
        for (int x = x0; x <= x1; ++x) {
          const std::size_t i = idx(x, y);
          if (st_[i] != 1 || !target_[i]) continue;
          ++t.n;
          t.sx += x;
          t.sy += y;
          const double dd = (centre(x, y) - d.c).squaredNorm();
          if (dd < best) {
            best = dd;
            *nearest = centre(x, y);
          }
        }
      }
      return true;
    });
    return t;
  }

  /// The uncut target cells within r of c, kept for the last disk (target_near).
  TargetSums sensed(const Vec2& c, double r) const {
    if (sense_valid_ && r == sense_.r && c == sense_.c) return sense_sums_;
    if (sense_valid_ && r == sense_.r && (c - sense_.c).squaredNorm() <= sq(kSenseShiftCells * h_)) {
      disk_runs(c, r, scratch_);
      TargetSums t = sense_sums_;
      for (int y = scratch_.y0; y < scratch_.rows_end(); ++y)
        minus(scratch_.at(y), sense_.at(y), [&](int x0, int x1) { add_target(y, x0, x1, 1, t); });
      for (int y = sense_.y0; y < sense_.rows_end(); ++y)
        minus(sense_.at(y), scratch_.at(y), [&](int x0, int x1) { add_target(y, x0, x1, -1, t); });
      std::swap(sense_, scratch_);
      sense_sums_ = t;
      return t;
    }
    disk_runs(c, r, sense_);
    sense_sums_ = walk_target(sense_, nullptr);
    sense_valid_ = true;
    return sense_sums_;
  }
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

/// Douglas–Peucker on an open polyline within eps, keeping a chord only where the walls allow it.
void simplify_into(const std::vector<Vec2>& pts, double eps, const Clearance& walls, std::vector<Vec2>& out) {
  if (pts.empty()) return;
  std::vector<char> keep(pts.size(), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, pts.size() - 1}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (b <= a + 1) continue;
    const Vec2 A = pts[a], B = pts[b];
    const Vec2 ab = B - A;
    const double L2 = ab.squaredNorm();
    double worst = -1;
    std::size_t wi = a + 1;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double t = L2 > 0 ? std::clamp((pts[i] - A).dot(ab) / L2, 0.0, 1.0) : 0.0;
      const double d = (pts[i] - (A + t * ab)).norm();
      if (d > worst) {
        worst = d;
        wi = i;
      }
    }
    if (worst <= eps && walls.move_ok(A, B)) continue;
    keep[wi] = 1;
    stack.push_back({a, wi});
    stack.push_back({wi, b});
  }
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (keep[i]) out.push_back(pts[i]);
}

class Planner {
public:
  Planner(const Region& region, const CutParams& cut, const AdaptiveParams& prm, double target_deg)
      : region_(region),
        cut_(cut),
        R_(cut.tool_diameter / 2),
        climb_(prm.climb),
        both_(prm.both_ways),
        pass_climb_(prm.climb),
        step_(prm.step_mm > 0 ? prm.step_mm : cut.tool_diameter / 40),
        raster_(region, adaptive_raster_mm(region, cut, prm), cut.tool_diameter),
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
                    : std::max(4, static_cast<int>(std::lround(kMinWorkCellsD40 * (cut.tool_diameter / 40) *
                                                               (cut.tool_diameter / 40) / (h * h))));
    max_cells_ = prm.safety * width * step_ / (h * h);
    prepare();
  }

  void run() {
    std::optional<Vec2> pos;  // tool down here, or nullopt (retracted)
    std::size_t guard = 0;
    const std::size_t max_rounds = 200000;
    while (guard++ < max_rounds) {
      if (pos) {
        Vec2 start, toward;
        std::vector<Vec2> way;
        // Both ways: a pass blocked at a wall turns round and cuts the next stripe of the same
        // front back the other way (the other milling direction), with no ride.
        if (both_ && last_blocked_ && last_cells_ >= min_work_) {
          pass_climb_ = !pass_climb_;
          const double got = cut_pass(*pos, -last_dir_, true);
          last_cells_ = got;
          pos = current_end();
          if (got >= min_work_) continue;
        }
        pass_climb_ = climb_;
        // First the front's upstream end: ride back along the material (kept on the other side,
        // nothing cut) to where the front meets a wall, and climb-cut it again from there.
        if (last_cells_ >= min_work_ && ride_back(*pos, way)) {
          // Where no pass can start at the ride's end (every first step would cut more than the
          // target: 116 of 257 passes on four_islands cut nothing there), the ride and the link to
          // the nearest start from its end become one link, pulled taut: one move through cut area
          // instead of a ride, a stop and a link.
          const std::vector<Vec2> ride = taut_ride(way);  // a few chords instead of a step every D/40
          std::vector<Vec2> beyond;
          if (!can_start(way.back(), last_heading_) && find_start(way.back(), start, toward, beyond)) {
            std::vector<Vec2> all = ride;
            all.insert(all.end(), beyond.begin() + 1, beyond.end());
            if (link_along(all)) {
              pos = pass_from(start, toward);
              continue;
            }
          }
          append_link(ride);
          last_cells_ = cut_pass(way.back(), last_heading_, true);
          pos = current_end();
          continue;
        }
        way.clear();
        if (find_start(*pos, start, toward, way)) {
          if (link_along(way))
            pos = pass_from(start, toward);
          else
            dead_[lattice_index(start)] = 1;
          continue;
        }
        pos.reset();  // nothing linkable from here
      }
      // Retracted: a new component's entry, or a start elsewhere in one already entered.
      if (!enter_next(pos)) break;
    }
    cut_walls();
  }

  /// A pass from `start` (the tool there), across the line to the material at `toward`; a start
  /// whose pass cuts next to nothing is not offered again. Returns where the tool is.
  Vec2 pass_from(const Vec2& start, const Vec2& toward) {
    last_cells_ = cut_pass(start, first_dir(start, toward), true);
    if (last_cells_ < min_work_) dead_[lattice_index(start)] = 1;
    return current_end();
  }

  /// The wall pass: every loop of A_0 (outer loops counter-clockwise, island loops clockwise for
  /// climb; reversed for conventional), the nearest loop next, each from its vertex nearest the
  /// tool, reached with the tool down through cut area (a retraction only where no way is free).
  void cut_walls() {
    if (chains_.empty()) return;
    std::vector<std::vector<Vec2>> loops = wall_loops(region_, cut_.clearance());
    for (auto& l : loops) {
      if (!climb_) std::reverse(l.begin(), l.end());
      // Straight edges get a vertex every kWallStartMm: a loop may start there (a corner holds
      // the band the passes could not reach, which a link into it would cut at once).
      std::vector<Vec2> dense;
      for (std::size_t j = 0; j < l.size(); ++j) {
        const Vec2 a = l[j], b = l[(j + 1) % l.size()];
        const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kWallStartMm)));
        for (int t = 0; t < n; ++t) dense.push_back(a + (b - a) * (static_cast<double>(t) / n));
      }
      l = std::move(dense);
    }
    while (!loops.empty()) {
      const Vec2 at_ = current_end();
      // Candidate starts: every loop's vertices, nearest first; the first a link reaches (or a
      // backtrack along the path, for the nearest) wins.
      std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> cand;
      for (std::size_t i = 0; i < loops.size(); ++i)
        for (std::size_t j = 0; j < loops[i].size(); ++j) cand.push_back({(loops[i][j] - at_).squaredNorm(), {i, j}});
      const std::size_t keep = std::min<std::size_t>(cand.size(), kWallStartTries);
      std::partial_sort(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(keep), cand.end());
      std::size_t li = cand.front().second.first, vi = cand.front().second.second;
      bool linked = false;
      for (std::size_t k = 0; k < keep && !linked; ++k) {
        Vec2 start, toward;
        std::vector<Vec2> way;
        const auto [i, j] = cand[k].second;
        if (find_start(at_, start, toward, way, &loops[i][j]) && link_along(way)) {
          li = i;
          vi = j;
          linked = true;
        }
      }
      std::vector<Vec2> loop;
      for (std::size_t j = 0; j <= loops[li].size(); ++j) loop.push_back(loops[li][(vi + j) % loops[li].size()]);
      loops.erase(loops.begin() + static_cast<std::ptrdiff_t>(li));
      if (!linked && !backtrack_to(loop.front())) {
        chains_.push_back(RawChain{});
        chains_.back().predrill = !safe(loop.front());
        ++stats_.wall_retractions;
      }
      RawChain& c = chains_.back();
      for (std::size_t j = 0; j < loop.size(); ++j) {
        if (!c.pts.empty()) mark_move(c.pts.back(), loop[j]);
        c.pts.push_back(loop[j]);
      }
    }
  }

  PlanResult result(PlanResult res) {
    AdaptiveStats& st = stats_;
    for (auto& raw : chains_) {
      Chain c;
      c.predrill = raw.predrill;
      std::vector<Vec2> pts;
      // The turn round the entry's bore and the rest apart, so that its end is kept.
      std::size_t turn_end = 0;  // in pts
      if (raw.turn_end > 0 && raw.turn_end < raw.pts.size()) {
        const auto split = raw.pts.begin() + static_cast<std::ptrdiff_t>(raw.turn_end);
        simplify_into(std::vector<Vec2>(raw.pts.begin(), split + 1), tol::adaptive_simplify_mm, exact_, pts);
        turn_end = pts.size() - 1;
        simplify_into(std::vector<Vec2>(split, raw.pts.end()), tol::adaptive_simplify_mm, exact_, pts);
      } else {
        simplify_into(raw.pts, tol::adaptive_simplify_mm, exact_, pts);
      }
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const Vec2& p = pts[i];
        if (c.pts.empty() || (c.pts.back().p() - p).norm() > tol::join_mm) c.pts.push_back({p.x(), p.y(), 0.0});
        if (turn_end > 0 && i == turn_end) c.entry_turn = c.pts.size() - 1;
      }
      if (c.pts.size() == 1) c.pts.push_back(c.pts.front());  // a lone entry: keep it a move
      res.path.chains.push_back(std::move(c));
    }
    for (const Chain& c : res.path.chains)
      if (c.predrill && !c.pts.empty()) res.predrill.push_back(c.pts.front().p());
    st.retractions = res.path.retractions();
    st.cut_length_mm = res.path.cut_length();
    st.rapid_length_mm = res.path.rapid_length();
    st.uncut_target_mm2 = static_cast<double>(raster_.uncut_target_cells()) * raster_.h() * raster_.h();
    std::size_t v = 0;
    for (const Chain& c : res.path.chains) v += c.pts.size();
    st.vertices = v;
    res.stats = st;
    return res;
  }

  AdaptiveStats stats_;

private:
  struct RawChain {
    std::vector<Vec2> pts;
    bool predrill = true;
    std::size_t turn_end = 0;  ///< pts[0] … pts[turn_end]: the turn round the entry's bore (Chain::entry_turn)
  };

  /// Target cells (within R of an allowed raster centre), raster components of allowed centres,
  /// their entry points (largest distance to the material's edge), the lattice.
  void prepare() {
    const int nx = raster_.nx(), ny = raster_.ny();
    const double h = raster_.h();
    const auto& st = raster_.states();
    std::vector<std::uint8_t> empty(st.size());
    for (std::size_t i = 0; i < st.size(); ++i) empty[i] = st[i] == 0;
    const std::vector<double> wall_d2 = edt(empty, nx, ny);  // squared cells to the nearest cell outside the region
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
    const std::vector<double> to_allowed = edt(allowed, nx, ny);
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
    raster_.count_blocks();
    // Components of allowed centres (8-connected), numbered in raster order of their first cell:
    // the rows' runs of allowed cells, joined where runs of neighbouring rows overlap or touch
    // diagonally (union–find). O(cells). Each component's entry: its cell farthest from the walls
    // (the first in raster order on a tie).
    struct RunOf {
      int y, x0, x1;
    };
    std::vector<RunOf> arun;  // the runs of allowed cells, in raster order
    std::vector<std::size_t> row_first(static_cast<std::size_t>(ny) + 1, 0);
    for (int y = 0; y < ny; ++y) {
      row_first[static_cast<std::size_t>(y)] = arun.size();
      for (int x = 0; x < nx;) {
        if (!allowed[raster_.idx(x, y)]) {
          ++x;
          continue;
        }
        const int x0 = x;
        while (x < nx && allowed[raster_.idx(x, y)]) ++x;
        arun.push_back({y, x0, x - 1});
      }
    }
    row_first[static_cast<std::size_t>(ny)] = arun.size();
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
    // A root is its component's first run (unions keep the smaller index), so numbering the roots
    // in run order numbers the components in raster order of their first cell.
    std::vector<int> comp_of(arun.size(), -1);
    std::vector<std::size_t> best;
    for (std::size_t i = 0; i < arun.size(); ++i) {
      const std::size_t r = find(i);
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
    stats_.components = entries_.size();
    // Lattice over the raster's box.
    lat_lo_ = raster_.centre(0, 0);
    lnx_ = static_cast<int>(std::floor((nx - 1) * h / kLatticeMm)) + 1;
    lny_ = static_cast<int>(std::floor((ny - 1) * h / kLatticeMm)) + 1;
    lat_ok_.assign(lin(0, lny_, lnx_), -1);
    dead_.assign(lat_ok_.size(), 0);
    lat_safe_.assign(lat_ok_.size(), 0);
  }

  [[nodiscard]] Vec2 lattice_point(std::size_t k) const {
    return lat_lo_ + kLatticeMm * Vec2(static_cast<double>(k % static_cast<std::size_t>(lnx_)),
                                       static_cast<double>(k / static_cast<std::size_t>(lnx_)));
  }
  [[nodiscard]] std::size_t lattice_index(const Vec2& p) const {
    const int x = std::clamp(static_cast<int>(std::lround((p.x() - lat_lo_.x()) / kLatticeMm)), 0, lnx_ - 1);
    const int y = std::clamp(static_cast<int>(std::lround((p.y() - lat_lo_.y()) / kLatticeMm)), 0, lny_ - 1);
    return lin(x, y, lnx_);
  }
  /// Allowed for links (cached: walls do not move).
  bool lattice_allowed(std::size_t k) {
    if (lat_ok_[k] < 0) lat_ok_[k] = link_walls_.point_ok(lattice_point(k)) ? 1 : 0;
    return lat_ok_[k] == 1;
  }

  /// The tool's disk there is cleared (up to raster noise).
  [[nodiscard]] bool safe(const Vec2& p) const { return raster_.clear_within(p, R_); }

  /// The straight move a→b with the tool down: no wall, at most the target's cut per step.
  [[nodiscard]] bool link_ok(const Vec2& a, const Vec2& b) const {
    if (!exact_.move_ok(a, b)) return false;
    const double L = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(L / step_)));
    const double allowed = max_cells_ * (L / n) / step_ + 0.5;
    if (raster_.capsule_clear(a, b, R_)) return true;  // through cut area: every count below is 0
    // The uncut cells of each sample's disk, from the last one's by the two crescents between them
    // (the same rounding as the full disk, so the same counts): O(R·step/h² + R/h) a sample.
    // The count at a itself is kept while the raster is unchanged: the links tried from one
    // position (the search's seeds, a taut pull) share it.
    if (!(a == fresh_at_) || raster_.version() != fresh_version_) {
      fresh_at_ = a;
      fresh_version_ = raster_.version();
      fresh_a_ = raster_.fresh(a, R_);
    }
    Vec2 prev = a;
    int fresh = fresh_a_;
    for (int i = 1; i <= n; ++i) {
      const Vec2 q = a + (b - a) * (static_cast<double>(i) / n);
      fresh += raster_.fresh_beyond(prev, q, R_) - raster_.fresh_beyond(q, prev, R_);
      if (fresh > allowed) return false;
      prev = q;
    }
    return true;
  }

  mutable Vec2 fresh_at_{kInf, kInf};
  mutable std::uint64_t fresh_version_ = 0;
  mutable int fresh_a_ = 0;

  /// Dijkstra from `from` over safe, allowed lattice positions to the nearest one with uncut target
  /// material within reach; the way there (from first, the start last).
  /// With `goal`: the way to that point instead (the lattice position nearest it that a straight
  /// link reaches, then the goal).
  bool find_start(const Vec2& from, Vec2& start, Vec2& toward, std::vector<Vec2>& way, const Vec2* goal = nullptr) {
    if (goal && link_ok(from, *goal)) {
      way = {from, *goal};
      start = toward = *goal;
      return true;
    }
    const std::size_t n = lat_ok_.size();
    std::vector<double> dist(n, kInf);
    std::vector<long> prev(n, -1);
    std::vector<std::uint8_t> state(n, 0);  // 0 unknown, 1 usable, 2 not
    auto usable = [&](std::size_t k) {
      if (state[k] == 0) {
        // Cutting only removes material: a position once found cleared stays cleared.
        if (!lat_safe_[k] && lattice_allowed(k) && safe(lattice_point(k))) lat_safe_[k] = 1;
        state[k] = lat_safe_[k] ? 1 : 2;
      }
      return state[k] == 1;
    };
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    const std::size_t c0 = lattice_index(from);
    const int cx0 = static_cast<int>(c0 % static_cast<std::size_t>(lnx_)),
              cy0 = static_cast<int>(c0 / static_cast<std::size_t>(lnx_));
    // Seeds: the lattice positions round the tool a straight link reaches, in growing rings.
    const int max_ring = static_cast<int>(std::ceil((R_ + 3) / kLatticeMm));
    for (int r = 1; r <= max_ring && open.empty(); ++r)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
          const int x = cx0 + dx, y = cy0 + dy;
          if (x < 0 || y < 0 || x >= lnx_ || y >= lny_) continue;
          const std::size_t k = lin(x, y, lnx_);
          if (!usable(k) || !link_ok(from, lattice_point(k))) continue;
          const double d = (lattice_point(k) - from).norm();
          if (d < dist[k]) {
            dist[k] = d;
            open.push({d, k});
          }
        }
    const double reach = R_ + 1.5 * kLatticeMm;
    while (!open.empty()) {  // O(lattice · log lattice) at worst
      const auto [d, k] = open.top();
      open.pop();
      if (d > dist[k]) continue;
      Vec2 near;
      const bool found = goal
                             ? (lattice_point(k) - *goal).norm() <= 2.5 * kLatticeMm && link_ok(lattice_point(k), *goal)
                             : !dead_[k] && raster_.target_near(lattice_point(k), reach, &near) >= min_work_;
      if (found) {
        start = goal ? *goal : lattice_point(k);
        toward = goal ? *goal : near;
        std::vector<Vec2> rev;
        if (goal) rev.push_back(*goal);
        for (long c = static_cast<long>(k); c >= 0; c = prev[static_cast<std::size_t>(c)])
          rev.push_back(lattice_point(static_cast<std::size_t>(c)));
        rev.push_back(from);
        way.assign(rev.rbegin(), rev.rend());
        return true;
      }
      const int x0 = static_cast<int>(k % static_cast<std::size_t>(lnx_)),
                y0 = static_cast<int>(k / static_cast<std::size_t>(lnx_));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = x0 + dx, y = y0 + dy;
          if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= lnx_ || y >= lny_) continue;
          const std::size_t q = lin(x, y, lnx_);
          if (!usable(q)) continue;
          const double nd = d + kLatticeMm * ((dx != 0 && dy != 0) ? std::numbers::sqrt2 : 1.0);
          if (nd < dist[q]) {
            dist[q] = nd;
            prev[q] = static_cast<long>(k);
            open.push({nd, q});
          }
        }
    }
    return false;
  }

  /// Cuts along `way` (from the tool's position) pulled taut: each straight move as long as
  /// link_ok allows. False (nothing appended) when a move between two lattice neighbours fails.
  bool link_along(const std::vector<Vec2>& way) {
    std::vector<Vec2> taut{way.front()};
    std::size_t k = 0;
    while (k + 1 < way.size()) {
      std::size_t far = k + 1;
      if (!link_ok(taut.back(), way[far])) return false;
      while (far + 1 < way.size() && link_ok(taut.back(), way[far + 1])) ++far;
      taut.push_back(way[far]);
      k = far;
    }
    RawChain& c = chains_.back();
    for (std::size_t i = 1; i < taut.size(); ++i) {
      mark_move(taut[i - 1], taut[i]);
      c.pts.push_back(taut[i]);
      stats_.link_length_mm += (taut[i] - taut[i - 1]).norm();
    }
    ++stats_.links;
    return true;
  }

  [[nodiscard]] Vec2 current_end() const { return chains_.back().pts.back(); }

  /// Marks the straight move a→b cut, at the planning step.
  void mark_move(const Vec2& a, const Vec2& b) {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_)));
    for (int t = 1; t <= n; ++t) raster_.mark(a + (b - a) * (static_cast<double>(t) / n), R_);
  }

  /// The first direction at a pass start: across the line to the nearest uncut material, so that
  /// the material is on the right (climb) or on the left (conventional).
  [[nodiscard]] Vec2 first_dir(const Vec2& start, const Vec2& toward) const {
    Vec2 v = toward - start;
    if (v.norm() < 1e-9) v = Vec2(1, 0);
    return rot(v.normalized(), climb_ ? kPi / 2 : -kPi / 2);
  }

  /// Fresh cells of a step to q, or +inf where the move is not allowed.
  [[nodiscard]] double cost(const Vec2& p, const Vec2& q) const {
    // A move no longer than the room p has beyond the clearance cannot reach a wall (every point of
    // it lies within its length of p): one distance query per position instead of an exact sweep
    // per candidate direction.
    if (!(p == room_at_)) {
      room_at_ = p;
      room_ = walls_.point_ok(p) ? walls_.wall_distance(p) - walls_.clearance() : -1.0;
      p_clear_ = raster_.clear_within(p, R_);
      p_pad_ = -1;
    }
    const double d = (q - p).norm();
    if (!(d < room_) && !walls_.move_ok(p, q)) return kInf;
    // Every caller stands on cut ground (a pass, a ride, a link's end), so only the crescent the step
    // adds can hold uncut cells; checked once per position, the full disk where it is not so.
    if (!p_clear_) return raster_.fresh(q, R_);
    if (d > p_pad_) {  // p's runs, for every step from p up to this long
      p_pad_ = std::max(2 * step_, d);
      raster_.runs(p, R_, p_pad_, p_runs_);
    }
    return raster_.fresh_beyond(p_runs_, q, R_);
  }
  mutable double p_pad_ = -1;
  mutable Raster::Runs p_runs_;
  mutable Vec2 room_at_{kInf, kInf};
  mutable double room_ = -1;
  mutable bool p_clear_ = false;

  /// Where no link leaves the tool's position: back along the chain's own path (cut area, the tool
  /// down) to a point every kBacktrackMm from which a link reaches `goal`, then that link. False
  /// (nothing appended) when none within kBacktrackTries does. O(tries · lattice search).
  bool backtrack_to(const Vec2& goal) {
    RawChain& c = chains_.back();
    if (c.pts.size() < 2) return false;
    double run = 0;
    int tries = 0;
    for (std::size_t k = c.pts.size() - 1; k-- > 0 && tries < kBacktrackTries;) {
      run += (c.pts[k + 1] - c.pts[k]).norm();
      if (run < kBacktrackMm) continue;
      run = 0;
      ++tries;
      Vec2 start, toward;
      std::vector<Vec2> way;
      if (!find_start(c.pts[k], start, toward, way, &goal)) continue;
      const std::vector<Vec2> back(c.pts.rbegin() + 1, c.pts.rend() - static_cast<std::ptrdiff_t>(k));
      double len = 0;
      for (const Vec2& q : back) {  // retrace: already cut
        len += (q - c.pts.back()).norm();
        c.pts.push_back(q);
      }
      if (link_along(way)) {
        stats_.backtrack_length_mm += len;
        return true;
      }
      c.pts.resize(c.pts.size() - back.size());
      return false;
    }
    return false;
  }

  /// From p (the end of a pass), rides back along the front with the material on the other side
  /// than a cutting pass keeps it, cutting nothing (every step's newly cut cells = 0), as far as
  /// the front goes: until the material is out of sensing range, a wall or the material turns the
  /// ride away (a step more than kRideAwayDeg off the front's tangent), or kRideMaxMm. `way` gets
  /// the ride (p first). False when it is shorter than kRideMinMm (nothing gained).
  bool ride_back(const Vec2& p0, std::vector<Vec2>& way) {
    way.assign(1, p0);
    const double side = climb_ ? 1.0 : -1.0;
    Vec2 p = p0;
    double len = 0;
    Vec2 hd(0, 0);
    const double rs = kRideStepSteps * step_;
    while (len < kRideMaxMm) {
      Vec2 cen;
      if (raster_.target_near(p, R_ + kSenseMm, nullptr, &cen) < min_work_) break;
      Vec2 u = cen - p;
      if (u.norm() < 1e-9) break;
      u.normalize();
      const Vec2 t0 = rot(u, -side * kPi / 2);  // the material on the other side
      auto dir = [&](double th) { return rot(t0, side * th); };
      auto free = [&](double th) { return cost(p, p + rs * dir(th)) <= 0; };
      double lo = -kRideAwayDeg * kPi / 180;
      if (!free(lo)) break;
      double hi = kPi / 2;
      if (free(hi))
        lo = hi;
      else
        for (int it = 0; it < 7; ++it) {
          const double mid = 0.5 * (lo + hi);
          if (free(mid))
            lo = mid;
          else
            hi = mid;
        }
      const Vec2 nd = dir(lo);
      if (hd.norm() > 0 && hd.dot(nd) < std::cos(kPi / 2)) break;  // it would turn back on itself
      p += rs * nd;
      hd = nd;
      way.push_back(p);
      len += rs;
    }
    last_heading_ = hd.norm() > 0 ? Vec2(-hd) : Vec2(1, 0);
    return len >= kRideMinMm;
  }

  /// The straight move a→b keeps the walls' margin and cuts nothing: no uncut cell within R of a
  /// position every 4 steps along it (the test every step of a ride passes; between two samples
  /// 4·step = D/10 apart a cell within R of the move but of neither sample lies at most
  /// (D/10)²/(8R) = D/400, a tenth of a D/40 cell, a fifth of a D/80 one, beyond R of both).
  [[nodiscard]] bool air_ok(const Vec2& a, const Vec2& b) const {
    if (!walls_.move_ok(a, b)) return false;
    if (raster_.capsule_clear(a, b, R_)) return true;  // no uncut cell within R of the move at all
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (4 * step_))));
    for (int i = 1; i <= n; ++i)
      if (!raster_.clear_within(a + (b - a) * (static_cast<double>(i) / n), R_)) return false;
    return true;
  }

  /// A ride (steps of step_ along the front, each cutting nothing) pulled taut: from each vertex
  /// the farthest later one that air_ok reaches (galloping, then bisection: O(log n) tests a
  /// vertex). The ride's hundreds of 0.25 mm steps, each turning a few degrees, held the machine
  /// to ≈ 36 mm/s by the junction-deviation rule where its air feed is 80 mm/s; its chords are
  /// also shorter.
  [[nodiscard]] std::vector<Vec2> taut_ride(const std::vector<Vec2>& way) const {
    std::vector<Vec2> out{way.front()};
    std::size_t k = 0;
    const std::size_t last = way.size() - 1;
    while (k < last) {
      std::size_t good = k + 1, stride = 1;  // one step of the ride: air_ok by construction
      while (good < last) {
        const std::size_t next = std::min(last, good + stride);
        if (!air_ok(way[k], way[next])) {
          std::size_t lo = good, hi = next;  // lo passes, hi fails
          while (hi - lo > 1) {
            const std::size_t mid = lo + (hi - lo) / 2;
            (air_ok(way[k], way[mid]) ? lo : hi) = mid;
          }
          good = lo;
          break;
        }
        good = next;
        stride *= 2;
      }
      out.push_back(way[good]);
      k = good;
    }
    return out;
  }

  /// Appends a tool-down move along `way` (from the chain's end) to the current chain; the raster
  /// marks it (it cuts nothing by construction, up to the raster).
  void append_link(const std::vector<Vec2>& way) {
    RawChain& c = chains_.back();
    for (std::size_t i = 1; i < way.size(); ++i) {
      mark_move(way[i - 1], way[i]);
      c.pts.push_back(way[i]);
      stats_.ride_length_mm += (way[i] - way[i - 1]).norm();
    }
    ++stats_.links;
  }

  /// The tangent along the material sensed from p (the centroid of the uncut target cells within
  /// R + kSenseMm, or heading d when it lies at p), with the material on the right for side +1
  /// (climb), on the left for −1; nullopt when no target material is in range.
  [[nodiscard]] std::optional<Vec2> material_tangent(const Vec2& p, const Vec2& d, double side) const {
    Vec2 cen;
    if (raster_.target_near(p, R_ + kSenseMm, nullptr, &cen) < min_work_) return std::nullopt;
    Vec2 u = cen - p;
    if (u.norm() < 1e-9) u = d;
    return rot(u.normalized(), side * kPi / 2);
  }

  /// The first of the probe directions rot(t0, −side·θ), θ = 90° (straight at the material), −90°
  /// (straight away), −120°, −150°, −180°, whose step cuts at most the target; nullopt when none.
  [[nodiscard]] std::optional<double> first_feasible(const Vec2& p, const Vec2& t0, double side) const {
    for (const double th : {kPi / 2, -kPi / 2, -2 * kPi / 3, -5 * kPi / 6, -kPi})
      if (cost(p, p + step_ * rot(t0, -side * th)) <= max_cells_) return th;
    return std::nullopt;
  }

  /// Whether cut_pass(p, d, first_wide = true) takes a first step.
  [[nodiscard]] bool can_start(const Vec2& p, const Vec2& d) const {
    const double side = pass_climb_ ? 1.0 : -1.0;
    const std::optional<Vec2> t0 = material_tangent(p, d, side);
    if (!t0) return false;
    return first_feasible(p, *t0, side).has_value();
  }

  /// One pass from p (already there, its disk cleared) heading about d. Returns the cells cut.
  ///
  /// The steering: the material is sensed as the centroid of the uncut target cells within
  /// R + kSenseMm of the tool (so the pass finds it again after a turn, unlike a one-step probe);
  /// the tangent t0 keeps it on the right (climb) or left (conventional). Each step goes in the
  /// direction turned as far toward the material as the step's newly cut area allows (≤ the
  /// target's: bisection over θ ∈ [−90°, 90°] from t0), so that in open material the pass rides
  /// the cut boundary at the target engagement (rings that spiral out), slides along walls (a move
  /// the walls refuse costs +inf) and loops round where the material is narrow. A pass ends when no
  /// target material is within sensing range, when every direction is refused, or after
  /// kIdleMm of path that cut nothing (that tail is dropped).
  double cut_pass(Vec2 p, Vec2 d, bool first_wide) {
    RawChain& c = chains_.back();
    if (c.pts.empty() || (c.pts.back() - p).norm() > tol::join_mm) c.pts.push_back(p);
    const std::size_t base = c.pts.size();
    const double side = pass_climb_ ? 1.0 : -1.0;  // rot(t0, -side·θ), θ > 0: toward the material
    const std::size_t idle_steps = static_cast<std::size_t>(std::ceil((R_ + kSenseMm) / step_));
    double total = 0;
    bool blocked = false;
    std::size_t idle = 0, last_productive = base;
    const std::size_t max_steps = 4000000;
    auto at = [&](const Vec2& dir) { return Vec2(p + step_ * dir); };
    for (std::size_t n = 0; n < max_steps; ++n) {
      const std::optional<Vec2> tangent = material_tangent(p, d, side);
      if (!tangent) break;  // nothing near: done
      const Vec2 t0 = *tangent;
      auto dir = [&](double th) { return rot(t0, -side * th); };
      // Straight at the material when that step is light enough (or cuts nothing); otherwise the
      // direction turned furthest toward it within the target, by bisection from the first
      // feasible probe.
      std::optional<double> chosen = first_feasible(p, t0, side);
      if (chosen && *chosen < kPi / 2) {
        double lo = *chosen, hi = kPi / 2;
        for (int it = 0; it < 7; ++it) {
          const double mid = 0.5 * (lo + hi);
          if (cost(p, at(dir(mid))) <= max_cells_)
            lo = mid;
          else
            hi = mid;
        }
        chosen = lo;
      }
      if (!chosen || (n > 0 && *chosen < -kBlockedDeg * kPi / 180)) {  // blocked (it could only back away)
        blocked = true;
        break;
      }
      Vec2 nd = dir(*chosen);
      if (n > 0 || !first_wide) {
        // Smoothness: a turn toward the material of at most kMaxTurnDeg per step (a turn away from
        // it is what keeps the cut at the target and is kept).
        double turn = std::atan2(d.x() * nd.y() - d.y() * nd.x(), d.dot(nd));  // signed, in [−π, π]
        if (std::abs(turn) > kPi - 1e-6) turn = -side * kPi;                   // a reversal: round toward the material
        const double lim = kMaxTurnDeg * kPi / 180;
        if (-side * turn > lim) {
          const Vec2 lim_dir = rot(d, -side * lim);
          if (cost(p, at(lim_dir)) <= max_cells_) nd = lim_dir;
        }
      }
      const Vec2 q = at(nd);
      const int got = raster_.mark(q, R_);
      d = nd;
      p = q;
      c.pts.push_back(q);
      total += got;
      ++stats_.steps;
      if (got > 0) {
        idle = 0;
        last_productive = c.pts.size();
      } else if (++idle >= idle_steps) {
        break;
      }
    }
    if (c.pts.size() > last_productive) blocked = false;  // it ended idle, not at a wall
    c.pts.resize(std::max(last_productive, base));        // drop the idle tail
    last_blocked_ = blocked;
    last_dir_ = d;
    ++stats_.passes;
    if (total < min_work_) ++stats_.idle_passes;
    return total;
  }

  /// Enters the next component not entered yet (helix at its entry point), or re-enters with a
  /// plunge at a cleared start that no link reaches. False when nothing is left.
  bool enter_next(std::optional<Vec2>& pos) {
    // A component not entered yet, the nearest entry first.
    std::optional<std::size_t> pick;
    for (std::size_t k = 0; k < entries_.size(); ++k) {
      if (entries_[k].entered) continue;
      if (!pick)
        pick = k;
      else if (!chains_.empty() && (entries_[k].p - current_end()).norm() < (entries_[*pick].p - current_end()).norm())
        pick = k;
    }
    if (pick) {
      Entry_& e = entries_[*pick];
      e.entered = true;
      chains_.push_back(RawChain{});
      chains_.back().predrill = true;
      ++stats_.entries;
      Vec2 d(0, 1);
      if (const auto hx = entry_helix(exact_, e.p, cut_.tool_diameter)) {
        raster_.mark(hx->first, hx->second + R_);
        // The helix's flat turn at the floor, in the plan too: it makes the path sweep the bore (the
        // uncut-area figures), and with another entry than the helix it is what cuts it. A program
        // entering by the helix skips it (Chain::entry_turn): the helix's own flat turn cut it.
        const Vec2 out = e.p - hx->first;
        const int nseg = std::max(8, static_cast<int>(std::ceil(2 * kPi * hx->second / step_)));
        chains_.back().pts.push_back(e.p);
        for (int k = 1; k <= nseg; ++k)
          chains_.back().pts.push_back(hx->first + rot(out, (climb_ ? 1.0 : -1.0) * 2 * kPi * k / nseg));
        chains_.back().turn_end = chains_.back().pts.size() - 1;
        d = rot(out.normalized(), climb_ ? kPi / 2 : -kPi / 2);  // round the hole, material outside
      } else {
        raster_.mark(e.p, R_);
        ++stats_.entries_without_helix;
      }
      last_cells_ = cut_pass(e.p, d, true);
      pos = current_end();
      return true;
    }
    // Every component entered: uncut target left where no link reaches? Re-enter at a cleared start.
    if (raster_.uncut_target_cells() < static_cast<std::size_t>(min_work_)) return false;
    for (std::size_t k = 0; k < lat_ok_.size(); ++k) {  // O(lattice), only after a failed search
      if (dead_[k] || !lattice_allowed(k)) continue;
      const Vec2 p = lattice_point(k);
      Vec2 near;
      if (raster_.target_near(p, R_ + 1.5 * kLatticeMm, &near) < min_work_ || !safe(p)) continue;
      chains_.push_back(RawChain{});
      chains_.back().predrill = false;
      ++stats_.reentries;
      const double got = cut_pass(p, first_dir(p, near), true);
      last_cells_ = got;
      if (got < min_work_) dead_[k] = 1;
      pos = current_end();
      return true;
    }
    return false;
  }

  struct Entry_ {
    Vec2 p;
    bool entered = false;
  };

  const Region& region_;
  CutParams cut_;
  double R_;
  bool climb_;
  bool both_;                  ///< AdaptiveParams::both_ways
  bool pass_climb_;            ///< the current pass's side (climb_ but for the return stripes of both ways)
  bool last_blocked_ = false;  ///< the last pass ended at a wall with material ahead
  Vec2 last_dir_{1, 0};        ///< its last heading
  double step_;
  Raster raster_;
  Clearance walls_;         ///< cutting moves: the contour pass's clearance
  Clearance exact_;         ///< links and simplified chords: the tool's clearance
  Clearance link_walls_;    ///< lattice positions
  double max_cells_ = 0;    ///< fresh cells allowed per step
  int min_work_ = 4;        ///< uncut cells worth a pass (kMinWorkCellsD40)
  double target_deg_ = 90;  ///< the engagement target, degrees
  double last_cells_ = 0;   ///< cells the last pass cut
  Vec2 last_heading_{1, 0};
  std::vector<Entry_> entries_;
  Vec2 lat_lo_;
  int lnx_ = 0, lny_ = 0;
  std::vector<signed char> lat_ok_;
  std::vector<std::uint8_t> dead_;
  std::vector<std::uint8_t> lat_safe_;  ///< lattice positions known allowed and cleared
  std::vector<RawChain> chains_;
};

}  // namespace

// The default cell: a step's crescent on D/40 cells holds a few cells more or fewer than its area,
// depending on where the cell centres fall (±2–3 cells, 0.66–0.85 mm of width at 0.25 mm steps on a
// Ø10 tool), which is ±6–7° at a 45° target; on D/80 the stray is about half.
double adaptive_raster_mm(const Region& region, const CutParams& cut, const AdaptiveParams& params) {
  constexpr double kMaxFineCells = 1e7;
  if (params.raster_mm > 0) return params.raster_mm;
  const double D = cut.tool_diameter;
  return raster::cells_of(region, D / 80, D) <= kMaxFineCells ? D / 80 : D / 40;
}

double adaptive_target_deg(const CutParams& cut, const AdaptiveParams& params) {
  double deg = params.max_engagement_deg;
  if (deg == 0) {
    const double R = cut.tool_diameter / 2;
    deg = std::acos(std::clamp(1 - cut.stepover / R, -1.0, 1.0)) * 180 / kPi;
  }
  if (!(deg > 0 && deg <= 180) || !std::isfinite(deg))
    throw Error("adaptive planner: max_engagement_deg must be in (0, 180], got " + std::to_string(deg));
  return deg;
}

PlanResult plan_adaptive(const Region& region, const CutParams& cut, const AdaptiveParams& params) {
  cut.check("adaptive planner");
  const double target = adaptive_target_deg(cut, params);
  if (!(params.safety > 0 && params.safety <= 1))
    throw Error("adaptive planner: safety must be in (0, 1], got " + std::to_string(params.safety));
  if (params.step_mm < 0 || params.raster_mm < 0 || !std::isfinite(params.step_mm) || !std::isfinite(params.raster_mm))
    throw Error("adaptive planner: step_mm and raster_mm must be >= 0 (0 = default)");
  const auto t0 = std::chrono::steady_clock::now();
  PlanResult res;
  res.planner = "adaptive";
  res.walls_cut = true;
  res.helix_entry_holes = true;
  const auto comps = offset_inward(region, cut.clearance() + tol::contour_margin_mm, tol::contour_chord_mm);
  if (comps.empty()) {
    res.status = PlanStatus::NoToolPoints;
    res.message = "the tool (clearance " + std::to_string(cut.clearance()) + " mm) fits nowhere in the pocket";
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  Planner p(region, cut, params, target);
  p.run();
  p.stats_.target_deg = target;
  res = p.result(std::move(res));
  if (res.path.chains.empty()) {
    // Components thinner than a raster cell: their wall loops (walls_cut is set, so nothing else
    // would cut them; the path must not be empty).
    for (const auto& loop : wall_loops(region, cut.clearance())) {
      Chain c;
      for (const Vec2& v : loop) c.pts.push_back({v.x(), v.y(), 0.0});
      c.pts.push_back(c.pts.front());
      res.predrill.push_back(c.pts.front().p());
      res.path.chains.push_back(std::move(c));
    }
  }
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace millnet::pocket
