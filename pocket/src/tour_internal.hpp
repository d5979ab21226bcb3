#pragma once
// Internal pieces of tour smoothing (smoothing.hpp) shared by smoothing.cpp, linking.cpp and
// ring_opt.cpp (not installed; mm throughout; a path is a sequence of indices into ToolPoints::pts).
//   linking.cpp   the tool-point grid graph (A* links, string pulling) and the obstacle-aware move
//                 costs built on it
//   ring_opt.cpp  2-opt + Or-opt on the open path with those costs
#include "millnet/pocket/smoothing.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace millnet::pocket::detail {

using Key = std::uint64_t;

/// Key of an unordered pair of point indices.
inline Key pair_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<Key>(hi) << 32) | lo;
}

/// Key of a grid index (i, j).
inline Key ij_key(int i, int j) {
  return (static_cast<Key>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
}

/// Straight distance between tool points a and b.
inline double dist(const ToolPoints& tp, int a, int b) {
  return (tp.pts[static_cast<std::size_t>(a)] - tp.pts[static_cast<std::size_t>(b)]).norm();
}

/// Length of the polyline through the tool points p.
[[nodiscard]] double polyline_length(const ToolPoints& tp, const std::vector<int>& p);

/// The 8-neighbour tool-point graph: an edge joins grid neighbours whose straight move is move_ok.
/// O(N) move_ok calls to build.
class GridGraph {
public:
  GridGraph(const ToolPoints& tp, const MoveOk& move_ok);

  /// The tool point at grid index (i, j), −1 when there is none.
  [[nodiscard]] int at(int i, int j) const;
  /// Connected components (BFS). O(N).
  [[nodiscard]] int components() const;
  /// A* from a to b, pruned at max_len, then string-pulled. Empty when there is no such link.
  [[nodiscard]] std::vector<int> link(int a, int b, double max_len) const;

private:
  const ToolPoints& tp_;
  const MoveOk& move_ok_;
  std::vector<std::vector<int>> adj_;
  std::unordered_map<Key, int> index_;
};

/// Obstacle-aware move costs with a cache (moves are queried many times by the local search): a
/// straight move costs its length when move_ok, else the length of its link when linking is on and
/// a link exists, else its length + retract_penalty_mm.
class MoveCosts {
public:
  MoveCosts(const ToolPoints& tp, const MoveOk& move_ok, const GridGraph& graph, const SmoothingParams& p)
      : tp_(tp), move_ok_(move_ok), graph_(graph), p_(p) {}

  struct Entry {
    double cost;
    bool ok;      ///< straight move is move_ok
    bool linked;  ///< a link replaces it
  };

  const Entry& get(int a, int b);
  double cost(int a, int b) { return get(a, b).cost; }

  /// The link a → b (points a … b), when get(a, b).linked.
  [[nodiscard]] std::vector<int> link(int a, int b);

private:
  const ToolPoints& tp_;
  const MoveOk& move_ok_;
  const GridGraph& graph_;
  const SmoothingParams& p_;
  std::unordered_map<Key, Entry> cache_;
  std::unordered_map<Key, std::vector<int>> links_;
};

/// 2-opt + Or-opt (segments of 1–3 points, both orientations) on the open path, whose ends may
/// move, with the candidate moves among each point's `neighbours` nearest tool points; stops when
/// no candidate move gains more than 1e-9 mm or after `budget` improving moves. Rewrites path;
/// returns the improving moves made.
long optimise_open_path(const ToolPoints& tp, std::vector<int>& path, MoveCosts& costs, int neighbours, long budget);

}  // namespace millnet::pocket::detail
