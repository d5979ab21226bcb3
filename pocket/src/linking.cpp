// Linking (smoothing.hpp, strong smoothing): the tool-point grid graph, A* links string-pulled over
// it, and the obstacle-aware move costs that the ring optimisation and the strong smoothing share.
#include "tour_internal.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>

namespace millnet::pocket {

namespace detail {

double polyline_length(const ToolPoints& tp, const std::vector<int>& p) {
  double s = 0;
  for (std::size_t k = 1; k < p.size(); ++k) s += dist(tp, p[k - 1], p[k]);
  return s;
}

GridGraph::GridGraph(const ToolPoints& tp, const MoveOk& move_ok) : tp_(tp), move_ok_(move_ok), adj_(tp.pts.size()) {
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

int GridGraph::at(int i, int j) const {
  const auto it = index_.find(ij_key(i, j));
  return it == index_.end() ? -1 : it->second;
}

int GridGraph::components() const {
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

std::vector<int> GridGraph::link(int a, int b, double max_len) const {
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

const MoveCosts::Entry& MoveCosts::get(int a, int b) {
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

std::vector<int> MoveCosts::link(int a, int b) {
  std::vector<int> p = links_.at(pair_key(a, b));
  if (p.front() != a) std::reverse(p.begin(), p.end());
  return p;
}

}  // namespace detail

std::vector<int> find_link(const ToolPoints& tp, int a, int b, const MoveOk& move_ok, double max_len_mm) {
  const auto n = static_cast<int>(tp.pts.size());
  if (a < 0 || b < 0 || a >= n || b >= n) throw Error("find_link: point index out of range");
  detail::GridGraph graph(tp, move_ok);
  return graph.link(a, b, max_len_mm);
}

}  // namespace millnet::pocket
