// Cutting data against hand-computed values (issue 17).
#include "millnet/core/error.hpp"
#include "millnet/tooling/cutting.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace t = millnet::tooling;

namespace {

t::Tool em10() {
  t::Tool tool;
  tool.id = "em10";
  tool.type = t::ToolType::Flat;
  tool.diameter_mm = 10;
  tool.flutes = 3;
  tool.flute_length_mm = 22;
  tool.stickout_mm = 40;
  return tool;
}

t::Material al(double vc, double fz) {
  t::Material m;
  m.id = "aluminium-6061";
  m.ranges.push_back({t::ToolMaterial::Carbide, 6, 12.5, vc, fz, "test"});
  m.ranges.push_back({t::ToolMaterial::Carbide, 0.5, 6, vc, fz / 2, "test small"});
  return m;
}

t::MachineLimits big_machine() {
  t::MachineLimits m;
  m.max_rpm = 30000;
  m.max_feed_mm_min = 20000;
  return m;
}

}  // namespace

TEST(CuttingData, HandComputedEndMillInAluminium) {
  // n = 1000·300/(π·10) = 9549.3 → 9549 rpm; f = 0.05·3·9549 = 1432.35 → 1432 mm/min (whole mm/min).
  const auto c = t::cutting_data(em10(), al(300, 0.05), 5, big_machine(), {});
  EXPECT_DOUBLE_EQ(c.d_eff_mm, 10);
  EXPECT_NEAR(c.rpm_computed, 9549.297, 1e-3);
  EXPECT_EQ(c.rpm, 9549);
  EXPECT_DOUBLE_EQ(c.feed_mm_min, 1432);
  EXPECT_TRUE(c.rpm_limited_by.empty());
  EXPECT_FALSE(c.feed_limited);
  EXPECT_DOUBLE_EQ(c.feed_slot_mm_min, 1146);   // 0.8 · 1432 = 1145.6
  EXPECT_DOUBLE_EQ(c.feed_plunge_mm_min, 430);  // 0.3 · 1432 = 429.6
  EXPECT_DOUBLE_EQ(c.feed_ramp_mm_min, 716);
}

TEST(CuttingData, SpindleSpeedIsCappedByTheMachineAndTheToolAndTheFeedFollows) {
  t::MachineLimits m = big_machine();
  m.max_rpm = 8000;
  auto c = t::cutting_data(em10(), al(300, 0.05), 5, m, {});
  EXPECT_EQ(c.rpm, 8000);
  EXPECT_EQ(c.rpm_limited_by, "machine max rpm");
  EXPECT_DOUBLE_EQ(c.feed_mm_min, 0.05 * 3 * 8000);  // fz kept, the feed drops with n
  t::Tool tool = em10();
  tool.max_rpm = 6000;
  c = t::cutting_data(tool, al(300, 0.05), 5, m, {});
  EXPECT_EQ(c.rpm, 6000);
  EXPECT_EQ(c.rpm_limited_by, "tool max rpm");
}

TEST(CuttingData, FeedIsCappedAtTheMachinesMaxFeed) {
  t::MachineLimits m = big_machine();
  m.max_feed_mm_min = 1000;
  const auto c = t::cutting_data(em10(), al(300, 0.05), 5, m, {});
  EXPECT_DOUBLE_EQ(c.feed_mm_min, 1000);
  EXPECT_TRUE(c.feed_limited);
  EXPECT_DOUBLE_EQ(c.feed_max_mm_min, 1000);  // thinning cannot exceed the machine either
}

