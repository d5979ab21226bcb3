#pragma once
// Postprocessing of a tour through grid tool points (Shin & Suh §5, and what its future work asks).
//   * Weak smoothing: the seed's diagonal patterns on the grid rewritten as axis-parallel moves, each
//     saving 2g(√2 − 1): types 1 and 2 are four moves "two parallel diagonals + two unit steps"
//     (diagonal first = type 1, unit step first = type 2; 2g(1 + √2) → 4g), type 3 two crossing
//     diagonals of one grid cell (2g√2 → 2g, the middle of the tour reversed). A rewrite is applied only
//     if every new move is move_ok; the visited tool points never change (cut area unchanged).
//   * Extra passes (option): 2-opt and Or-opt (segments of 1–3 points, both orientations) on the open
//     path with obstacle-aware move costs: a straight move costs its length when move_ok, else the
//     length of its link (below) when linking is on, else its length + retract_penalty_mm.
//   * Strong smoothing: a move whose swept tool disk would overcut (move_ok false) either becomes a link
//     — the shortest path over the tool-point grid graph (8-neighbour moves between tool points whose
//     straight move is move_ok, A*), string-pulled, kept when ≤ link_max_ratio × the straight distance
//     (and ≤ link_max_mm when > 0) — or splits the tour into chains: retract, rapid, plunge; every
//     chain start needs a pre-drilled hole.
// Lengths in mm; a path is a sequence of indices into ToolPoints::pts.
#include "millnet/pocket/toolpoints.hpp"

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace millnet::pocket {

/// The straight tool-centre move p→q keeps the tool disk inside the pocket (Clearance::move_ok).
using MoveOk = std::function<bool(const Vec2&, const Vec2&)>;

struct SmoothingParams {
  bool linking = true;               ///< keep the tool down along grid links instead of retracting
  double link_max_ratio = 3.0;       ///< a link may be at most this × the straight distance (≥ 1)
  double link_max_mm = 0;            ///< and at most this long; 0 ⇒ no absolute cap
  bool weak = true;                  ///< the seed's weak smoothing (types 1, 2, 3)
  bool extra_passes = true;          ///< 2-opt / Or-opt with obstacle-aware costs
  int opt_neighbours = 10;           ///< candidate list size of the extra passes
  double retract_penalty_mm = 1000;  ///< cost of one retraction when reordering (≥ 0)
  long max_opt_moves = 0;            ///< budget of improving moves; 0 ⇒ 50·N
};

/// Pattern counts and savings of weak smoothing.
struct WeakStats {
  int type1 = 0, type2 = 0, type3 = 0;
  double saved_mm = 0;
  [[nodiscard]] int patterns() const { return type1 + type2 + type3; }
};

/// Figures of smooth_tour(), in mm and counts.
struct SmoothingStats {
  int reachable_regions = 0;           ///< components of the tool-point grid graph
  int min_retractions = 0;             ///< reachable_regions − 1
  double som_tour_length_mm = 0;       ///< the ring opened at its costliest move, before smoothing
  int som_overcut_moves = 0;           ///< its moves that are not move_ok
  WeakStats weak;                      ///< weak smoothing, before and after the extra passes
  double two_opt_saved_mm = 0;         ///< saved by the extra passes (and the weak smoothing after them)
  long opt_moves = 0;                  ///< improving moves the extra passes applied
  int retractions_before_linking = 0;  ///< moves that are not move_ok on the final order
  int links = 0;                       ///< of those, the ones that became links
  double link_length_mm = 0;
  std::size_t retractions = 0;  ///< chains − 1
  double tour_length_mm = 0;    ///< cut length of the chains (links included)
  double rapid_length_mm = 0;   ///< chain end → next chain start

  /// (key, value) pairs sorted by key: "link_length_mm", "links", "min_retractions", "opt_moves",
  /// "rapid_length_mm", "reachable_regions", "retractions", "retractions_before_linking",
  /// "som_overcut_moves", "som_tour_length_mm", "tour_length_mm", "two_opt_saved_mm",
  /// "weak_patterns", "weak_smoothing_saved_mm", "weak_type1", "weak_type2", "weak_type3".
  [[nodiscard]] std::vector<std::pair<std::string, double>> key_values() const;
};

/// Weak smoothing of an open path (indices into tp.pts, each grid point given by tp.ij) in place,
/// repeated until no pattern is left. O(N) per sweep (type 3 finds crossing partners through a hash
/// of grid cells); each rewrite shortens the path, so the number of sweeps is bounded.
WeakStats weak_smoothing(const ToolPoints& tp, std::vector<int>& path, const MoveOk& move_ok);

/// What smooth_tour() produced: chains of tool-point indices (links included, so a point may appear
/// again inside a link), the visiting order (a permutation) and figures.
struct SmoothedTour {
  std::vector<int> order;                ///< open path through every tool point once
  std::vector<std::vector<int>> chains;  ///< cut with the tool down; a retraction between chains
  SmoothingStats stats;                  ///< all zero when there is no tool point
};

/// Strong smoothing, weak smoothing and the extra passes on a closed tour (e.g. the SOM ring order)
/// through all points of `tp`. The ring is opened at its most expensive move. Deterministic.
/// Complexity: O(N) move_ok calls for the grid graph; the local search costs O(K) cached move costs per
/// candidate check (K = opt_neighbours) and O(min(L, N − L)) per applied move (array reversal), at
/// most max_opt_moves moves; each distinct non-move_ok pair runs one bounded A* (cached).
/// Throws millnet::Error when `ring` is not a permutation of the tool points or params are invalid.
[[nodiscard]] SmoothedTour smooth_tour(const ToolPoints& tp, const std::vector<int>& ring, const MoveOk& move_ok,
                                       const SmoothingParams& params);

/// Shortest collision-free link a → b over the tool-point grid graph (8-neighbour moves that are
/// move_ok), string-pulled (an intermediate point is dropped while the straight move stays move_ok),
/// no longer than max_len_mm. Returns the points a … b, or empty if there is none. A*, O(V log V)
/// over the visited part of the graph.
[[nodiscard]] std::vector<int> find_link(const ToolPoints& tp, int a, int b, const MoveOk& move_ok, double max_len_mm);

/// Corner blending (issue 11): a corner P of a polyline A→P→B that turns by φ becomes a tangent arc
/// of radius r from A' = P − t·u to B' = P + t·w (u, w the unit directions in and out, t = r·tan(φ/2),
/// bulge ±tan(φ/4), positive for a left turn), so that the machine keeps its speed through it (the
/// motion model times an arc as chords whose joints turn by a fraction of a degree, instead of one
/// joint of φ). r is the largest value ≤ max_radius_mm for which
///   * t ≤ half of each neighbouring segment (blends of neighbouring corners never overlap),
///   * the arc's midpoint lies ≤ max_deviation_mm from P: e = r·(1/cos(φ/2) − 1) (coverage: every
///     point of the path before the blend is within that distance of the path after it),
///   * t ≤ 0.99·√3·clearance_mm and move_ok(A', B'): the arc lies inside the triangle A'PB', whose
///     sides A'P and PB' are parts of moves already move_ok; a triangle whose three sides keep the
///     clearance and whose longest side is < 2√3·clearance keeps it everywhere inside (a wall point
///     inside would lie within the inradius ≤ side/(2√3) of a side), so the arc does not overcut;
/// r is halved (at most 4 times) while move_ok(A', B') fails; a corner whose r would fall below
/// min_radius_mm, a reversal (φ ≈ 180°) and a vertex not `blendable` stay sharp. Straight-on
/// vertices (φ < 1e-9) are dropped (collinear moves merged). O(n) move_ok calls.
struct CornerBlendParams {
  double max_radius_mm = 2.5;
  double max_deviation_mm = 1.0;
  double min_radius_mm = 0.05;
  double clearance_mm = 5;  ///< the tool centre's clearance (Clearance::clearance())
};

struct CornerBlendStats {
  int corners = 0;  ///< vertices where the path turns
  int blended = 0;  ///< of those, replaced by an arc
  int merged = 0;   ///< straight-on vertices dropped
};

/// The polyline `pts` (open, ≥ 1 point) as vertices with bulges: corners at vertices with
/// blendable[k] != 0 blended (the two ends are never touched). blendable.size() == pts.size().
[[nodiscard]] std::vector<Vertex> blend_corners(const std::vector<Vec2>& pts, const std::vector<char>& blendable,
                                                const CornerBlendParams& params, const MoveOk& move_ok,
                                                CornerBlendStats* stats = nullptr);

}  // namespace millnet::pocket
