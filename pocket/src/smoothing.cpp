#include "millnet/pocket/smoothing.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

namespace millnet::pocket {

namespace {

using Key = std::uint64_t;

Key pair_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<Key>(hi) << 32) | lo;
}

Key ij_key(int i, int j) {
  return (static_cast<Key>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
}

double dist(const ToolPoints& tp, int a, int b) {
  return (tp.pts[static_cast<std::size_t>(a)] - tp.pts[static_cast<std::size_t>(b)]).norm();
}

std::array<int, 2> delta(const ToolPoints& tp, int a, int b) {
  const auto& pa = tp.ij[static_cast<std::size_t>(a)];
  const auto& pb = tp.ij[static_cast<std::size_t>(b)];
  return {pb[0] - pa[0], pb[1] - pa[1]};
}
bool is_diag(const std::array<int, 2>& d) { return std::abs(d[0]) == 1 && std::abs(d[1]) == 1; }
bool is_unit(const std::array<int, 2>& d) { return std::abs(d[0]) + std::abs(d[1]) == 1; }

/// The 8-neighbour tool-point graph: an edge joins grid neighbours whose straight move is move_ok.
class GridGraph {
public:
  GridGraph(const ToolPoints& tp, const MoveOk& move_ok) : tp_(tp), move_ok_(move_ok), adj_(tp.pts.size()) {
    for (std::size_t k = 0; k < tp.pts.size(); ++k) index_.emplace(ij_key(tp.ij[k][0], tp.ij[k][1]), static_cast<int>(k));
    // 4 of the 8 directions per point, each edge checked once: O(N) move_ok calls.
    static constexpr int dirs[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    for (std::size_t k = 0; k < tp.pts.size(); ++k)
      for (const auto& d : dirs) {
        const int o = at(tp.ij[k][0] + d[0], tp.ij[k][1] + d[1]);
        if (o < 0 || !move_ok_(tp.pts[k], tp.pts[static_cast<std::size_t>(o)])) continue;
        adj_[k].push_back(o);
        adj_[static_cast<std::size_t>(o)].push_back(static_cast<int>(k));
      }
    for (auto& v : adj_) std::sort(v.begin(), v.end());  // deterministic expansion order
  }

  int at(int i, int j) const {
    const auto it = index_.find(ij_key(i, j));
    return it == index_.end() ? -1 : it->second;
  }

  /// Connected components (BFS). O(N).
  int components() const {
    std::vector<int> comp(adj_.size(), -1);
    int c = 0;
    std::vector<int> stack;
    for (std::size_t s = 0; s < adj_.size(); ++s) {
      if (comp[s] >= 0) continue;
      stack.assign(1, static_cast<int>(s));
      comp[s] = c;
      while (!stack.empty()) {
        const int u = stack.back();
        stack.pop_back();
        for (int v : adj_[static_cast<std::size_t>(u)])
          if (comp[static_cast<std::size_t>(v)] < 0) {
            comp[static_cast<std::size_t>(v)] = c;
            stack.push_back(v);
          }
      }
      ++c;
    }
    return c;
  }

  /// A* from a to b, pruned at max_len, then string-pulled. Empty when there is no such link.
  std::vector<int> link(int a, int b, double max_len) const {
    if (a == b) return {a};
    struct Node {
      double f;
      int v;
      bool operator>(const Node& o) const { return f > o.f || (f == o.f && v > o.v); }
    };
    std::unordered_map<int, std::pair<double, int>> g;  // vertex → (cost, parent)
    std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
    g[a] = {0.0, -1};
    open.push({dist(tp_, a, b), a});
    const double slack = 1e-9 * (1 + max_len);
    bool found = false;
    while (!open.empty()) {
      const Node nd = open.top();
      open.pop();
      const double gu = g[nd.v].first;
      if (nd.f > gu + dist(tp_, nd.v, b) + slack) continue;  // stale entry
      if (nd.v == b) {
        found = true;
        break;
      }
      for (int w : adj_[static_cast<std::size_t>(nd.v)]) {
        const double gw = gu + dist(tp_, nd.v, w);
        const double fw = gw + dist(tp_, w, b);
        if (fw > max_len + slack) continue;
        auto it = g.find(w);
        if (it != g.end() && it->second.first <= gw) continue;
        g[w] = {gw, nd.v};
        open.push({fw, w});
      }
    }
    if (!found) return {};
    std::vector<int> path;
    for (int v = b; v >= 0; v = g[v].second) path.push_back(v);
    std::reverse(path.begin(), path.end());
    // String pulling: from each kept point jump to the farthest later point reachable straight.
    // O(L²) move_ok calls for a link of L points (links are short).
    std::vector<int> pulled{path.front()};
    std::size_t cur = 0;
    while (cur + 1 < path.size()) {
      std::size_t nxt = cur + 1;
      for (std::size_t k = path.size() - 1; k > cur + 1; --k)
        if (move_ok_(tp_.pts[static_cast<std::size_t>(path[cur])], tp_.pts[static_cast<std::size_t>(path[k])])) {
          nxt = k;
          break;
        }
      pulled.push_back(path[nxt]);
      cur = nxt;
    }
    return pulled;
  }

private:
  const ToolPoints& tp_;
  const MoveOk& move_ok_;
  std::vector<std::vector<int>> adj_;
  std::unordered_map<Key, int> index_;
};

double polyline_length(const ToolPoints& tp, const std::vector<int>& p) {
  double s = 0;
  for (std::size_t k = 1; k < p.size(); ++k) s += dist(tp, p[k - 1], p[k]);
  return s;
}

/// Obstacle-aware move costs with a cache (moves are queried many times by the local search).
class MoveCosts {
public:
  MoveCosts(const ToolPoints& tp, const MoveOk& move_ok, const GridGraph& graph, const SmoothingParams& p)
      : tp_(tp), move_ok_(move_ok), graph_(graph), p_(p) {}

  struct Entry {
    double cost;
    bool ok;            ///< straight move is move_ok
    bool linked;        ///< a link replaces it
  };

  const Entry& get(int a, int b) {
    const Key k = pair_key(a, b);
    auto it = cache_.find(k);
    if (it != cache_.end()) return it->second;
    const double d = dist(tp_, a, b);
    Entry e{d, true, false};
    if (!move_ok_(tp_.pts[static_cast<std::size_t>(a)], tp_.pts[static_cast<std::size_t>(b)])) {
      e.ok = false;
      e.cost = d + p_.retract_penalty_mm;
      if (p_.linking) {
        double cap = p_.link_max_ratio * d;
        if (p_.link_max_mm > 0) cap = std::min(cap, p_.link_max_mm);
        auto path = graph_.link(std::min(a, b), std::max(a, b), cap);
        if (!path.empty()) {
          e.linked = true;
          e.cost = polyline_length(tp_, path);
          links_.emplace(k, std::move(path));
        }
      }
    }
    return cache_.emplace(k, e).first->second;
  }
  double cost(int a, int b) { return get(a, b).cost; }

  /// The link a → b (points a … b), when get(a, b).linked.
  std::vector<int> link(int a, int b) {
    std::vector<int> p = links_.at(pair_key(a, b));
    if (p.front() != a) std::reverse(p.begin(), p.end());
    return p;
  }

private:
  const ToolPoints& tp_;
  const MoveOk& move_ok_;
  const GridGraph& graph_;
  const SmoothingParams& p_;
  std::unordered_map<Key, Entry> cache_;
  std::unordered_map<Key, std::vector<int>> links_;
};

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
            if (static_cast<std::size_t>(j) != i) cand.emplace_back((pts[static_cast<std::size_t>(j)] - pts[i]).squaredNorm(), j);
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
      : n_(static_cast<int>(ring.size()) - 1), m_(static_cast<int>(ring.size())), tour_(std::move(ring)),
        pos_(tour_.size()), costs_(costs), cand_(std::move(cand)) {
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
          if (side == 0) sk = succ(sk); else s1 = pred(s1);
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
                move2(A, s1, c, d);   // A c … B sk … s1 d
                move2(A, c, B, sk);   // A B … c sk … s1 d
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

// --- weak smoothing -------------------------------------------------------------------------------

/// Types 1 and 2 on the window path[i … i+4]; returns the type rewritten (0 = none).
int rewrite_parallel(const ToolPoints& tp, std::vector<int>& path, std::size_t i, const MoveOk& move_ok) {
  const int p0 = path[i], p1 = path[i + 1], p2 = path[i + 2], p3 = path[i + 3], p4 = path[i + 4];
  const auto d0 = delta(tp, p0, p1), d1 = delta(tp, p1, p2), d2 = delta(tp, p2, p3), d3 = delta(tp, p3, p4);
  auto parallel = [](const std::array<int, 2>& u, const std::array<int, 2>& v) {
    return (u[0] == v[0] && u[1] == v[1]) || (u[0] == -v[0] && u[1] == -v[1]);
  };
  int type = 0;
  if (is_diag(d0) && is_unit(d1) && is_diag(d2) && is_unit(d3) && parallel(d0, d2)) type = 1;
  else if (is_unit(d0) && is_diag(d1) && is_unit(d2) && is_diag(d3) && parallel(d1, d3)) type = 2;
  if (type == 0) return 0;
  // The interior three points in the (unique, when it exists) order that makes four unit steps.
  static constexpr int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const int mid[3] = {p1, p2, p3};
  for (const auto& pm : perms) {
    const int q[5] = {p0, mid[pm[0]], mid[pm[1]], mid[pm[2]], p4};
    bool ok = true;
    for (int s = 0; s < 4 && ok; ++s) ok = is_unit(delta(tp, q[s], q[s + 1]));
    for (int s = 0; s < 4 && ok; ++s)
      ok = move_ok(tp.pts[static_cast<std::size_t>(q[s])], tp.pts[static_cast<std::size_t>(q[s + 1])]);
    if (!ok) continue;
    for (int s = 1; s < 4; ++s) path[i + static_cast<std::size_t>(s)] = q[s];
    return type;
  }
  return 0;
}

/// Key of the grid cell crossed by a diagonal move a→b, with the diagonal's orientation.
Key diag_key(const ToolPoints& tp, int a, int b, bool other) {
  const auto& pa = tp.ij[static_cast<std::size_t>(a)];
  const auto& pb = tp.ij[static_cast<std::size_t>(b)];
  const int i0 = std::min(pa[0], pb[0]), j0 = std::min(pa[1], pb[1]);
  const bool slash = (pb[0] - pa[0]) == (pb[1] - pa[1]);  // "/" joins (i0,j0)-(i0+1,j0+1)
  const bool o = other ? !slash : slash;
  return (static_cast<Key>(static_cast<std::uint32_t>(i0)) << 33) ^ (static_cast<Key>(static_cast<std::uint32_t>(j0)) << 1) ^
         (o ? 1U : 0U);
}

}  // namespace

WeakStats weak_smoothing(const ToolPoints& tp, std::vector<int>& path, const MoveOk& move_ok) {
  WeakStats st;
  if (tp.ij.size() != tp.pts.size()) throw Error("weak_smoothing: tool points without grid indices");
  const double g = tp.frame.spacing;
  const double save = 2 * g * (std::numbers::sqrt2 - 1);
  bool changed = true;
  while (changed) {  // each sweep O(N); every rewrite shortens the path, so this ends
    changed = false;
    // Types 1 and 2.
    for (std::size_t i = 0; i + 4 < path.size(); ++i) {
      const int t = rewrite_parallel(tp, path, i, move_ok);
      if (t == 0) continue;
      (t == 1 ? st.type1 : st.type2) += 1;
      st.saved_mm += save;
      changed = true;
    }
    // Type 3: a diagonal at i and the crossing diagonal of the same cell at k > i + 1 become two unit
    // steps, path[i+1 … k] reversed. Positions are looked up in a hash and validated (entries go stale).
    std::unordered_multimap<Key, std::size_t> diag;
    auto add = [&](std::size_t k) {
      if (k + 1 < path.size() && is_diag(delta(tp, path[k], path[k + 1])))
        diag.emplace(diag_key(tp, path[k], path[k + 1], false), k);
    };
    for (std::size_t k = 0; k + 1 < path.size(); ++k) add(k);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      if (!is_diag(delta(tp, path[i], path[i + 1]))) continue;
      const Key other = diag_key(tp, path[i], path[i + 1], true);
      std::size_t best = 0;
      const auto range = diag.equal_range(other);
      for (auto it = range.first; it != range.second; ++it) {
        const std::size_t k = it->second;
        if (k <= i + 1 || k + 1 >= path.size() || (best != 0 && k >= best)) continue;
        if (!is_diag(delta(tp, path[k], path[k + 1])) || diag_key(tp, path[k], path[k + 1], false) != other) continue;
        best = k;
      }
      if (best == 0) continue;
      const int a = path[i], b = path[i + 1], c = path[best], d = path[best + 1];
      if (!is_unit(delta(tp, a, c)) || !is_unit(delta(tp, b, d))) continue;
      if (!move_ok(tp.pts[static_cast<std::size_t>(a)], tp.pts[static_cast<std::size_t>(c)]) ||
          !move_ok(tp.pts[static_cast<std::size_t>(b)], tp.pts[static_cast<std::size_t>(d)]))
        continue;
      std::reverse(path.begin() + static_cast<std::ptrdiff_t>(i + 1), path.begin() + static_cast<std::ptrdiff_t>(best + 1));
      for (std::size_t k = i + 1; k < best; ++k) add(k);  // diagonals inside the reversed part moved
      ++st.type3;
      st.saved_mm += save;
      changed = true;
    }
  }
  return st;
}

std::vector<int> find_link(const ToolPoints& tp, int a, int b, const MoveOk& move_ok, double max_len_mm) {
  const auto n = static_cast<int>(tp.pts.size());
  if (a < 0 || b < 0 || a >= n || b >= n) throw Error("find_link: point index out of range");
  GridGraph graph(tp, move_ok);
  return graph.link(a, b, max_len_mm);
}

SmoothedTour smooth_tour(const ToolPoints& tp, const std::vector<int>& ring, const MoveOk& move_ok,
                         const SmoothingParams& params) {
  const std::size_t n = tp.pts.size();
  if (tp.ij.size() != n) throw Error("smooth_tour: tool points without grid indices (ij)");
  {
    std::vector<char> seen(n, 0);
    bool perm = ring.size() == n;
    for (int i : ring) {
      if (!perm) break;
      if (i < 0 || static_cast<std::size_t>(i) >= n || seen[static_cast<std::size_t>(i)]) perm = false;
      else seen[static_cast<std::size_t>(i)] = 1;
    }
    if (!perm) throw Error("smooth_tour: the tour is not a permutation of the " + std::to_string(n) + " tool points");
  }
  if (!(params.link_max_ratio >= 1)) throw Error("smoothing parameters: 'link_max_ratio' must be ≥ 1");
  if (!(params.link_max_mm >= 0)) throw Error("smoothing parameters: 'link_max_mm' must be ≥ 0");
  if (!(params.retract_penalty_mm >= 0)) throw Error("smoothing parameters: 'retract_penalty_mm' must be ≥ 0");
  if (params.opt_neighbours < 1) throw Error("smoothing parameters: 'opt_neighbours' must be ≥ 1");
  SmoothedTour out;
  auto& st = out.stats;
  if (n == 0) return out;

  GridGraph graph(tp, move_ok);
  MoveCosts costs(tp, move_ok, graph, params);
  const int regions = graph.components();
  st["reachable_regions"] = regions;
  st["min_retractions"] = regions - 1;

  // Open the ring at its most expensive move (the one a retraction or a long link would need). O(N).
  std::vector<int> path = ring;
  if (n > 2) {
    std::size_t cut = n - 1;  // the move ring[n−1] → ring[0]
    double worst = -1;
    for (std::size_t k = 0; k < n; ++k) {
      const double c = costs.cost(ring[k], ring[(k + 1) % n]);
      if (c > worst) {
        worst = c;
        cut = k;
      }
    }
    std::rotate(path.begin(), path.begin() + static_cast<std::ptrdiff_t>((cut + 1) % n), path.end());
  }
  auto euclid = [&](const std::vector<int>& p) { return polyline_length(tp, p); };
  auto bad_moves = [&](const std::vector<int>& p) {
    int c = 0;
    for (std::size_t k = 1; k < p.size(); ++k) c += costs.get(p[k - 1], p[k]).ok ? 0 : 1;
    return c;
  };
  st["som_tour_length_mm"] = euclid(path);
  st["som_overcut_moves"] = bad_moves(path);

  WeakStats weak;
  auto add_weak = [&](const WeakStats& w) {
    weak.type1 += w.type1;
    weak.type2 += w.type2;
    weak.type3 += w.type3;
    weak.saved_mm += w.saved_mm;
  };
  if (params.weak) add_weak(weak_smoothing(tp, path, move_ok));

  double opt_saved = 0;
  long opt_moves = 0;
  if (params.extra_passes && n >= 4) {
    const double before = euclid(path);
    std::vector<int> r = path;
    r.push_back(static_cast<int>(n));  // the dummy node closes the open path
    RingOpt opt(std::move(r), costs, nearest_lists(tp.pts, params.opt_neighbours));
    const long budget = params.max_opt_moves > 0 ? params.max_opt_moves : 50 * static_cast<long>(n);
    opt_moves = opt.run(budget);
    path = opt.path();
    if (params.weak) add_weak(weak_smoothing(tp, path, move_ok));
    opt_saved = before - euclid(path);
  }
  st["weak_smoothing_saved_mm"] = weak.saved_mm;
  st["weak_patterns"] = weak.patterns();
  st["weak_type1"] = weak.type1;
  st["weak_type2"] = weak.type2;
  st["weak_type3"] = weak.type3;
  st["two_opt_saved_mm"] = opt_saved;
  st["opt_moves"] = static_cast<double>(opt_moves);

  // Strong smoothing: overcutting moves become links or retractions. O(N + link lengths).
  int before_linking = 0, links = 0;
  double link_len = 0;
  out.chains.emplace_back(1, path.front());
  for (std::size_t k = 1; k < path.size(); ++k) {
    const int a = path[k - 1], b = path[k];
    const auto& e = costs.get(a, b);
    if (e.ok) {
      out.chains.back().push_back(b);
      continue;
    }
    ++before_linking;
    if (e.linked) {
      const auto l = costs.link(a, b);
      out.chains.back().insert(out.chains.back().end(), l.begin() + 1, l.end());
      ++links;
      link_len += e.cost;
    } else {
      out.chains.emplace_back(1, b);
    }
  }
  double cut = 0;
  for (const auto& c : out.chains) cut += euclid(c);
  double rapid = 0;
  for (std::size_t k = 1; k < out.chains.size(); ++k) rapid += dist(tp, out.chains[k - 1].back(), out.chains[k].front());
  st["retractions_before_linking"] = before_linking;
  st["links"] = links;
  st["link_length_mm"] = link_len;
  st["retractions"] = static_cast<double>(out.chains.size() - 1);
  st["tour_length_mm"] = cut;
  st["rapid_length_mm"] = rapid;
  out.order = std::move(path);
  return out;
}

}  // namespace millnet::pocket
