// Issue 42 §5 and §10: what LinuxCNC's interpreter refuses, the travel bound, quoted bytes in
// messages, and the work a program read from outside costs its users (gcode/bounds.hpp).
#include "millnet/core/error.hpp"
#include "millnet/gcode/bounds.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/gcode/writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace millnet::gcode;

namespace {

std::string error_of(std::string_view text) {
  try {
    (void)read(text, "hostile.nc");
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "no error";
}

/// A program moving to (x0, 0), then one arc G2/G3 to (x1, y1) about the centre offset (i, j).
std::string arc(const std::string& units, double x0, const std::string& to_and_centre, const std::string& g = "G2") {
  return units + " G90\nG0 X" + std::to_string(x0) + " Y0 Z1\nG1 Z-1 F100\n" + g + " " + to_and_centre + "\nM30\n";
}

bool one_printable_line(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7F; });
}

}  // namespace

// LinuxCNC (interp_arc.cc): the radii to start and end may differ by 0.02828 mm, or by up to
// 2.828 mm when that is within 0.1 % of the radius.
TEST(GcodeReaderBounds, ArcEndOffItsCircleIsRefusedByLinuxCncsRule) {
  // Start radius 5, end radius 20 (the case had 0.001 and 20: a zero-radius arc, below).
  const std::string e = error_of(arc("G21", 5, "X20 Y0 I-5 J0"));
  EXPECT_NE(e.find("hostile.nc:4: the arc's end is not on its circle: radius 5 mm at the start, 20 mm at the end"),
            std::string::npos)
      << e;
  // Radius 10 → 10.028: within 0.02828 mm.
  EXPECT_EQ(error_of(arc("G21", 10, "X0 Y10.028 I-10 J0", "G3")), "no error");
  // Radius 10 → 10.029: 0.029 mm and 0.29 %.
  EXPECT_NE(error_of(arc("G21", 10, "X0 Y10.029 I-10 J0", "G3")).find("not on its circle"), std::string::npos);
  // Radius 1000 → 1000.5: 0.5 mm is 0.05 % of the radius, below 2.828 mm.
  EXPECT_EQ(error_of(arc("G21", 1000, "X0 Y1000.5 I-1000 J0", "G3")), "no error");
  // Radius 10000 → 10003: 0.03 % but 3 mm > 2.828 mm.
  EXPECT_NE(error_of(arc("G21", 10000, "X0 Y10003 I-10000 J0", "G3")).find("not on its circle"), std::string::npos);
  // Inch: the tolerance is 0.002828 in (0.0718 mm): radius 1 in → 1.0025 in passes, 1.003 does not.
  EXPECT_EQ(error_of(arc("G20", 1, "X0 Y1.0025 I-1 J0", "G3")), "no error");
  EXPECT_NE(error_of(arc("G20", 1, "X0 Y1.003 I-1 J0", "G3")).find("in at the end"), std::string::npos);
}

TEST(GcodeReaderBounds, ZeroRadiusArcIsRefused) {
  // The arc: start radius 0.001 mm, end radius 20 mm.
  const std::string e = error_of(arc("G21", 0.001, "X20 Y0 I-0.001 J0"));
  EXPECT_NE(
      e.find("hostile.nc:4: zero-radius arc: radius 0.001 mm at the start, 20 mm at the end (at least 0.00127 mm)"),
      std::string::npos)
      << e;
  EXPECT_EQ(error_of(arc("G21", 0.002, "X-0.002 Y0 I-0.002 J0")), "no error");
}

TEST(GcodeReaderBounds, OneCodePerModalGroupAndLine) {
  EXPECT_NE(
      error_of("G0 G1 X5 F100\n").find("hostile.nc:1: two G-codes of one modal group on the line: G0 and G1 (motion)"),
      std::string::npos);
  EXPECT_NE(error_of("G90 G91\n").find("G90 and G91 (distance mode)"), std::string::npos);
  EXPECT_NE(error_of("G21 G21\n").find("(units)"), std::string::npos);
  EXPECT_NE(error_of("M3 M5 S100\n").find("two M-codes of one modal group on the line: M3 and M5 (spindle)"),
            std::string::npos);
  EXPECT_NE(error_of("M0 M30\n").find("(stopping)"), std::string::npos);
  // Codes of different groups together, as millnet writes them.
  EXPECT_EQ(error_of("G21 G90 G17 G94\nT1 M6\nM3 S1000\nG0 X0 Y0 Z5\nM5 M30\n"), "no error");
}

