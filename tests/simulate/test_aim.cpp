// Ranking by the technological aim and Spearman's rank correlation (hand-computed cases).
#include "millnet/simulate/aim.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace millnet::simulate;

namespace {
StrategyScore score(int slot, double ra, double p90, double time, double gouge = 0, double uncut = 0) {
  StrategyScore s;
  s.slot = slot;
  s.ra_median_um = ra;
  s.ra_p90_um = p90;
  s.time_min = time;
  s.max_gouge_mm = gouge;
  s.uncut_area_mm2 = uncut;
  return s;
}
std::vector<int> slots(const std::vector<StrategyScore>& s, const std::vector<std::size_t>& order) {
  std::vector<int> out;
  for (std::size_t i : order) out.push_back(s[i].slot);
  return out;
}
}  // namespace

TEST(Aim, QualityRanksByMedianRaThenP90) {
  const std::vector<StrategyScore> s = {score(1, 0.8, 1.0, 10), score(2, 0.5, 2.0, 30), score(3, 0.5, 1.5, 40),
                                        score(4, 1.2, 1.3, 5), score(5, 0.45, 0.9, 50)};
  EXPECT_EQ(slots(s, rank_strategies(s, {})), (std::vector<int>{5, 3, 2, 1, 4}));
}

TEST(Aim, GougingStrategyGoesLastWhateverItsRoughness) {
  const std::vector<StrategyScore> s = {score(1, 0.8, 1.0, 10), score(2, 0.1, 0.2, 1, /*gouge*/ 0.05)};
  AimParams p;
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{1, 2}));
  p.aim = Aim::Time;
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{1, 2}));
}

TEST(Aim, AStrategyThatLeavesTheSurfaceUnfinishedGoesAfterTheCompleteOnes) {
  // Surface 10,000 mm²: margin 1 % = 100 mm² over the least uncut non-gouging strategy (160 mm²).
  std::vector<StrategyScore> s{score(1, 1.2, 1.3, 30, 0, 170), score(2, 1.25, 1.3, 30, 0, 260),
                               score(3, 1.3, 1.4, 30, 0, 160), score(4, 0.0, 0.0, 20, 0, 9000),
                               score(5, 0.5, 0.6, 20, 0.01, 10)};  // 5 gouges: its 10 mm² sets no floor
  for (auto& x : s) x.surface_area_mm2 = 10000;
  // Complete: uncut ≤ 160 + 100 = 260 mm², so 1, 2 (exactly 260) and 3; 4 is not.
  EXPECT_EQ(slots(s, rank_strategies(s, {})), (std::vector<int>{1, 2, 3, 4, 5}));
  s[1].uncut_area_mm2 = 261;  // now 2 is incomplete, still before the incomplete 4 (less uncut)
  EXPECT_EQ(slots(s, rank_strategies(s, {})), (std::vector<int>{1, 3, 2, 4, 5}));
  AimParams time;
  time.aim = Aim::Time;  // incompleteness outranks time too
  EXPECT_EQ(slots(s, rank_strategies(s, time)), (std::vector<int>{1, 3, 2, 4, 5}));
  AimParams loose;
  loose.complete_share = 1;  // everything within 10,000 mm² of the least: Ra decides
  EXPECT_EQ(slots(s, rank_strategies(s, loose)), (std::vector<int>{4, 1, 2, 3, 5}));
}

TEST(Aim, TimeAndQualityWithinBudget) {
  const std::vector<StrategyScore> s = {score(1, 0.8, 1.0, 10), score(2, 0.5, 0.6, 30), score(3, 0.4, 0.5, 40),
                                        score(4, 1.2, 1.3, 5)};
  AimParams p;
  p.aim = Aim::Time;
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{4, 1, 2, 3}));
  p.aim = Aim::QualityWithinTime;
  p.time_budget_min = 30;  // 3 is over budget: it comes after every strategy within it
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{2, 1, 4, 3}));
}

TEST(Aim, ParseNamesTheAcceptedValues) {
  EXPECT_EQ(parse_aim("time"), Aim::Time);
  try {
    (void)parse_aim("speed");
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("quality_within_time"), std::string::npos);
  }
}

TEST(Aim, SpearmanHandComputed) {
  EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4, 5}, {1, 2, 3, 4, 5}), 1.0);
  EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4, 5}, {5, 4, 3, 2, 1}), -1.0);
  // d = (0, 0, 1, -1, 0): 1 - 6·2 / (5·24) = 0.9
  EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4, 5}, {1, 2, 4, 3, 5}), 0.9);
  EXPECT_TRUE(std::isnan(spearman({1}, {1})));
}

TEST(Aim, RanksFromOrderInvertTheOrder) {
  // order: item 2 best, then 0, then 3, then 1 ⇒ ranks 2, 4, 1, 3.
  EXPECT_EQ(ranks_from_order({2, 0, 3, 1}), (std::vector<int>{2, 4, 1, 3}));
  EXPECT_TRUE(ranks_from_order({}).empty());
}

TEST(Aim, SlotsByRankListTheSlotsBestFirst) {
  // slots 1..5 ranked 3, 1, 5, 2, 4 ⇒ best first 2, 4, 1, 5, 3.
  EXPECT_EQ(slots_by_rank({1, 2, 3, 4, 5}, {3, 1, 5, 2, 4}), (std::vector<int>{2, 4, 1, 5, 3}));
  // Round trip with ranks_from_order on non-contiguous slots.
  const std::vector<int> slots{1, 3, 7};
  EXPECT_EQ(slots_by_rank(slots, ranks_from_order({1, 2, 0})), (std::vector<int>{3, 7, 1}));
  EXPECT_THROW((void)slots_by_rank({1, 2}, {1}), millnet::Error);
  EXPECT_THROW((void)slots_by_rank({1, 2}, {1, 3}), millnet::Error);
}