TEST(CuttingData, ChipThinningAtTenPercentEngagement) {
  // RCTF(0.1·D) = D / (2·√(0.1D·0.9D)) = 1 / (2·0.3) = 5/3.
  EXPECT_NEAR(t::chip_thinning_factor(10, 1), 5.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(t::chip_thinning_factor(10, 5), 1.0);
  EXPECT_DOUBLE_EQ(t::chip_thinning_factor(10, 8), 1.0);
  const auto c = t::cutting_data(em10(), al(300, 0.05), 5, big_machine(), {});
  EXPECT_NEAR(c.feed_at(10, 1), 1432 * 5.0 / 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.feed_at(10, 6), c.feed_mm_min);
  // Capped at max_chip_thinning (3): a_e = 0.1 mm would ask RCTF = 15.8.
  EXPECT_NEAR(c.feed_at(10, 0.1), 3 * 1432, 1e-9);
}

TEST(CuttingData, BallNoseEffectiveDiameterAtAShallowDepth) {
  t::Tool ball;
  ball.type = t::ToolType::Ball;
  ball.diameter_mm = 2;
  ball.corner_radius_mm = 1;
  // a_p 0.04 mm (the paper's a_a): D_eff = 2·√(0.04·1.96) = 0.56 mm.
  EXPECT_NEAR(t::effective_diameter(ball, 0.04), 0.56, 1e-12);
  EXPECT_DOUBLE_EQ(t::effective_diameter(ball, 1.0), 2.0);
  EXPECT_DOUBLE_EQ(t::effective_diameter(ball, 3.0), 2.0);
  t::Tool bull;
  bull.type = t::ToolType::Bull;
  bull.diameter_mm = 10;
  bull.corner_radius_mm = 1;
  // (10 − 2) + 2·√(0.5·1.5) = 8 + 1.7320508
  EXPECT_NEAR(t::effective_diameter(bull, 0.5), 8 + 2 * std::sqrt(0.75), 1e-12);
  EXPECT_DOUBLE_EQ(t::effective_diameter(em10(), 0.01), 10);
  // The speed follows D_eff: Vc 200 at D_eff 0.56 → 113,682 rpm, capped by the machine.
  const auto c = t::cutting_data(ball, al(200, 0.02), 0.04, big_machine(), {});
  EXPECT_NEAR(c.rpm_computed, 200000 / (std::numbers::pi * 0.56), 1e-6);
  EXPECT_EQ(c.rpm, 30000);
}

TEST(CuttingData, BadInputNamesWhatAndByHowMuch) {
  t::MachineLimits m = big_machine();
  m.min_rpm = 12000;
  try {
    (void)t::cutting_data(em10(), al(300, 0.05), 5, m, {});
    FAIL() << "a speed below the machine's minimum must be refused";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("below the machine's minimum 12000 rpm by 2451 rpm"), std::string::npos)
        << e.what();
  }
  t::Overrides ov;
  ov.rpm = 31000;
  try {
    (void)t::cutting_data(em10(), al(300, 0.05), 5, big_machine(), {}, ov);
    FAIL() << "an override above the machine's max must be refused";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the machine's max 30000 rpm by 1000 rpm"), std::string::npos)
        << e.what();
  }
  t::Tool hss = em10();
  hss.material = t::ToolMaterial::HSS;
  EXPECT_THROW((void)t::cutting_data(hss, al(300, 0.05), 5, big_machine(), {}), millnet::Error);
  t::Tool big = em10();
  big.diameter_mm = 20;
  EXPECT_THROW((void)t::cutting_data(big, al(300, 0.05), 5, big_machine(), {}), millnet::Error);
  t::Tool bad = em10();
  bad.flute_length_mm = 50;  // longer than its stick-out
  EXPECT_THROW(bad.check("tool"), millnet::Error);
}

TEST(CuttingData, OverridesReplaceTheTableFigures) {
  t::Overrides ov;
  ov.vc_m_min = 150;
  ov.fz_mm = 0.1;
  const auto c = t::cutting_data(em10(), al(300, 0.05), 5, big_machine(), {}, ov);
  EXPECT_EQ(c.rpm, std::round(150000 / (std::numbers::pi * 10)));
  EXPECT_DOUBLE_EQ(c.feed_mm_min, std::round(0.1 * 3 * c.rpm));
}

// Issue 40: where a tool sits on the machine — its number, length offset and holder — is checked
// like its geometry, and changes neither its label nor its cutter.
TEST(ToolCheck, NumberLengthOffsetHolderAndPointAngle) {
  t::Tool tool = em10();
  const std::string label = tool.label();
  tool.number = 7;
  tool.holder_diameter_mm = 24;
  tool.holder_length_mm = 60;
  EXPECT_NO_THROW(tool.check("tools.json"));
  EXPECT_EQ(tool.label(), label);
  EXPECT_EQ(tool.length_offset_register(), 7);  // H = T unless stated
  tool.length_offset = 17;
  EXPECT_EQ(tool.length_offset_register(), 17);
  auto message = [](const t::Tool& x) {
    try {
      x.check("tools.json");
    } catch (const millnet::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  t::Tool narrow = tool;
  narrow.holder_diameter_mm = 8;
  EXPECT_EQ(message(narrow), "tools.json em10: holder diameter 8 mm is narrower than the tool (10 mm)");
  t::Tool bad = tool;
  bad.number = -1;
  EXPECT_EQ(message(bad), "tools.json em10: tool number (T) -1 is outside [0, 99999]");
  bad = tool;
  bad.length_offset = 100000;
  EXPECT_EQ(message(bad), "tools.json em10: length offset (H) 100000 is outside [0, 99999]");
  bad = tool;
  bad.holder_length_mm = std::nan("");
  EXPECT_EQ(message(bad), "tools.json em10: holder length (mm) nan is outside [0, 10000]");
  t::Tool drill = tool;
  drill.type = t::ToolType::Drill;
  drill.point_angle_deg = 140;
  EXPECT_DOUBLE_EQ(drill.cutter().point_angle_deg, 140);
  EXPECT_NEAR(drill.cutter().point_height(), 5 / std::tan(70 * std::numbers::pi / 180), 1e-12);
  drill.point_angle_deg = 180;
  EXPECT_EQ(message(drill), "tools.json em10: point angle 180 deg must be in (0, 180)");
}
