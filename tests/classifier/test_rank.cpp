// classifier::rank: the per-part aggregation over variants, against hand-computed figures.
#include "millnet/classifier/rank.hpp"
#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

namespace {

using millnet::classifier::Prediction;
using millnet::classifier::rank;

Prediction three_variants() {
  Prediction p;
  p.probabilities.resize(3, 3);
  p.probabilities << 0.6, 0.3, 0.1,  // top 1
      0.2, 0.5, 0.3,                 // top 2
      0.5, 0.4, 0.1;                 // top 1
  p.d2_min.resize(3);
  p.d2_min << 4.0, 1.5, 9.0;
  p.unfamiliar = {true, false, true};
  return p;
}

TEST(Rank, TotalsMeansSharesAndTopAreTheHandComputedOnes) {
  const auto r = rank(three_variants());
  ASSERT_EQ(r.totals.size(), 3u);
  EXPECT_NEAR(r.totals[0], 1.3, 1e-15);
  EXPECT_NEAR(r.totals[1], 1.2, 1e-15);
  EXPECT_NEAR(r.totals[2], 0.5, 1e-15);
  EXPECT_NEAR(r.mean[0], 1.3 / 3, 1e-15);
  EXPECT_EQ(r.top, 1);
  EXPECT_DOUBLE_EQ(r.confidence, r.mean[0]);
  EXPECT_EQ(r.variant_top, (std::vector<int>{1, 2, 1}));
  EXPECT_DOUBLE_EQ(r.consistency, 2.0 / 3);
  EXPECT_NEAR(r.first_share[0], 2.0 / 3, 1e-15);
  EXPECT_NEAR(r.first_share[1], 1.0 / 3, 1e-15);
  EXPECT_EQ(r.first_share[2], 0.0);
  EXPECT_EQ(r.order, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_DOUBLE_EQ(r.d2_min, 1.5);
}

TEST(Rank, UnfamiliarIsAStrictMajorityVote) {
  Prediction p = three_variants();
  EXPECT_TRUE(rank(p).unfamiliar);  // 2 of 3
  EXPECT_EQ(rank(p).unfamiliar_variants, 2u);
  p.unfamiliar = {true, false, false};
  EXPECT_FALSE(rank(p).unfamiliar);  // 1 of 3
  p.probabilities.conservativeResize(2, 3);
  p.d2_min.conservativeResize(2);
  p.unfamiliar = {true, false};
  EXPECT_FALSE(rank(p).unfamiliar);  // a tie is not a majority
}

TEST(Rank, TiesKeepTheFirstSlotAndANoVariantPredictionThrows) {
  Prediction p;
  p.probabilities.resize(1, 3);
  p.probabilities << 0.4, 0.4, 0.2;
  p.d2_min.resize(1);
  p.d2_min << 0.0;
  p.unfamiliar = {false};
  const auto r = rank(p);
  EXPECT_EQ(r.top, 1);
  EXPECT_EQ(r.order, (std::vector<std::size_t>{0, 1, 2}));
  Prediction empty;
  empty.probabilities.resize(0, 3);
  EXPECT_THROW((void)rank(empty), millnet::Error);
}

}  // namespace

TEST(Rank, SlotRanksOrderTheSlotsByTotalsHighestFirst) {
  using millnet::classifier::slot_ranks;
  // totals of slots 1..3: 0.2, 0.9, 0.5 ⇒ slot 2 first, slot 3 second, slot 1 third.
  EXPECT_EQ(slot_ranks({0.2, 0.9, 0.5}, {1, 2, 3}), (std::vector<int>{3, 1, 2}));
  // Ties keep the order of `slots`; a slot beyond the totals counts as 0.
  EXPECT_EQ(slot_ranks({0.5, 0.5, 0.1}, {2, 1, 3, 7}), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(slot_ranks({0.1, 0.0}, {5, 2, 1}), (std::vector<int>{2, 3, 1}));
  EXPECT_TRUE(slot_ranks({1.0}, {}).empty());
}
