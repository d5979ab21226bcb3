// Ring optimisation (smoothing.hpp, extra passes): 2-opt + Or-opt on the open path with the
// obstacle-aware move costs of linking.cpp, candidate moves among each point's nearest tool points.
#include "tour_internal.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>

namespace millnet::pocket::detail {

namespace {

/// k nearest tool points of each point (Euclidean, ties by index), through a bucket grid.
/// O(N·k·log k) for spread-out points.
std::vector<std::vector<int>> nearest_lists(const std::vector<Vec2>& pts, int k) {
  const std::size_t n = pts.size();
  std::vector<std::vector<int>> out(n);
  if (n < 2 || k <= 0) return out;
  Vec2 lo = pts[0], hi = pts[0];
  for (const auto& p : pts) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec2 ext = hi - lo;
  double s = std::sqrt(std::max(ext.x() * ext.y(), 0.0) / static_cast<double>(n));
  s = std::max({s, std::max(ext.x(), ext.y()) / static_cast<double>(n), 1e-9});
  const int nx = static_cast<int>(ext.x() / s) + 1, ny = static_cast<int>(ext.y() / s) + 1;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  auto cx = [&](double x) { return std::min(static_cast<int>((x - lo.x()) / s), nx - 1); };
  auto cy = [&](double y) { return std::min(static_cast<int>((y - lo.y()) / s), ny - 1); };
  for (std::size_t i = 0; i < n; ++i)
    cells[static_cast<std::size_t>(cy(pts[i].y()) * nx + cx(pts[i].x()))].push_back(static_cast<int>(i));
  const auto kk = static_cast<std::size_t>(std::min<std::size_t>(static_cast<std::size_t>(k), n - 1));
  std::vector<std::pair<double, int>> cand;
  for (std::size_t i = 0; i < n; ++i) {
    const int x0 = cx(pts[i].x()), y0 = cy(pts[i].y());
    cand.clear();
    for (int r = 0;; ++r) {
      for (int y = y0 - r; y <= y0 + r; ++y) {
        if (y < 0 || y >= ny) continue;
        const int step = (y == y0 - r || y == y0 + r) ? 1 : std::max(2 * r, 1);
        for (int x = x0 - r; x <= x0 + r; x += step) {
          if (x < 0 || x >= nx) continue;
          for (int j : cells[static_cast<std::size_t>(y * nx + x)])
            if (static_cast<std::size_t>(j) != i)
              cand.emplace_back((pts[static_cast<std::size_t>(j)] - pts[i]).squaredNorm(), j);
        }
      }
      // points beyond ring r are at least r·s away
      if (cand.size() >= kk) {
        std::nth_element(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(kk - 1), cand.end());
        const double rs = static_cast<double>(r) * s;
        if (cand[kk - 1].first <= rs * rs) break;
      }
      if (r > nx + ny) break;
    }
    std::sort(cand.begin(), cand.end());
    for (std::size_t m = 0; m < std::min(kk, cand.size()); ++m) out[i].push_back(cand[m].second);
  }
  return out;
}

/// 2-opt + Or-opt on a ring of the N points plus one dummy node (index N, cost 0 to everything), i.e.
/// on an open path whose ends may move. Array representation; a reversal flips the shorter side.
class RingOpt {
public:
  RingOpt(std::vector<int> ring, MoveCosts& costs, std::vector<std::vector<int>> cand)
      : n_(static_cast<int>(ring.size()) - 1),
        m_(static_cast<int>(ring.size())),
        tour_(std::move(ring)),
        pos_(tour_.size()),
        costs_(costs),
        cand_(std::move(cand)) {
    for (int k = 0; k < m_; ++k) pos_[static_cast<std::size_t>(tour_[static_cast<std::size_t>(k)])] = k;
    cand_.resize(static_cast<std::size_t>(m_));  // the dummy node has no candidates of its own
  }

  /// Improves until no candidate move gains more than 1e-9 mm or the move budget is spent.
  long run(long budget) {
    std::vector<char> queued(static_cast<std::size_t>(m_), 1);
    std::queue<int> q;
    for (int k = 0; k < m_; ++k) q.push(tour_[static_cast<std::size_t>(k)]);
    long moves = 0;
    while (!q.empty() && moves < budget) {
      const int a = q.front();
      q.pop();
      queued[static_cast<std::size_t>(a)] = 0;
      std::vector<int> touched;
      if (improve_city(a, touched)) {
        ++moves;
        touched.push_back(a);
        for (int t : touched)
          if (!queued[static_cast<std::size_t>(t)]) {
            queued[static_cast<std::size_t>(t)] = 1;
            q.push(t);
          }
      }
    }
    return moves;
  }

  /// The open path: the ring cut at the dummy node.
  std::vector<int> path() const {
    std::vector<int> p;
    const int d = pos_[static_cast<std::size_t>(n_)];
    for (int k = 1; k < m_; ++k) p.push_back(tour_[static_cast<std::size_t>((d + k) % m_)]);
    return p;
  }

private:
  int succ(int c) const { return tour_[static_cast<std::size_t>((pos_[static_cast<std::size_t>(c)] + 1) % m_)]; }
  int pred(int c) const { return tour_[static_cast<std::size_t>((pos_[static_cast<std::size_t>(c)] + m_ - 1) % m_)]; }
  double cost(int a, int b) { return (a == n_ || b == n_) ? 0.0 : costs_.cost(a, b); }

