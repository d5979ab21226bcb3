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

namespace {
StrategyScore spec_score(int slot, double time, double share, double p90 = 1.0, double gouge = 0) {
  StrategyScore s = score(slot, 1.0, p90, time, gouge);
  s.spec_share = share;
  return s;
}
}  // namespace

// Issue 37 §2, by hand: out-of-spec share 1 % ⇒ meeting the spec needs ≥ 99 % of the surface in it.
TEST(Aim, TimeToSpecRanksTheStrategiesThatMeetTheSpecByTimeThenTheOthersByShare) {
  AimParams p;
  p.aim = Aim::TimeToSpec;
  const std::vector<StrategyScore> s = {spec_score(1, 30, 0.995),  // meets, 30 min
                                        spec_score(2, 10, 0.80),   // fastest, misses (80 %)
                                        spec_score(3, 25, 0.990),  // meets exactly at 99 %, fastest of those that meet
                                        spec_score(4, 5, 0.40),    // misses more
                                        spec_score(5, 20, 1.0, 1.0, /*gouge*/ 0.05)};  // would win, but gouges
  const std::vector<std::size_t> order = rank_strategies(s, p);
  EXPECT_EQ(slots(s, order), (std::vector<int>{3, 1, 2, 4, 5}));
  EXPECT_TRUE(meets_spec(s[2], p));
  EXPECT_FALSE(meets_spec(s[1], p));
  // Regret against the best (slot 3, 25 min): 30 / 25 − 1 = 0.2; 10 / 25 − 1 = −0.6 for the faster
  // strategy that misses (faster, but not good enough).
  const std::vector<double> r = regrets(s, order, p);
  EXPECT_DOUBLE_EQ(r[2], 0.0);
  EXPECT_DOUBLE_EQ(r[0], 0.2);
  EXPECT_DOUBLE_EQ(r[1], -0.6);
  EXPECT_DOUBLE_EQ(r[4], 20.0 / 25 - 1);
}

TEST(Aim, TimeToSpecNearTiesGoToTheLowerRaP90) {
  AimParams p;
  p.aim = Aim::TimeToSpec;
  // 2 is 1.5 % slower than 1 (within 2 %) with a better p90; 3 is 3 % slower: a tie with neither.
  const std::vector<StrategyScore> s = {spec_score(1, 20.0, 1.0, 1.4), spec_score(2, 20.3, 1.0, 1.2),
                                        spec_score(3, 20.6, 1.0, 0.9)};
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{2, 1, 3}));
  p.near_tie_share = 0.05;  // all three tie: p90 decides
  EXPECT_EQ(slots(s, rank_strategies(s, p)), (std::vector<int>{3, 2, 1}));
}

TEST(Aim, NoRegretWhenNoStrategyMeetsTheSpec) {
  AimParams p;
  p.aim = Aim::TimeToSpec;
  const std::vector<StrategyScore> s = {spec_score(1, 20, 0.9), spec_score(2, 10, 0.95)};
  const std::vector<std::size_t> order = rank_strategies(s, p);
  EXPECT_EQ(slots(s, order), (std::vector<int>{2, 1}));  // the larger share in spec first
  for (double r : regrets(s, order, p)) EXPECT_TRUE(std::isnan(r));
  // Without a measured specification nothing meets it.
  EXPECT_FALSE(meets_spec(score(1, 1, 1, 1), p));
}

// The paper's quality aim read as Figures 9–10 do: the share of the surface within the Ra target
// (not machined counts as outside), shares within one point go to the faster strategy.
TEST(Aim, QualityWithAnRaTargetRanksByTheShareWithinItTiesToTheFaster) {
  std::vector<StrategyScore> s = {score(1, 0.5, 0.9, 30), score(2, 1.2, 1.4, 10), score(3, 0.1, 0.2, 5),
                                  score(4, 1.0, 1.1, 12)};
  s[0].ra_target_share = 0.960;  // best share
  s[1].ra_target_share = 0.955;  // within a point of 1, faster: first
  s[2].ra_target_share = 0.300;  // smoothest median (untouched floors elsewhere), but little within the target
  s[3].ra_target_share = 0.949;  // 1.1 points below 1: not a tie with 1's group
  EXPECT_EQ(slots(s, rank_strategies(s, {})), (std::vector<int>{2, 1, 4, 3}));
  s[2].ra_target_share = std::nan("");  // one without a share: the lexicographic median rule of before
  EXPECT_EQ(slots(s, rank_strategies(s, {})), (std::vector<int>{3, 1, 4, 2}));
}

// Issue 39: the network's outputs. Time to spec: the best 1, a strategy that meets the spec its
// best time / its time, one that misses it or gouges 0; a faster near-tie ranked after the best
// stays just below 1.
TEST(Aim, ScoresAreTheBestTimeOverEachTimeAndZeroForAMissOrAGouge) {
  AimParams p;
  p.aim = Aim::TimeToSpec;
  std::vector<StrategyScore> s = {score(1, 1, 1.0, 20), score(2, 1, 1.0, 9.9), score(3, 1, 1.0, 5),
                                  score(4, 1, 1.0, 8, /*gouge*/ 0.05), score(5, 1, 0.9, 10)};
  for (auto& x : s) x.spec_share = 1.0;
  s[2].spec_share = 0.9;  // 3 is fastest but misses the spec
  const std::vector<std::size_t> order = rank_strategies(s, p);
  ASSERT_EQ(slots(s, order).front(), 5);  // 2 and 5 within 2 %: the lower Ra p90
  const std::vector<double> sc = aim_scores(s, order, p);
  EXPECT_EQ(sc[4], 1.0);
  EXPECT_DOUBLE_EQ(sc[0], 10.0 / 20);
  EXPECT_EQ(sc[1], 1 - 1e-6);  // 9.9 min, faster than the best's 10 but ranked after it: just below 1
  EXPECT_EQ(sc[2], 0.0);
  EXPECT_EQ(sc[3], 0.0);
  // Nothing meets the spec: the shares in spec over the best share.
  for (auto& x : s) x.spec_share = 0.5;
  s[0].spec_share = 0.8;
  const std::vector<std::size_t> o2 = rank_strategies(s, p);
  const std::vector<double> sc2 = aim_scores(s, o2, p);
  EXPECT_EQ(sc2[0], 1.0);
  EXPECT_DOUBLE_EQ(sc2[1], 0.5 / 0.8);
  EXPECT_EQ(sc2[3], 0.0);  // gouges
  // Quality: one-hot on the best.
  p.aim = Aim::Quality;
  const std::vector<std::size_t> o3 = rank_strategies(s, p);
  const std::vector<double> sc3 = aim_scores(s, o3, p);
  EXPECT_EQ(std::count(sc3.begin(), sc3.end(), 1.0), 1);
  EXPECT_EQ(std::count(sc3.begin(), sc3.end(), 0.0), 4);
}
