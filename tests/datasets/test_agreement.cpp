// datasets::label_agreement: per recipe label, parts, agreeing parts and the simulated bests (by hand).
#include "millnet/datasets/agreement.hpp"

#include <gtest/gtest.h>

using namespace millnet::datasets;

TEST(Agreement, CountsPerLabelAscendingAndSkipsUnlabelledParts) {
  const std::vector<LabelledBest> parts{{2, 2}, {1, 3}, {2, 5}, {0, 4}, {1, 1}, {2, 2}};
  const std::vector<LabelAgreement> a = label_agreement(parts);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].label, 1);
  EXPECT_EQ(a[0].parts, 2);
  EXPECT_EQ(a[0].agree, 1);
  EXPECT_EQ(a[0].simulated_best, (std::map<int, int>{{1, 1}, {3, 1}}));
  EXPECT_EQ(a[1].label, 2);
  EXPECT_EQ(a[1].parts, 3);
  EXPECT_EQ(a[1].agree, 2);
  EXPECT_EQ(a[1].simulated_best, (std::map<int, int>{{2, 2}, {5, 1}}));
}

TEST(Agreement, NoLabelledPartsGiveNothing) {
  EXPECT_TRUE(label_agreement({}).empty());
  EXPECT_TRUE(label_agreement({{0, 3}, {-1, 2}}).empty());
}
