#pragma once
// The self-organizing map tour of Shin & Suh §4 (after Angeniol, Vaubois & Le Texier 1988), with the
// seed's two modifications: weighted competition (eq. 6) and adaptive α from the mapping degree (eq. 5).
//
// A ring of M = node_factor·N nodes (fixed size: this implementation does not create/delete nodes as
// Angeniol's does; a ring of ~2N nodes plays the role of the grown ring, and two cities that end on the
// same node are ordered along the ring direction, so the tour is always a permutation).
// For each city X (in a seeded random order per pass): winner j_c = argmin_j (X₁−C₁)² + w·(X₂−C₂)²,
// then C_j += f(G, n)·(X − C_j), f = (1/√2)·exp(−n²/G²), n = ring distance |j − j_c| (mod M), for the
// neighbours where f > 1e-6·f(0) (|n| ≤ G·sqrt(ln 1e6)). After each pass G ← (1 − α)·G.
//
// Complexity: the winner search uses a uniform grid of nodes in the w-scaled plane, updated in O(1)
// per node move (nodes move by convex combinations toward cities, so they never leave the grid's box);
// a query costs O(1) cells once the ring has spread over the cities (pocket/src/node_grid.hpp). One
// pass costs O(N·(query + G·sqrt(ln 1e6))); the whole run O(N·G0/α + passes·N) (som_node_steps).
#include "millnet/pocket/geometry.hpp"

#include <cstdint>
#include <vector>

namespace millnet::pocket {

struct SomParams {
  double node_factor = 2.0;     ///< ring nodes M = max(3, round(node_factor·N)); ≥ 1
  double g0 = 0;                ///< initial gain G₀ in ring nodes; 0 ⇒ auto = clamp(0.1·M, 3, 30)
  double alpha = 0.1;           ///< G ← (1 − α)·G per pass (0 < α < 1), used unless adaptive_alpha
  bool adaptive_alpha = false;  ///< seed eq. 5: α = C·log(1 + exp(−K)), K = mapping degree / k_scale_mm
  double c = 0.4;               ///< the constant C of eq. 5
  /// Length unit that makes K dimensionless (eq. 3 is in the drawing's units; the seed used mm with a
  /// few hundred cities). K = sqrt(Σ_i |X_i − C*(X_i)|²) / k_scale_mm, summed over one pass, with
  /// C*(X_i) the winner right after its update.
  double k_scale_mm = 1.0;
  double alpha_min = 0.02;  ///< floor of the adaptive α so that G always decreases (a pass budget)
  double w = 1.0;           ///< weight of (X₂ − C₂)² in the competition (eq. 6); > 0
  int max_passes = 400;     ///< hard stop (the tour is still a valid permutation); the run also stops
                            ///< 20 passes after G has shrunk to the winner alone (nothing moves the
                            ///< order any more; cities sharing a node are ordered along the ring)
  double tolerance_mm = 0;  ///< a city is mapped when its node is this close; 0 ⇒ auto =
                            ///< 0.01·sqrt(bbox area / N)
  std::uint64_t seed = 1;   ///< initial ring phase and the city order of every pass
};

struct SomResult {
  std::vector<int> order;  ///< closed tour: a permutation of 0..N−1 (the ring order of the cities)
  int passes = 0;
  bool converged = false;        ///< every city has its own node within the tolerance
  std::size_t nodes = 0;         ///< M
  std::size_t shared_nodes = 0;  ///< cities that found their winner node already taken by another city
                                 ///< (such cities are ordered along the ring direction at that node)
  double final_gain = 0;         ///< G after the last pass
};

/// SOM tour through `cities` (mm). Throws millnet::Error for invalid parameters or non-finite points.
/// Deterministic for a seed (own xoshiro256** generator, no std:: distributions).
[[nodiscard]] SomResult som_tour(const std::vector<Vec2>& cities, const SomParams& params);

/// The work of som_tour on n cities, from the schedule of G alone: Σ over passes of the ring nodes
/// each city pulls (2·width + 1) and its winner queries, × n; an upper bound for adaptive α (its
/// floor alpha_min). O(passes).
[[nodiscard]] double som_node_steps(double n, const SomParams& params);

/// Σ |p[order[k+1]] − p[order[k]]|, plus the closing edge when `closed`. O(N).
[[nodiscard]] double tour_length(const std::vector<Vec2>& pts, const std::vector<int>& order, bool closed);

/// True when `order` is a permutation of 0..n−1. O(n).
[[nodiscard]] bool is_permutation_of(const std::vector<int>& order, std::size_t n);

/// Small deterministic generator (xoshiro256**, seeded through splitmix64), shared by the SOM and tests.
class Rng {
public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next();
  double uniform();                  ///< [0, 1)
  std::size_t below(std::size_t n);  ///< [0, n), n > 0
private:
  std::uint64_t s_[4];
};

}  // namespace millnet::pocket
