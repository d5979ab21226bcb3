#pragma once
// Ranking finishing strategies by the technological aim (Korosec & Kopac §1 and §7): the paper
// labels a part with the strategy whose machined surface is best; a shop may rather want the
// shortest machining time, or the best surface within a time budget.
//
// Every rule puts a strategy that gouges the part (max_gouge_mm > gouge tolerance) after every
// strategy that does not: a gouged part is scrap, whatever its roughness or time. Next, a strategy
// that leaves part of the surface unfinished goes after every strategy that finishes it: its
// untouched stock is a flat, smooth plane whose Ra of ~0 would otherwise win the quality rule (a
// Z-level finish leaves a plateau's top as it found it). "Complete" is relative, because some
// stock is out of every strategy's reach (a ball cannot enter the concave corner at a wall's
// foot): uncut area ≤ the smallest uncut area among the non-gouging strategies + complete_share ×
// the surface area.
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::simulate {

enum class Aim { Quality, Time, QualityWithinTime, TimeToSpec };

/// "quality" | "time" | "quality_within_time" | "time_to_spec"; throws millnet::Error naming the
/// accepted values.
[[nodiscard]] Aim parse_aim(std::string_view s);
[[nodiscard]] const char* to_string(Aim aim);

/// What the simulation measured for one strategy (the figures of its metrics file).
struct StrategyScore {
  int slot = 0;                 ///< strategy slot 1..8
  double ra_median_um = 0;      ///< median areal roughness over the surface, µm
  double ra_p90_um = 0;         ///< 90th percentile, µm
  double uncut_area_mm2 = 0;    ///< surface left with more than allowance + tolerance
  double surface_area_mm2 = 0;  ///< the scored surface (for the completeness margin)
  double max_gouge_mm = 0;      ///< deepest cut below the design surface (≥ 0)
  double time_min = 0;          ///< machining time (kinematic), min
  /// Share of the machinable surface in the surface specification (SurfaceMetrics::spec_share);
  /// NaN when no specification was measured.
  double spec_share = std::numeric_limits<double>::quiet_NaN();
  /// Share of the sampled surface with Ra ≤ the Ra target (SurfaceMetrics::ra_target_share); NaN: none.
  double ra_target_share = std::numeric_limits<double>::quiet_NaN();
};

struct AimParams {
  Aim aim = Aim::Quality;
  double time_budget_min = 60;  ///< QualityWithinTime only
  double gouge_tolerance_mm = 0.002;
  double complete_share = 0.01;     ///< completeness margin, share of the surface area
  double out_of_spec_share = 0.01;  ///< TimeToSpec: a strategy meets the spec with spec_share ≥ 1 − this
  double near_tie_share = 0.02;     ///< TimeToSpec: times within this share of a faster one tie (→ Ra p90)
  double quality_tie_share = 0.01;  ///< Quality with an Ra target: shares within one point tie (→ time)
};

/// Whether a strategy meets the surface specification: spec_share ≥ 1 − out_of_spec_share (false
/// when no specification was measured).
[[nodiscard]] bool meets_spec(const StrategyScore& s, const AimParams& params);

/// Indices into `scores`, best first. Non-gouging strategies first, always. Then:
///  * TimeToSpec (issue 37 §2): those that meet the specification (meets_spec), by time — where
///    times are within near_tie_share of the fastest of a group, the group goes by Ra p90, then
///    time; then those that miss it, by their share in spec (more first), then time;
///  * Quality with an Ra target (ra_target_share known for all): by the share within the target,
///    more first — shares within quality_tie_share of the group's best tie and go to the faster
///    (the reading of the paper's Figures 9–10); no completeness rule: not-machined surface is
///    outside the target already;
///  * otherwise complete before incomplete (above), incomplete ones by uncut area, and among the
///    complete ones — Quality: ra_median, ra_p90, uncut area, time; Time: time, ra_median;
///    QualityWithinTime: those within the budget by Quality, then the others by time.
/// Last ties by slot. O(n²) at worst for the tie groups (n = strategies, ≤ 8). Deterministic.
[[nodiscard]] std::vector<std::size_t> rank_strategies(const std::vector<StrategyScore>& scores,
                                                       const AimParams& params);

/// Each strategy's regret (issue 37 §2): its time / the time of the best (order[0]) − 1, so the
/// best's is 0 and a strategy twice as long has 1. NaN for all when the best gouges, or with
/// TimeToSpec misses the specification (no strategy is good enough to be measured against).
[[nodiscard]] std::vector<double> regrets(const std::vector<StrategyScore>& scores,
                                          const std::vector<std::size_t>& order, const AimParams& params);

/// Each strategy's score under the aim, the output a network trained on simulated outcomes learns
/// (issue 39 §1): TimeToSpec and Time — the best's time / its time for a strategy that does not
/// gouge and (TimeToSpec) meets the specification, 0 for one that gouges or misses it; so the best
/// scores 1 and a strategy taking twice as long 0.5. When no strategy meets the specification, the
/// non-gouging ones score their share in spec / the best share (the ranking's order of those
/// that miss). Quality and QualityWithinTime: 1 for the best, 0 for the others (their order is not
/// a ratio of costs). Scores lie in [0, 1], the best's alone 1 (the others ≤ 1 − 1e-6); a score
/// s > 0 is a regret of 1/s − 1. O(n).
[[nodiscard]] std::vector<double> aim_scores(const std::vector<StrategyScore>& scores,
                                             const std::vector<std::size_t>& order, const AimParams& params);

/// The 1-based rank of each item from an order of the items, best first (order[r] = the item at
/// rank r + 1, a permutation of 0..n−1, e.g. rank_strategies'): rank[order[r]] = r + 1. O(n).
[[nodiscard]] std::vector<int> ranks_from_order(const std::vector<std::size_t>& order);

/// The slots best first, from the 1-based rank of each slot (rank[i] is slots[i]'s rank, a
/// permutation of 1..n): the inverse of ranks_from_order, spelled in slots. O(n).
[[nodiscard]] std::vector<int> slots_by_rank(const std::vector<int>& slots, const std::vector<int>& rank);

/// Spearman's rank correlation of two rankings of the same n items (rank_a[i], rank_b[i] = the
/// 1-based rank of item i in each; no ties): 1 − 6·Σd² / (n(n² − 1)). n < 2 ⇒ NaN.
[[nodiscard]] double spearman(const std::vector<int>& rank_a, const std::vector<int>& rank_b);

}  // namespace millnet::simulate
