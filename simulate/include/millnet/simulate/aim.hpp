#pragma once
// Ranking finishing strategies by the technological aim (Korosec & Kopac §1 and §7): the paper
// labels a part with the strategy whose machined surface is best; a shop may rather want the
// shortest machining time, or the best surface within a time budget.
//
// Every rule puts a strategy that gouges the part (max_gouge_mm > gouge tolerance) after every
// strategy that does not: a gouged part is scrap, whatever its roughness or time.
#include <string>
#include <string_view>
#include <vector>

namespace millnet::simulate {

enum class Aim { Quality, Time, QualityWithinTime };

/// "quality" | "time" | "quality_within_time"; throws millnet::Error naming the accepted values.
[[nodiscard]] Aim parse_aim(std::string_view s);
[[nodiscard]] const char* to_string(Aim aim);

/// What the simulation measured for one strategy (the figures of its metrics file).
struct StrategyScore {
  int slot = 0;                  ///< strategy slot 1..8
  double ra_median_um = 0;       ///< median areal roughness over the surface, µm
  double ra_p90_um = 0;          ///< 90th percentile, µm
  double uncut_area_mm2 = 0;     ///< surface left with more than allowance + tolerance
  double max_gouge_mm = 0;       ///< deepest cut below the design surface (≥ 0)
  double time_min = 0;           ///< machining time (kinematic), min
};

struct AimParams {
  Aim aim = Aim::Quality;
  double time_budget_min = 60;   ///< QualityWithinTime only
  double gouge_tolerance_mm = 0.002;
};

/// Indices into `scores`, best first. Rules (ties broken by the next key, finally by slot):
///  * Quality: non-gouging first; then ra_median, ra_p90, uncut area, time;
///  * Time: non-gouging first; then time, ra_median;
///  * QualityWithinTime: non-gouging first; then those within the budget by Quality, then the
///    others by time.
/// O(n log n). Deterministic (a total order).
[[nodiscard]] std::vector<std::size_t> rank_strategies(const std::vector<StrategyScore>& scores,
                                                       const AimParams& params);

/// Spearman's rank correlation of two rankings of the same n items (rank_a[i], rank_b[i] = the
/// 1-based rank of item i in each; no ties): 1 − 6·Σd² / (n(n² − 1)). n < 2 ⇒ NaN.
[[nodiscard]] double spearman(const std::vector<int>& rank_a, const std::vector<int>& rank_b);

}  // namespace millnet::simulate
