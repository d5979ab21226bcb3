// The adaptive planner's cleared-area raster (adaptive_raster.hpp): counting, cutting and sensing
// uncut cells.
#include "adaptive_raster.hpp"

#include "millnet/pocket/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace millnet::pocket::adaptive {

void Raster::count_blocks() {
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

int Raster::fresh(const Vec2& c, double r) const {
  int n = 0;
  disk(c, r, [&](std::size_t i) { n += st_[i] == 1; });
  return n;
}

int Raster::fresh_beyond(const Vec2& p, const Vec2& c, double r) const {
  int n = 0;
  crescent(
      c, r, [&](int y) { return row_run(p, r, y); }, [&](int y, int x0, int x1) { n += uncut_in(y, x0, x1); });
  return n;
}

void Raster::disk_runs(const Vec2& c, double r, DiskRuns& out, double pad) const {
  const auto [ya, yb] = run(c.y(), r + pad, lo_.y());
  out.c = c;
  out.r = r;
  out.y0 = ya;
  out.x.clear();
  for (int y = ya; y <= yb; ++y) out.x.push_back(row_run(c, r, y));
}

void Raster::runs(const Vec2& p, double r, double pad, Runs& out) const {
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

int Raster::fresh_beyond(const Runs& pr, const Vec2& c, double r) const {
  int n = 0;
  const DiskRuns& d = pr.disk;
  crescent(
      c, r, [&](int y) { return d.at(y); }, [&](int y, int x0, int x1) { n += uncut_in(y, x0, x1); },
      [&](int y) { return y < d.y0 || y >= d.rows_end() || pr.live[static_cast<std::size_t>(y - d.y0)] != 0; });
  return n;
}

int Raster::mark(const Vec2& c, double r) {
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

bool Raster::clear_within(const Vec2& c, double r) const {
  bool ok = true;
  blocks(c, r, uncut_, [&](int x, int y) {
    if (st_[idx(x, y)] == 1 && (centre(x, y) - c).squaredNorm() <= r * r) ok = false;
    return ok;
  });
  return ok;
}

bool Raster::capsule_clear(const Vec2& a, const Vec2& b, double r) const {
  const double bs = kB * h_, rr = r + tol::on_curve_mm;
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

int Raster::target_near(const Vec2& c, double r, Vec2* nearest, Vec2* centroid) const {
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

std::size_t Raster::uncut_target_cells() const {
  std::size_t n = 0;
  for (int v : tuncut_) n += static_cast<std::size_t>(v);
  return n;
}

void Raster::add_target(int y, int x0, int x1, int sign, TargetSums& t) const {
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

Raster::TargetSums Raster::walk_target(const DiskRuns& d, Vec2* nearest) const {
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

Raster::TargetSums Raster::sensed(const Vec2& c, double r) const {
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

}  // namespace millnet::pocket::adaptive
