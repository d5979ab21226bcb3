// tooling::Cutter, the one owner of a cutter's shape and checks (issue 36): profiles against hand
// values, the ranges every module relies on, and a tool library entry's cutter.
#include "millnet/tooling/cutter.hpp"
#include "millnet/tooling/cutting.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using millnet::tooling::Cutter;
using millnet::tooling::CutterType;

TEST(Cutter, ProfilesAreTheHandComputedHeights) {
  EXPECT_EQ(Cutter::ball(2).profile_height(0), 0);
  EXPECT_NEAR(Cutter::ball(2).profile_height(1), 1, 1e-15);
  EXPECT_NEAR(Cutter::ball(2).profile_height(0.6), 1 - 0.8, 1e-15);
  EXPECT_EQ(Cutter::flat(2).profile_height(1), 0);
  EXPECT_TRUE(std::isinf(Cutter::flat(2).profile_height(1.01)));
  EXPECT_EQ(Cutter::bull(4, 1).profile_height(1), 0);
  EXPECT_NEAR(Cutter::bull(4, 1).profile_height(2), 1, 1e-15);
  EXPECT_NEAR(Cutter::bull(4, 1).profile_height(1.6), 0.2, 1e-15);
  // A 90° drill point: the cone rises 1 mm per mm; a 118° one by 1 / tan 59°.
  EXPECT_NEAR(Cutter::drill(6, 90).profile_height(1.5), 1.5, 1e-12);
  EXPECT_NEAR(Cutter::drill(6, 90).point_height(), 3, 1e-12);
  EXPECT_NEAR(Cutter::drill(10).point_height(), 5 / std::tan(59 * M_PI / 180), 1e-12);
  EXPECT_EQ(Cutter::ball(2).point_height(), 0);
}

TEST(Cutter, ABullWhoseCornerIsItsRadiusIsABall) {
  const Cutter b = Cutter::bull(4, 2);
  EXPECT_NO_THROW(b.check());
  EXPECT_EQ(b.shape(), CutterType::Ball);
  EXPECT_EQ(b.profile_corner_radius(), 2);
  for (double d : {0.0, 0.5, 1.3, 1.99, 2.0}) EXPECT_EQ(b.profile_height(d), Cutter::ball(4).profile_height(d));
  EXPECT_EQ(Cutter::bull(4, 1).shape(), CutterType::Bull);
  EXPECT_EQ(b.describe(), "bull D4 r2");
}

TEST(Cutter, ChecksRefuseWhatNoModuleCanMachine) {
  EXPECT_THROW(Cutter::flat(0).check(), millnet::Error);
  EXPECT_THROW(Cutter::flat(-1).check(), millnet::Error);
  EXPECT_THROW(Cutter::ball(1e308).check(), millnet::Error);  // issue 42: ball:1e308 gave Ra 0
  EXPECT_THROW(Cutter::flat(1000.5).check(), millnet::Error);
  EXPECT_NO_THROW(Cutter::flat(1000).check());
  EXPECT_THROW(Cutter::bull(4, 0).check(), millnet::Error);
  EXPECT_THROW(Cutter::bull(4, 2.1).check(), millnet::Error);
  EXPECT_THROW((Cutter{CutterType::Ball, 2, 0.5}).check(), millnet::Error);
  EXPECT_THROW((Cutter{CutterType::Flat, 2, 0.5}).check(), millnet::Error);
  EXPECT_THROW(Cutter::ball(std::numeric_limits<double>::quiet_NaN()).check(), millnet::Error);
  EXPECT_THROW(Cutter::drill(5, 180).check(), millnet::Error);
  EXPECT_THROW(Cutter::drill(5, 0).check(), millnet::Error);
  Cutter c = Cutter::ball(2);
  c.flute_length_mm = -1;
  EXPECT_THROW(c.check(), millnet::Error);
  try {
    Cutter::bull(4, 2.1).check();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("0 < corner radius <= diameter/2 = 2, got 2.1"), std::string::npos)
        << e.what();
  }
}

TEST(Cutter, DescriptionsNameTypeAndSize) {
  EXPECT_EQ(Cutter::ball(2).describe(), "ball D2");
  EXPECT_EQ(Cutter::flat(10).describe(), "flat D10");
  EXPECT_EQ(Cutter::bull(6, 1).describe(), "bull D6 r1");
  EXPECT_EQ(Cutter::drill(8.5).describe(), "drill D8.5");
}

TEST(Cutter, ALibraryToolGivesItsShapeFluteLengthAndReach) {
  millnet::tooling::Tool t;
  t.id = "br10r1";
  t.type = CutterType::Bull;
  t.diameter_mm = 10;
  t.corner_radius_mm = 1;
  t.flute_length_mm = 22;
  t.stickout_mm = 40;
  const Cutter c = t.cutter();
  EXPECT_EQ(c.type, CutterType::Bull);
  EXPECT_EQ(c.corner_radius, 1);
  EXPECT_EQ(c.flute_length_mm, 22);
  EXPECT_EQ(c.reach_mm, 40);
  // issue 42: a library "flat" tool with corner radius 2 was accepted
  t.type = CutterType::Flat;
  t.corner_radius_mm = 2;
  EXPECT_THROW(t.check("tools.json"), millnet::Error);
}