  /// Reverses the forward segment f … t (or, equivalently for the cyclic tour, its complement).
  void reverse(int f, int t) {
    int i = pos_[static_cast<std::size_t>(f)], j = pos_[static_cast<std::size_t>(t)];
    int len = (j - i + m_) % m_ + 1;
    if (2 * len > m_) {  // the complement succ(t) … pred(f) is shorter
      const int ni = (j + 1) % m_, nj = (i + m_ - 1) % m_;
      i = ni;
      j = nj;
      len = m_ - len;
    }
    for (int s = 0; s < len / 2; ++s) {
      std::swap(tour_[static_cast<std::size_t>(i)], tour_[static_cast<std::size_t>(j)]);
      pos_[static_cast<std::size_t>(tour_[static_cast<std::size_t>(i)])] = i;
      pos_[static_cast<std::size_t>(tour_[static_cast<std::size_t>(j)])] = j;
      i = (i + 1) % m_;
      j = (j + m_ - 1) % m_;
    }
  }

  /// Removes edges {u1,u2}, {v1,v2} (same orientation) and adds {u1,v1}, {u2,v2}.
  void move2(int u1, int u2, int v1, int v2) {
    if (succ(u1) == u2)
      reverse(u2, v1);
    else
      reverse(v1, u2);
    (void)v2;
  }

  bool improve_city(int a, std::vector<int>& touched) {
    if (a == n_ || m_ < 5) return false;
    static constexpr double eps = 1e-9;
    const auto& cands = cand_[static_cast<std::size_t>(a)];
    // 2-opt: new edge (a, c) with both successor and predecessor variants.
    for (int dir = 0; dir < 2; ++dir)
      for (std::size_t ci = 0; ci <= cands.size(); ++ci) {
        const int c = ci < cands.size() ? cands[ci] : n_;
        const int b = dir == 0 ? succ(a) : pred(a);
        const int d = dir == 0 ? succ(c) : pred(c);
        if (c == b || d == a || c == a) continue;
        const double delta = cost(a, c) + cost(b, d) - cost(a, b) - cost(c, d);
        if (delta < -eps) {
          move2(a, b, c, d);
          touched.insert(touched.end(), {b, c, d});
          return true;
        }
      }
    // Or-opt: the segment of k points starting (forward) or ending at a moves between c and succ(c).
    for (int k = 1; k <= 3 && k + 3 <= m_; ++k)
      for (int side = 0; side < 2; ++side) {
        int s1 = a, sk = a;
        for (int t = 1; t < k; ++t) {
          if (side == 0)
            sk = succ(sk);
          else
            s1 = pred(s1);
        }
        const int A = pred(s1), B = succ(sk);
        auto in_seg = [&](int x) {
          const int off = (pos_[static_cast<std::size_t>(x)] - pos_[static_cast<std::size_t>(s1)] + m_) % m_;
          return off < k;
        };
        const double removed_ab = cost(A, s1) + cost(sk, B);
        const double added_ab = cost(A, B);
        for (int end = 0; end < 2; ++end) {
          const auto& cl = cand_[static_cast<std::size_t>(end == 0 ? s1 : sk)];
          for (std::size_t ci = 0; ci <= cl.size(); ++ci) {
            const int c0 = ci < cl.size() ? cl[ci] : n_;
            if (in_seg(c0)) continue;
            for (int var = 0; var < 2; ++var) {
              const int c = var == 0 ? c0 : pred(c0);
              const int d = var == 0 ? succ(c0) : c0;
              if (in_seg(c) || in_seg(d) || c == B || d == A) continue;
              const double base = added_ab - removed_ab - cost(c, d);
              const double drev = base + cost(c, sk) + cost(s1, d);
              const double dfwd = base + cost(c, s1) + cost(sk, d);
              if (std::min(drev, dfwd) < -eps) {
                move2(A, s1, c, d);                    // A c … B sk … s1 d
                move2(A, c, B, sk);                    // A B … c sk … s1 d
                if (dfwd < drev) move2(c, sk, s1, d);  // c s1 … sk d
                touched.insert(touched.end(), {A, B, c, d, s1, sk});
                return true;
              }
            }
          }
        }
      }
    return false;
  }

  int n_, m_;
  std::vector<int> tour_, pos_;
  MoveCosts& costs_;
  std::vector<std::vector<int>> cand_;
};

}  // namespace

long optimise_open_path(const ToolPoints& tp, std::vector<int>& path, MoveCosts& costs, int neighbours, long budget) {
  std::vector<int> r = path;
  r.push_back(static_cast<int>(tp.pts.size()));  // the dummy node closes the open path
  RingOpt opt(std::move(r), costs, nearest_lists(tp.pts, neighbours));
  const long moves = opt.run(budget);
  path = opt.path();
  return moves;
}

}  // namespace millnet::pocket::detail
