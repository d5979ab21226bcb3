// gcode::read on hand-written text: modes, units, arcs by I J and by R, comments, errors.
#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace millnet::gcode;

namespace {
const Move& move_at(const Program& p, std::size_t k) { return std::get<Move>(p.items.at(k)); }
std::string error_of(std::string_view text) {
  try {
    (void)read(text, "hand.nc");
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(GcodeReader, HandWrittenProgram) {
  const std::string text =
      "%\n"
      "(my part)\n"
      "; second header line\n"
      "\n"
      "N10 g21 g90 g17 g94\n"
      "N20 T3 M6 (ball 2)\n"
      "N30 G0 Z5\n"
      "N40 X10 Y0 ; go\n"
      "N50 M3 S18000\n"
      "N60 G01 Z-1 F100\n"
      "N70 X20\n"
      "N80 G3 X20 Y10 I0 J5 F300\n"
      "N90 G2 X10 Y10 R5\n"
      "N100 G91 G1 X-5 Y-5\n"
      "N110 G90 G20 G0 Z0.5\n"
      "N120 M1\n"
      "N130 M5 M30\n"
      "G1 X99 (after the end: not read)\n";
  const Program p = read(text, "hand.nc");
  EXPECT_EQ(p.header, (std::vector<std::string>{"my part", "second header line"}));
  ASSERT_EQ(p.items.size(), 13u);
  ASSERT_EQ(p.source_line.size(), p.items.size());
  const auto& tc = std::get<ToolChange>(p.items[0]);
  EXPECT_EQ(tc.number, 3);
  EXPECT_EQ(tc.description, "ball 2");
  EXPECT_EQ(p.source_line[0], 6u);
  EXPECT_EQ(move_at(p, 1).axes, kZ);
  EXPECT_EQ(move_at(p, 1).to, (Point3{0, 0, 5}));
  EXPECT_EQ(std::get<Comment>(p.items[2]).text, "go");
  EXPECT_EQ(move_at(p, 3).to, (Point3{10, 0, 5}));
  EXPECT_EQ(move_at(p, 3).axes, kXYZ);
  EXPECT_EQ(p.source_line[3], 8u);
  const auto& sp = std::get<Spindle>(p.items[4]);
  EXPECT_EQ(sp.dir, SpindleDir::CW);
  EXPECT_EQ(sp.rpm, 18000);
  EXPECT_EQ(move_at(p, 5).motion, Motion::Line);
  EXPECT_EQ(move_at(p, 5).feed, 100);
  EXPECT_EQ(move_at(p, 6).to, (Point3{20, 0, -1}));  // modal G1, modal F
  EXPECT_EQ(move_at(p, 6).feed, 100);
  const Move& a = move_at(p, 7);
  EXPECT_EQ(a.motion, Motion::ArcCCW);
  EXPECT_EQ(a.center, (std::array<double, 2>{20, 5}));
  EXPECT_EQ(a.feed, 300);
  const Move& r = move_at(p, 8);  // R 5 over a chord of 10: the centre is the chord's midpoint
  EXPECT_EQ(r.motion, Motion::ArcCW);
  EXPECT_NEAR(r.center[0], 15, 1e-12);
  EXPECT_NEAR(r.center[1], 10, 1e-12);
  EXPECT_EQ(move_at(p, 9).to, (Point3{5, 5, -1}));  // G91
  EXPECT_NEAR(move_at(p, 10).to[2], 12.7, 1e-12);   // G20: inches
  EXPECT_EQ(move_at(p, 10).motion, Motion::Rapid);
  EXPECT_TRUE(std::get<Pause>(p.items[11]).optional);
  EXPECT_EQ(std::get<Spindle>(p.items[12]).dir, SpindleDir::Off);
  EXPECT_EQ(p.source_line[12], 17u);
}

TEST(GcodeReader, ArcByRadiusPicksTheShortOrTheLongArc) {
  // From (0,0) to (10,0) with |R| = 10: the centre lies 8.660 off the chord.
  const double h = std::sqrt(100.0 - 25.0);
  const Program ccw_short = read("G0 X0 Y0 Z0\nG3 X10 Y0 R10 F100\n", "r");
  EXPECT_NEAR(std::get<Move>(ccw_short.items[1]).center[1], h, 1e-12);  // left of +X
  const Program ccw_long = read("G0 X0 Y0 Z0\nG3 X10 Y0 R-10 F100\n", "r");
  EXPECT_NEAR(std::get<Move>(ccw_long.items[1]).center[1], -h, 1e-12);
  const Program cw_short = read("G0 X0 Y0 Z0\nG2 X10 Y0 R10 F100\n", "r");
  EXPECT_NEAR(std::get<Move>(cw_short.items[1]).center[1], -h, 1e-12);
  EXPECT_NE(error_of("G0 X0 Y0\nG2 X10 Y0 R4 F100\n").find("hand.nc:2"), std::string::npos);
}

TEST(GcodeReader, InchFeedsAndIncrementalArcs) {
  const Program p = read("G20 G0 X1 Y0 Z0\nG91 G2 X1 Y1 I0 J1 F10\n", "in");
  const Move& m = std::get<Move>(p.items[1]);
  EXPECT_NEAR(m.to[0], 50.8, 1e-12);
  EXPECT_NEAR(m.to[1], 25.4, 1e-12);
  EXPECT_NEAR(m.center[0], 25.4, 1e-12);
  EXPECT_NEAR(m.center[1], 25.4, 1e-12);
  EXPECT_NEAR(m.feed, 254, 1e-12);
}

TEST(GcodeReader, ErrorsNameTheSourceLineAndTheWord) {
  const std::string e1 = error_of("G21\nG0 Z5\nG55 X1\n");
  EXPECT_NE(e1.find("hand.nc:3"), std::string::npos) << e1;
  EXPECT_NE(e1.find("G55"), std::string::npos) << e1;
  const std::string e2 = error_of("(x)\nM7\n");
  EXPECT_NE(e2.find("hand.nc:2"), std::string::npos) << e2;
  EXPECT_NE(e2.find("M7"), std::string::npos) << e2;
  const std::string e3 = error_of("G0 Z1\nG1 X5\n");
  EXPECT_NE(e3.find("hand.nc:2"), std::string::npos) << e3;
  EXPECT_NE(e3.find("feed"), std::string::npos) << e3;
  EXPECT_NE(error_of("G0 X1 A3\n").find("A3"), std::string::npos);
  EXPECT_NE(error_of("G0 X1 X2\n").find("repeated"), std::string::npos);
  EXPECT_NE(error_of("G0 X1 (open\n").find("hand.nc:1"), std::string::npos);
  EXPECT_NE(error_of("X1\n").find("motion"), std::string::npos);
  EXPECT_NE(error_of("G0 Z1\nG2 X1 Y1 I1 F100\n").find("unknown XY"), std::string::npos);
  EXPECT_NE(error_of("M6\n").find("T word"), std::string::npos);
  EXPECT_NE(error_of("G0 X1.2.3\n").find("X1.2.3"), std::string::npos);
  EXPECT_EQ(error_of("G0 X1\nG92 X0\n").find("hand.nc:2: unsupported word G92"), 0u);
}
