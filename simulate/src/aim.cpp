// Ranking strategies by the technological aim (see aim.hpp).
#include "millnet/simulate/aim.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>

namespace millnet::simulate {

Aim parse_aim(std::string_view s) {
  if (s == "quality") return Aim::Quality;
  if (s == "time") return Aim::Time;
  if (s == "quality_within_time") return Aim::QualityWithinTime;
  throw Error("aim \"" + std::string(s) + "\": expected quality, time or quality_within_time");
}

const char* to_string(Aim aim) {
  switch (aim) {
    case Aim::Quality: return "quality";
    case Aim::Time: return "time";
    case Aim::QualityWithinTime: return "quality_within_time";
  }
  return "?";
}

std::vector<std::size_t> rank_strategies(const std::vector<StrategyScore>& scores, const AimParams& params) {
  std::vector<std::size_t> order(scores.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto gouges = [&](const StrategyScore& s) { return s.max_gouge_mm > params.gouge_tolerance_mm; };
  double least_uncut = std::numeric_limits<double>::infinity();
  for (const StrategyScore& s : scores)
    if (!gouges(s)) least_uncut = std::min(least_uncut, s.uncut_area_mm2);
  auto complete = [&](const StrategyScore& s) {
    return s.uncut_area_mm2 <= least_uncut + params.complete_share * s.surface_area_mm2;
  };
  auto quality_key = [](const StrategyScore& s) {
    return std::make_tuple(s.ra_median_um, s.ra_p90_um, s.uncut_area_mm2, s.time_min, s.slot);
  };
  auto time_key = [](const StrategyScore& s) { return std::make_tuple(s.time_min, s.ra_median_um, s.slot); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t ia, std::size_t ib) {
    const StrategyScore& a = scores[ia];
    const StrategyScore& b = scores[ib];
    if (gouges(a) != gouges(b)) return !gouges(a);
    if (complete(a) != complete(b)) return complete(a);
    if (!complete(a) && a.uncut_area_mm2 != b.uncut_area_mm2) return a.uncut_area_mm2 < b.uncut_area_mm2;
    switch (params.aim) {
      case Aim::Quality: return quality_key(a) < quality_key(b);
      case Aim::Time: return time_key(a) < time_key(b);
      case Aim::QualityWithinTime: {
        const bool in_a = a.time_min <= params.time_budget_min, in_b = b.time_min <= params.time_budget_min;
        if (in_a != in_b) return in_a;
        return in_a ? quality_key(a) < quality_key(b) : time_key(a) < time_key(b);
      }
    }
    return false;
  });
  return order;
}

std::vector<int> ranks_from_order(const std::vector<std::size_t>& order) {
  std::vector<int> rank(order.size());
  for (std::size_t r = 0; r < order.size(); ++r) rank[order[r]] = static_cast<int>(r + 1);
  return rank;
}

std::vector<int> slots_by_rank(const std::vector<int>& slots, const std::vector<int>& rank) {
  if (slots.size() != rank.size()) throw Error("slots_by_rank: slots and ranks differ in length");
  std::vector<int> by(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (rank[i] < 1 || static_cast<std::size_t>(rank[i]) > slots.size())
      throw Error("slots_by_rank: rank " + std::to_string(rank[i]) + " outside 1.." + std::to_string(slots.size()));
    by[static_cast<std::size_t>(rank[i] - 1)] = slots[i];
  }
  return by;
}

double spearman(const std::vector<int>& rank_a, const std::vector<int>& rank_b) {
  if (rank_a.size() != rank_b.size()) throw Error("spearman: the two rankings differ in length");
  const auto n = static_cast<double>(rank_a.size());
  if (rank_a.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  double d2 = 0;
  for (std::size_t i = 0; i < rank_a.size(); ++i) {
    const double d = rank_a[i] - rank_b[i];
    d2 += d * d;
  }
  return 1 - 6 * d2 / (n * (n * n - 1));
}

}  // namespace millnet::simulate
