// gcode::stats against hand-computed lengths and times (a = 100 mm/s², feed 600 mm/min = 10 mm/s).
#include "millnet/core/error.hpp"
#include "millnet/gcode/stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace millnet::gcode;

namespace {
constexpr double kA = 100;       // mm/s²
constexpr double kF = 600;       // mm/min
constexpr double kDelta = 0.01;  // mm
MotionModel model() { return {6000, 3000, kA, kDelta}; }
Move to(Motion m, Point3 p, double feed = kF) {
  Move x;
  x.motion = m;
  x.to = p;
  x.feed = m == Motion::Rapid ? 0 : feed;
  return x;
}
/// Starts at the origin (the first rapid moves nowhere: its start is unknown), then the lines.
Program lines(std::initializer_list<Point3> pts) {
  Program p;
  p.items.emplace_back(to(Motion::Rapid, {0, 0, 0}));
  for (const Point3& q : pts) p.items.emplace_back(to(Motion::Line, q));
  return p;
}
double seconds(const ProgramStats& s) { return s.kinematic_time_min * 60; }
}  // namespace

TEST(GcodeStats, ShortLineIsATriangle) {
  // 0.5 mm: reaching 10 mm/s takes v²/2a = 0.5 mm, so the speed peaks at √(a·L) = √50 and falls back.
  const ProgramStats s = stats(lines({{0.5, 0, 0}}), model());
  EXPECT_NEAR(seconds(s), 2 * std::sqrt(50.0) / kA, 1e-12);  // 0.141421 s
  EXPECT_NEAR(s.feed_time_min * 60, 0.05, 1e-12);
  EXPECT_EQ(s.blocks, 1u);
}

TEST(GcodeStats, LongLineIsATrapezoid) {
  // 10 mm: 0.1 s up (0.5 mm), 9 mm at 10 mm/s (0.9 s), 0.1 s down.
  const ProgramStats s = stats(lines({{10, 0, 0}}), model());
  EXPECT_NEAR(seconds(s), 1.1, 1e-12);
  EXPECT_NEAR(s.cut_length_mm, 10, 1e-12);
  EXPECT_NEAR(s.feed_time_min, 10.0 / kF, 1e-12);
}

TEST(GcodeStats, CollinearLinesDoNotSlowDown) {
  const ProgramStats s = stats(lines({{3, 4, 0}, {6, 8, 0}}), model());
  EXPECT_NEAR(seconds(s), 1.1, 1e-9);
  EXPECT_EQ(s.blocks, 2u);
}

TEST(GcodeStats, RightAngleCornerAtTheJunctionDeviationSpeed) {
  // θ = 90°: sin(θ/2) = √2/2, v² = a·δ·s/(1−s) = 1 · 2.414214 → v = 1.553774 mm/s at the corner.
  const double s2 = std::sqrt(0.5);
  const double vj = std::sqrt(kA * kDelta * s2 / (1 - s2));
  EXPECT_NEAR(vj, 1.5537740, 1e-6);
  EXPECT_NEAR(junction_speed({1, 0, 0}, {0, 1, 0}, kA, kDelta), vj, 1e-12);
  // Each 10 mm leg: 0.1 s up from (or down to) rest, (10 − vj)/a at the corner end, the rest cruising.
  const double leg = 0.1 + (10 - vj) / kA + (10 - 0.5 - (100 - vj * vj) / (2 * kA)) / 10;
  EXPECT_NEAR(leg, 1.0856694, 1e-6);
  const ProgramStats s = stats(lines({{10, 0, 0}, {10, 10, 0}}), model());
  EXPECT_NEAR(seconds(s), 2 * leg, 1e-12);  // 2.171339 s
}

TEST(GcodeStats, ReversalStops) {
  EXPECT_EQ(junction_speed({1, 0, 0}, {-1, 0, 0}, kA, kDelta), 0.0);
  const ProgramStats s = stats(lines({{10, 0, 0}, {0, 0, 0}}), model());
  EXPECT_NEAR(seconds(s), 2.2, 1e-12);
}

TEST(GcodeStats, FeedTimeIsLengthOverFeedAndRapidsAtTheRapidRate) {
  Program p = lines({{10, 0, 0}});
  p.items.emplace_back(to(Motion::Line, {10, 0, -2}, 100));   // 2 mm plunge at 100 mm/min
  p.items.emplace_back(to(Motion::Rapid, {10, 0, 10}));       // 12 mm at 6000 mm/min
  p.items.emplace_back(to(Motion::Line, {20, 0, 10}, 9000));  // capped at max_feed 3000
  const ProgramStats s = stats(p, model());
  EXPECT_NEAR(s.cut_length_mm, 22, 1e-12);
  EXPECT_NEAR(s.rapid_length_mm, 12, 1e-12);
  EXPECT_NEAR(s.plunge_length_mm, 2, 1e-12);
  EXPECT_NEAR(s.feed_time_min, 10.0 / 600 + 2.0 / 100 + 12.0 / 6000 + 10.0 / 3000, 1e-12);
  EXPECT_GT(s.kinematic_time_min, s.feed_time_min);
}

TEST(GcodeStats, ArcLengthAndChords) {
  // A CCW half circle of radius 10 from (10,0) to (−10,0): length 10π; chords within the tolerance.
  Program p;
  p.items.emplace_back(to(Motion::Rapid, {10, 0, 0}));
  Move a = to(Motion::ArcCCW, {-10, 0, 0});
  a.center = {0, 0};
  p.items.emplace_back(a);
  const ProgramStats s = stats(p, model());
  EXPECT_NEAR(s.cut_length_mm, 10 * std::numbers::pi, 1e-12);
  const double phi = 2 * std::acos(1 - kArcChordToleranceMm / 10);
  EXPECT_EQ(s.blocks, static_cast<std::size_t>(std::ceil(std::numbers::pi / phi)));
  // Chord joints are nearly straight: close to one 10π-long trapezoid (chords are a bit shorter).
  EXPECT_NEAR(seconds(s), 10 * std::numbers::pi / 10 + 0.1, 0.01);
}

TEST(GcodeStats, PausesAndSpindleChangesStopTheMachine) {
  Program p = lines({{5, 0, 0}});
  p.items.emplace_back(Spindle{SpindleDir::Off, 0});
  p.items.emplace_back(to(Motion::Line, {10, 0, 0}));
  // two 5 mm trapezoids from rest to rest: 0.1 + 0.4 + 0.1 each
  EXPECT_NEAR(seconds(stats(p, model())), 1.2, 1e-12);
  p.items.insert(p.items.begin() + 2, Comment{"comments do not stop"});
  p.items.erase(p.items.begin() + 3);
  EXPECT_NEAR(seconds(stats(p, model())), 1.1, 1e-12);
}

TEST(GcodeStats, UnknownStartIsNotCounted) {
  Program p;
  Move z = to(Motion::Rapid, {0, 0, 5});
  z.axes = kZ;
  p.items.emplace_back(z);
  p.items.emplace_back(to(Motion::Rapid, {3, 4, 5}));  // from an unknown XY: not counted
  p.items.emplace_back(to(Motion::Rapid, {6, 8, 5}));
  EXPECT_NEAR(stats(p, model()).rapid_length_mm, 5, 1e-12);
}

TEST(GcodeStats, BadModelThrows) {
  MotionModel m = model();
  m.acceleration_mm_s2 = 0;
  EXPECT_THROW((void)stats(Program{}, m), millnet::Error);
  m = model();
  m.junction_deviation_mm = -1;
  EXPECT_THROW((void)stats(Program{}, m), millnet::Error);
}
