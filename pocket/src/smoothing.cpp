// Tour smoothing (smoothing.hpp): weak smoothing here; linking in linking.cpp, the extra passes'
// ring optimisation in ring_opt.cpp; smooth_tour runs them in order.
#include "millnet/pocket/smoothing.hpp"

#include "tour_internal.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

namespace millnet::pocket {

namespace {

using detail::dist;
using detail::Key;
using detail::MoveCosts;
using detail::polyline_length;

std::array<int, 2> delta(const ToolPoints& tp, int a, int b) {
  const auto& pa = tp.ij[static_cast<std::size_t>(a)];
  const auto& pb = tp.ij[static_cast<std::size_t>(b)];
  return {pb[0] - pa[0], pb[1] - pa[1]};
}
bool is_diag(const std::array<int, 2>& d) { return std::abs(d[0]) == 1 && std::abs(d[1]) == 1; }
bool is_unit(const std::array<int, 2>& d) { return std::abs(d[0]) + std::abs(d[1]) == 1; }

// --- weak smoothing -------------------------------------------------------------------------------

/// Types 1 and 2 on the window path[i … i+4]; returns the type rewritten (0 = none).
int rewrite_parallel(const ToolPoints& tp, std::vector<int>& path, std::size_t i, const MoveOk& move_ok) {
  const int p0 = path[i], p1 = path[i + 1], p2 = path[i + 2], p3 = path[i + 3], p4 = path[i + 4];
  const auto d0 = delta(tp, p0, p1), d1 = delta(tp, p1, p2), d2 = delta(tp, p2, p3), d3 = delta(tp, p3, p4);
  auto parallel = [](const std::array<int, 2>& u, const std::array<int, 2>& v) {
    return (u[0] == v[0] && u[1] == v[1]) || (u[0] == -v[0] && u[1] == -v[1]);
  };
  int type = 0;
  if (is_diag(d0) && is_unit(d1) && is_diag(d2) && is_unit(d3) && parallel(d0, d2))
    type = 1;
  else if (is_unit(d0) && is_diag(d1) && is_unit(d2) && is_diag(d3) && parallel(d1, d3))
    type = 2;
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
  return (static_cast<Key>(static_cast<std::uint32_t>(i0)) << 33) ^
         (static_cast<Key>(static_cast<std::uint32_t>(j0)) << 1) ^ (o ? 1U : 0U);
}

// --- smooth_tour, step by step ---------------------------------------------------------------------

void check_tour(const ToolPoints& tp, const std::vector<int>& ring, const SmoothingParams& params) {
  const std::size_t n = tp.pts.size();
  if (tp.ij.size() != n) throw Error("smooth_tour: tool points without grid indices (ij)");
  {
    std::vector<char> seen(n, 0);
    bool perm = ring.size() == n;
    for (int i : ring) {
      if (!perm) break;
      if (i < 0 || static_cast<std::size_t>(i) >= n || seen[static_cast<std::size_t>(i)])
        perm = false;
      else
        seen[static_cast<std::size_t>(i)] = 1;
    }
    if (!perm) throw Error("smooth_tour: the tour is not a permutation of the " + std::to_string(n) + " tool points");
  }
  if (!(params.link_max_ratio >= 1)) throw Error("smoothing parameters: 'link_max_ratio' must be ≥ 1");
  if (!(params.link_max_mm >= 0)) throw Error("smoothing parameters: 'link_max_mm' must be ≥ 0");
  if (!(params.retract_penalty_mm >= 0)) throw Error("smoothing parameters: 'retract_penalty_mm' must be ≥ 0");
  if (params.opt_neighbours < 1) throw Error("smoothing parameters: 'opt_neighbours' must be ≥ 1");
}

/// The ring opened at its most expensive move (the one a retraction or a long link would need). O(N).
std::vector<int> open_at_costliest_move(const std::vector<int>& ring, MoveCosts& costs) {
  const std::size_t n = ring.size();
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
  return path;
}

/// Moves of the path that would overcut (not move_ok).
int overcut_moves(const std::vector<int>& p, MoveCosts& costs) {
  int c = 0;
  for (std::size_t k = 1; k < p.size(); ++k) c += costs.get(p[k - 1], p[k]).ok ? 0 : 1;
  return c;
}

void add_weak(WeakStats& weak, const WeakStats& w) {
  weak.type1 += w.type1;
  weak.type2 += w.type2;
  weak.type3 += w.type3;
  weak.saved_mm += w.saved_mm;
}

struct ExtraPasses {
  double saved_mm = 0;
  long moves = 0;
};

/// 2-opt / Or-opt on the open path, then weak smoothing again (when on).
ExtraPasses extra_passes(const ToolPoints& tp, std::vector<int>& path, const MoveOk& move_ok, MoveCosts& costs,
                         const SmoothingParams& params, WeakStats& weak) {
  ExtraPasses ex;
  const double before = polyline_length(tp, path);
  const long budget = params.max_opt_moves > 0 ? params.max_opt_moves : 50 * static_cast<long>(tp.pts.size());
  ex.moves = detail::optimise_open_path(tp, path, costs, params.opt_neighbours, budget);
  if (params.weak) add_weak(weak, weak_smoothing(tp, path, move_ok));
  ex.saved_mm = before - polyline_length(tp, path);
  return ex;
}

/// Strong smoothing: overcutting moves become links or retractions (a new chain). O(N + link lengths).
std::vector<std::vector<int>> strong_smoothing(const std::vector<int>& path, MoveCosts& costs, SmoothingStats& st) {
  std::vector<std::vector<int>> chains;
  int before_linking = 0, links = 0;
  double link_len = 0;
  chains.emplace_back(1, path.front());
  for (std::size_t k = 1; k < path.size(); ++k) {
    const int a = path[k - 1], b = path[k];
    const auto& e = costs.get(a, b);
    if (e.ok) {
      chains.back().push_back(b);
      continue;
    }
    ++before_linking;
    if (e.linked) {
      const auto l = costs.link(a, b);
      chains.back().insert(chains.back().end(), l.begin() + 1, l.end());
      ++links;
      link_len += e.cost;
    } else {
      chains.emplace_back(1, b);
    }
  }
  st.retractions_before_linking = before_linking;
  st.links = links;
  st.link_length_mm = link_len;
  return chains;
}

/// Cut and rapid lengths of the chains and the retractions between them.
void chain_stats(const ToolPoints& tp, const std::vector<std::vector<int>>& chains, SmoothingStats& st) {
  double cut = 0;
  for (const auto& c : chains) cut += polyline_length(tp, c);
  double rapid = 0;
  for (std::size_t k = 1; k < chains.size(); ++k) rapid += dist(tp, chains[k - 1].back(), chains[k].front());
  st.retractions = chains.size() - 1;
  st.tour_length_mm = cut;
  st.rapid_length_mm = rapid;
}

}  // namespace

std::vector<std::pair<std::string, double>> SmoothingStats::key_values() const {
  // Sorted by key: the order the metrics files have had since these figures lived in a std::map.
  return {{"link_length_mm", link_length_mm},
          {"links", links},
          {"min_retractions", min_retractions},
          {"opt_moves", static_cast<double>(opt_moves)},
          {"rapid_length_mm", rapid_length_mm},
          {"reachable_regions", reachable_regions},
          {"retractions", static_cast<double>(retractions)},
          {"retractions_before_linking", retractions_before_linking},
          {"som_overcut_moves", som_overcut_moves},
          {"som_tour_length_mm", som_tour_length_mm},
          {"tour_length_mm", tour_length_mm},
          {"two_opt_saved_mm", two_opt_saved_mm},
          {"weak_patterns", weak.patterns()},
          {"weak_smoothing_saved_mm", weak.saved_mm},
          {"weak_type1", weak.type1},
          {"weak_type2", weak.type2},
          {"weak_type3", weak.type3}};
}

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
      std::reverse(path.begin() + static_cast<std::ptrdiff_t>(i + 1),
                   path.begin() + static_cast<std::ptrdiff_t>(best + 1));
      for (std::size_t k = i + 1; k < best; ++k) add(k);  // diagonals inside the reversed part moved
      ++st.type3;
      st.saved_mm += save;
      changed = true;
    }
  }
  return st;
}

SmoothedTour smooth_tour(const ToolPoints& tp, const std::vector<int>& ring, const MoveOk& move_ok,
                         const SmoothingParams& params) {
  check_tour(tp, ring, params);
  SmoothedTour out;
  auto& st = out.stats;
  if (tp.pts.empty()) return out;

  const detail::GridGraph graph(tp, move_ok);
  MoveCosts costs(tp, move_ok, graph, params);
  const int regions = graph.components();
  st.reachable_regions = regions;
  st.min_retractions = regions - 1;

  std::vector<int> path = open_at_costliest_move(ring, costs);
  st.som_tour_length_mm = polyline_length(tp, path);
  st.som_overcut_moves = overcut_moves(path, costs);

  if (params.weak) add_weak(st.weak, weak_smoothing(tp, path, move_ok));
  ExtraPasses extra;
  if (params.extra_passes && tp.pts.size() >= 4) extra = extra_passes(tp, path, move_ok, costs, params, st.weak);
  st.two_opt_saved_mm = extra.saved_mm;
  st.opt_moves = extra.moves;

  out.chains = strong_smoothing(path, costs, st);
  chain_stats(tp, out.chains, st);
  out.order = std::move(path);
  return out;
}

}  // namespace millnet::pocket