TEST(GcodeReaderBounds, NestedCommentIsNamedAsSuch) {
  const std::string e = error_of("G21 G90 (outer (inner) text)\n");
  EXPECT_NE(e.find("hostile.nc:1: nested comment: a '(' at column 16 inside the comment opened at column 9"),
            std::string::npos)
      << e;
}

TEST(GcodeReaderBounds, PositionsAndCentresStayWithinTheTravelBound) {
  EXPECT_EQ(error_of("G0 X100000 Y-100000 Z1\n"), "no error");
  EXPECT_NE(error_of("G0 X100000.001\n").find("hostile.nc:1: X 100000.001 mm is beyond the travel bound ±100000 mm"),
            std::string::npos);
  // 308 digits: a finite double far beyond any machine.
  EXPECT_NE(error_of("G0 X1" + std::string(307, '0') + "\n").find("X 1e+307 mm is beyond"), std::string::npos);
  // G20: 4000 in = 101,600 mm.
  EXPECT_NE(error_of("G20\nG0 Y4000\n").find("hostile.nc:2: Y 101600 mm"), std::string::npos);
  // G91 adds up past the bound on the fourth move.
  const std::string g91 = error_of("G91\nG0 X30000\nG0 X30000\nG0 X30000\nG0 X30000\n");
  EXPECT_NE(g91.find("hostile.nc:5: X 120000 mm is beyond the travel bound ±100000 mm (G91: the sum"),
            std::string::npos)
      << g91;
  // An arc of radius 1e13 (its chords overflowed size_t) and one of 1e12 (3.1 GB).
  EXPECT_NE(
      error_of(arc("G21", 0, "X1 Y0 I0 J10000000000000 Z-1.1")).find("hostile.nc:4: arc centre Y 1e+13 mm is beyond"),
      std::string::npos);
  EXPECT_NE(error_of(arc("G21", 0, "X1 Y0 R1000000000000")).find("arc centre"), std::string::npos);
  EXPECT_NE(error_of("T100000 M6\n").find("tool number T100000 out of range (0 to 99999)"), std::string::npos);
}

TEST(GcodeReaderBounds, MessagesQuoteAtMost40CharactersAndNoControlBytes) {
  const std::string nul = error_of(std::string("G1 \0X5 F100\n", 12));
  EXPECT_EQ(nul, "hostile.nc:1: unsupported character '\\x00'");
  const std::string after = error_of(std::string("G1 X\x01 F100\n", 11));
  EXPECT_EQ(after, "hostile.nc:1: word X has no valid number (followed by '\\x01')");
  const std::string digits = error_of("G1 X" + std::string(2000, '1') + " F100\n");
  EXPECT_NE(digits.find("hostile.nc:1: word X" + std::string(39, '1') + "… (2001 characters): the number does not fit"),
            std::string::npos)
      << digits;
  EXPECT_LT(digits.size(), 140u);
  const std::string open = error_of("G1 (a comment never closed \x1b[31m" + std::string(100, 'x') + "\n");
  EXPECT_NE(open.find("comment not closed: (a comment never closed \\x1B[31mxxx"), std::string::npos) << open;
  for (const std::string& m : {nul, after, digits, open}) EXPECT_TRUE(one_printable_line(m)) << m;
}

