// Ranking strategies by the technological aim (see aim.hpp).
#include "millnet/simulate/aim.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

namespace millnet::simulate {

Aim parse_aim(std::string_view s) {
  if (s == "quality") return Aim::Quality;
  if (s == "time") return Aim::Time;
  if (s == "quality_within_time") return Aim::QualityWithinTime;
  if (s == "time_to_spec") return Aim::TimeToSpec;
  throw Error("aim \"" + std::string(s) + "\": expected time_to_spec, quality, time or quality_within_time");
}

const char* to_string(Aim aim) {
  switch (aim) {
    case Aim::Quality: return "quality";
    case Aim::Time: return "time";
    case Aim::QualityWithinTime: return "quality_within_time";
    case Aim::TimeToSpec: return "time_to_spec";
  }
  return "?";
}

bool meets_spec(const StrategyScore& s, const AimParams& params) {
  return s.spec_share >= 1 - params.out_of_spec_share - 1e-12;  // false on NaN
}

namespace {

using Order = std::vector<std::size_t>;

/// Reorders [first, last) of an order already sorted by its primary key into tie groups: the first
/// remaining item leads a group of every later one that `ties` with it (the rest keep their order),
/// and the group is sorted by `within`. O(n²).
template <class Tie, class Within>
void tie_groups(Order::iterator first, Order::iterator last, Tie ties, Within within) {
  while (first != last) {
    const std::size_t lead = *first;
    const auto mid = std::stable_partition(first, last, [&](std::size_t i) { return ties(lead, i); });
    std::stable_sort(first, mid, within);
    first = mid;
  }
}

/// TimeToSpec: (no gouge, meets) by time in near-tie groups (→ Ra p90); then those that miss by
/// share in spec, then time; gouging ones last in the same order.
Order rank_time_to_spec(const std::vector<StrategyScore>& scores, const AimParams& params) {
  Order order(scores.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto gouges = [&](std::size_t i) { return scores[i].max_gouge_mm > params.gouge_tolerance_mm; };
  auto meets = [&](std::size_t i) { return meets_spec(scores[i], params); };
  auto share = [&](std::size_t i) { return std::isnan(scores[i].spec_share) ? 0.0 : scores[i].spec_share; };
  auto key = [&](std::size_t i) {
    return std::make_tuple(gouges(i), !meets(i), meets(i) ? 0.0 : -share(i), scores[i].time_min, scores[i].slot);
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  const auto good_end = std::find_if(order.begin(), order.end(), [&](std::size_t i) { return gouges(i) || !meets(i); });
  tie_groups(
      order.begin(), good_end,
      [&](std::size_t lead, std::size_t i) {
        return scores[i].time_min <= scores[lead].time_min * (1 + params.near_tie_share);
      },
      [&](std::size_t a, std::size_t b) {
        return std::make_tuple(scores[a].ra_p90_um, scores[a].time_min, scores[a].slot) <
               std::make_tuple(scores[b].ra_p90_um, scores[b].time_min, scores[b].slot);
      });
  return order;
}

/// Quality with an Ra target: (no gouge) by the share within the target in one-point tie groups
/// (→ the faster); gouging ones last.
Order rank_ra_target(const std::vector<StrategyScore>& scores, const AimParams& params) {
  Order order(scores.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto gouges = [&](std::size_t i) { return scores[i].max_gouge_mm > params.gouge_tolerance_mm; };
  auto key = [&](std::size_t i) {
    return std::make_tuple(gouges(i), -scores[i].ra_target_share, scores[i].time_min, scores[i].slot);
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  const auto good_end = std::find_if(order.begin(), order.end(), gouges);
  tie_groups(
      order.begin(), good_end,
      [&](std::size_t lead, std::size_t i) {
        return scores[lead].ra_target_share - scores[i].ra_target_share <= params.quality_tie_share + 1e-12;
      },
      [&](std::size_t a, std::size_t b) {
        return std::make_tuple(scores[a].time_min, scores[a].slot) <
               std::make_tuple(scores[b].time_min, scores[b].slot);
      });
  return order;
}

}  // namespace

std::vector<std::size_t> rank_strategies(const std::vector<StrategyScore>& scores, const AimParams& params) {
  if (params.aim == Aim::TimeToSpec) return rank_time_to_spec(scores, params);
  if (params.aim == Aim::Quality && !scores.empty() &&
      std::none_of(scores.begin(), scores.end(), [](const StrategyScore& s) { return std::isnan(s.ra_target_share); }))
    return rank_ra_target(scores, params);
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
      case Aim::TimeToSpec: break;  // ranked above
    }
    return false;
  });
  return order;
}

std::vector<double> regrets(const std::vector<StrategyScore>& scores, const std::vector<std::size_t>& order,
                            const AimParams& params) {
  std::vector<double> r(scores.size(), std::numeric_limits<double>::quiet_NaN());
  if (order.empty()) return r;
  const StrategyScore& best = scores.at(order.front());
  if (best.max_gouge_mm > params.gouge_tolerance_mm) return r;
  if (params.aim == Aim::TimeToSpec && !meets_spec(best, params)) return r;
  if (!(best.time_min > 0)) return r;
  for (std::size_t i = 0; i < scores.size(); ++i) r[i] = scores[i].time_min / best.time_min - 1;
  return r;
}

/// Every strategy but the best scores below 1, so that the best is the one largest output (a
/// near-tie faster than the best, ranked after it by Ra p90, keeps a regret of ~0).
constexpr double kBelowBest = 1 - 1e-6;

std::vector<double> aim_scores(const std::vector<StrategyScore>& scores, const std::vector<std::size_t>& order,
                               const AimParams& params) {
  std::vector<double> out(scores.size(), 0.0);
  if (order.empty()) return out;
  const auto clean = [&](std::size_t i) { return !(scores[i].max_gouge_mm > params.gouge_tolerance_mm); };
  const std::size_t best = order.front();
  if (!clean(best)) return out;
  if (params.aim != Aim::Time && params.aim != Aim::TimeToSpec) {
    out[best] = 1;
    return out;
  }
  if (params.aim == Aim::TimeToSpec && !meets_spec(scores[best], params)) {
    const auto share = [&](std::size_t i) { return std::isnan(scores[i].spec_share) ? 0.0 : scores[i].spec_share; };
    const double top = share(best);
    for (std::size_t i = 0; i < scores.size(); ++i)
      if (clean(i) && top > 0) out[i] = std::clamp(share(i) / top, 0.0, kBelowBest);
    out[best] = 1;
    return out;
  }
  const double t_best = scores[best].time_min;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const bool ok = clean(i) && (params.aim == Aim::Time || meets_spec(scores[i], params));
    if (ok && scores[i].time_min > 0 && t_best > 0) out[i] = std::clamp(t_best / scores[i].time_min, 0.0, kBelowBest);
  }
  out[best] = 1;
  return out;
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