// The estimate counts what stats() makes: its blocks for the same program (the oracle).
TEST(GcodeReaderBounds, TimingChordsEqualTheMotionModelsBlocks) {
  const std::string text =
      "G21 G90\nG0 X10 Y0 Z1\nG1 Z0 F500\nG3 X10 Y0 I-10 J0\nG2 X0 Y10 I-10 J0 Z-1\nG3 X-1 Y11 R1\n"
      "G2 X50 Y11 I25.5 J0\nG1 X0 Y0\nG3 X0.5 Y0.5 I0.25 J0.25\n";
  const Program p = read(text, "arcs.nc");
  const auto work = program_work(p, "arcs.nc");
  ASSERT_EQ(work.size(), 3u);
  EXPECT_EQ(work[0].unit, "planner blocks");
  EXPECT_EQ(work[0].count, static_cast<double>(stats(p, MotionModel{}).blocks));
  EXPECT_GT(work[0].count, 400);
}

TEST(GcodeReaderBounds, SimulatorAndPreviewCountsByHand) {
  // One helical turn of radius 5 (its Z drops): chords of sagitta 1e-4 mm span
  // 2·acos(1 − 1e-4/5) = 0.0126492 rad, so ⌈2π / 0.0126492⌉ = 497; plus the two lines before it.
  const Program p = read("G21 G90\nG0 X15 Y10 Z1\nG1 Z0 F300\nG2 X15 Y10 I-5 J0 Z-0.5\n", "helix.nc");
  const auto work = program_work(p, "helix.nc");
  EXPECT_EQ(work[1].unit, "swept primitives");
  EXPECT_EQ(work[1].count, 2 + 497);
  EXPECT_EQ(work[2].unit, "path points");
  EXPECT_EQ(work[2].count, 2 + 60);  // 6° steps
  // A planar arc is swept whole: one primitive.
  EXPECT_EQ(program_work(read("G0 X15 Y10 Z1\nG1 Z0 F300\nG2 X15 Y10 I-5 J0\n", "flat.nc"), "flat.nc")[1].count, 3);
}

TEST(GcodeReaderBounds, ReadCheckedRefusesNoMotionAndWorkBeyondTheLimit) {
  try {
    (void)read_checked("(nothing)\nM3 S1000\nM30\n", "empty.nc", millnet::WorkLimits{});
    ADD_FAILURE() << "an empty program was accepted";
  } catch (const millnet::Error& e) {
    EXPECT_STREQ(e.what(), "empty.nc: no motion (no G0, G1, G2 or G3 move): nothing to simulate");
  }
  std::string helix = "G21 G90\nG0 X15 Y10 Z1\nG1 Z0 F300\n";
  for (int k = 1; k <= 10; ++k) helix += "G2 X15 Y10 I-5 J0 Z-" + std::to_string(0.01 * k) + "\n";
  millnet::WorkLimits small;
  small.max_work = 4000;
  try {
    (void)read_checked(helix, "helix.nc", small);
    ADD_FAILURE() << "4,972 primitives passed a limit of 4,000";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("helix.nc: its moves, helices in chords of 0.0001 mm for the z-map simulator "
                                         "makes 5.0e3 swept primitives"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("the limit is 4.0e3 (--max-work, /limits/max_work)"), std::string::npos);
  }
  ProgramUse view;
  view.simulate = false;
  EXPECT_NO_THROW((void)read_checked(helix, "helix.nc", small, view));  // 602 preview points
}

// Programs millnet writes read back as before: arcs of every size the planners make, in mm and inch.
TEST(GcodeReaderBounds, MillnetsOwnProgramsReadBackUnchanged) {
  Program p;
  p.header = {"part"};
  auto add = [&](Motion m, Point3 to, std::array<double, 2> c = {0, 0}) {
    Move mv;
    mv.motion = m;
    mv.to = to;
    mv.center = c;
    mv.feed = m == Motion::Rapid ? 0 : 800;
    p.items.push_back(mv);
  };
  add(Motion::Rapid, {0, 0, 5});
  add(Motion::Line, {0, 0, -1});
  add(Motion::ArcCCW, {2, 2, -1}, {1, 1});
  add(Motion::ArcCW, {99000, 2, -1}, {49501, 2});
  add(Motion::ArcCCW, {99000, 2.0001, -1.5}, {99000, 1.00005});
  for (const Dialect& d : {linuxcnc(4), grbl(3)}) {
    const std::string text = write(p, d);
    const Program back = read(text, "own.nc");
    EXPECT_EQ(write(back, d), text);
  }
}
