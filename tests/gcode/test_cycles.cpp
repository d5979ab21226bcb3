// Drilling cycles (gcode/cycles.hpp): G81 / G83 read as the moves LinuxCNC makes of them (hand-
// computed, and against rs274's own canonical moves), written back as cycle blocks on LinuxCNC and
// Fanuc and as plain moves on GRBL (which has no canned cycles), the same moves whichever; what
// LinuxCNC refuses is refused with one line.
#include "millnet/core/error.hpp"
#include "millnet/gcode/cycles.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"
#include "testing/grbl_check.hpp"
#include "testing/linuxcnc.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace millnet::gcode;

namespace {

std::vector<Move> moves_of(const Program& p) {
  std::vector<Move> out;
  for (const Item& it : p.items)
    if (const auto* m = std::get_if<Move>(&it)) out.push_back(*m);
  return out;
}

std::string error_of(std::string_view text) {
  try {
    (void)read(text, "drill.nc");
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "no error";
}

/// rs274's canonical straight moves of a program (STRAIGHT_TRAVERSE / STRAIGHT_FEED x, y, z), the
/// zero-length ones left out (LinuxCNC makes an XY traverse to where the tool already is).
std::vector<std::array<double, 4>> linuxcnc_moves(const std::string& text) {
  const std::filesystem::path nc = std::filesystem::temp_directory_path() / "millnet_cycles_test.nc";
  std::ofstream(nc) << text;
  const std::string cmd = "/usr/bin/rs274 -g '" + nc.string() + "' </dev/null 2>/dev/null";
  std::vector<std::array<double, 4>> out;
  FILE* f = popen(cmd.c_str(), "r");
  if (f == nullptr) return out;
  char buf[512];
  std::array<double, 3> at{NAN, NAN, NAN};
  while (std::fgets(buf, sizeof buf, f) != nullptr) {
    const std::string s(buf);
    const bool feed = s.find("STRAIGHT_FEED(") != std::string::npos;
    const bool rapid = s.find("STRAIGHT_TRAVERSE(") != std::string::npos;
    if (!feed && !rapid) continue;
    double x = 0, y = 0, z = 0;
    if (std::sscanf(s.c_str() + s.find('(') + 1, "%lf, %lf, %lf", &x, &y, &z) != 3) continue;
    if (x == at[0] && y == at[1] && z == at[2]) continue;
    at = {x, y, z};
    out.push_back({feed ? 1.0 : 0.0, x, y, z});
  }
  pclose(f);
  return out;
}

}  // namespace

// G83 from Z 5 above (10, 5): R 1, Q 4, to Z -10. LinuxCNC: feed to 1 − 4 = −3, rapid to R, rapid to
// −3 + 0.254, feed to −7, rapid to R, rapid to −6.746, feed to the bottom (−11 is below it), rapid
// back to 5 (G98: the Z before the cycle).
TEST(DrillCycles, G83IsReadAsTheHandComputedPecks) {
  const Program p = read("G21 G90\nG0 X0 Y0 Z5\nG98 G83 X10 Y5 Z-10 R1 Q4 F100\nG80\nM30\n", "drill.nc");
  const std::vector<Move> m = moves_of(p);
  const std::vector<std::array<double, 4>> want{{0, 10, 5, 5},      {0, 10, 5, 1},  {1, 10, 5, -3}, {0, 10, 5, 1},
                                                {0, 10, 5, -2.746}, {1, 10, 5, -7}, {0, 10, 5, 1},  {0, 10, 5, -6.746},
                                                {1, 10, 5, -10},    {0, 10, 5, 5}};
  ASSERT_EQ(m.size(), want.size() + 1);
  for (std::size_t k = 0; k < want.size(); ++k) {
    const Move& mv = m[k + 1];
    EXPECT_EQ(mv.motion, want[k][0] == 1 ? Motion::Line : Motion::Rapid) << k;
    EXPECT_NEAR(mv.to[0], want[k][1], 1e-12) << k;
    EXPECT_NEAR(mv.to[1], want[k][2], 1e-12) << k;
    EXPECT_NEAR(mv.to[2], want[k][3], 1e-12) << k;
    EXPECT_EQ(mv.cycle, 83) << k;
    if (mv.motion == Motion::Line) EXPECT_EQ(mv.feed, 100) << k;
  }
}

// LinuxCNC's interpreter as the oracle: the moves it makes of G81 and G83 series (G98 and G99, a
// repeated hole by X Y alone, Z R Q changed on the way, inch units) are the reader's.
TEST(DrillCycles, TheReadersMovesAreLinuxCncsOwn) {
  const std::vector<std::string> programs{
      "G21 G90 G17\nG0 X1 Y2 Z8\nG98 G81 X3 Y4 Z-2 R2 F200\nX6 Y4\nY9 Z-5.5 R0.5\nG80\nG0 Z20\nM30\n",
      "G21 G90 G17\nG0 X0 Y0 Z10\nG99 G83 X5 Y5 Z-20 R2 Q3.3 F150\nX15 Q7\nX25 Z-1 R3\nG80\nM30\n",
      "G20 G90 G17\nG0 X0 Y0 Z1\nG98 G83 X1 Y1 Z-0.8 R0.1 Q0.25 F10\nX2\nG80\nM30\n",
      "G21 G90 G17\nG0 X0 Y0 Z-3\nG98 G81 X4 Y0 Z-6 R1 F90\nG80\nM30\n"};  // below R first: up to R
  for (const std::string& text : programs) {
    SCOPED_TRACE(text);
    const std::vector<std::array<double, 4>> lx = linuxcnc_moves(text);
    const std::vector<Move> m = moves_of(read(text, "drill.nc"));
    ASSERT_EQ(lx.size(), m.size());
    const double unit = text.find("G20") != std::string::npos ? 25.4 : 1.0;
    for (std::size_t k = 0; k < m.size(); ++k) {
      EXPECT_EQ(m[k].motion == Motion::Line, lx[k][0] == 1) << k;
      for (std::size_t a = 0; a < 3; ++a) EXPECT_NEAR(m[k].to[a], lx[k][a + 1] * unit, 1e-4 * unit) << k << " " << a;
    }
  }
}

// Holes built as drill_cycle_moves are written as cycle blocks where the dialect has them and as
// moves on GRBL; read back, every dialect gives the same moves; LinuxCNC and GRBL's grammar accept.
TEST(DrillCycles, WrittenAsCyclesOnLinuxCncAndFanucAsMovesOnGrblAndReadBackTheSame) {
  Program p;
  Move reach;
  reach.to = {10, 10, 5};
  p.items.emplace_back(Spindle{SpindleDir::CW, 3000});
  p.items.emplace_back(reach);
  Point3 at = reach.to;
  std::uint8_t known = kXYZ;
  const std::vector<DrillHole> holes{
      {10, 10, -4, 1, 0, 300}, {30, 10, -4, 1, 0, 300}, {30, 40, -25, 1, 6, 300}, {50, 40, -25, 1, 6, 300}};
  for (const DrillHole& h : holes) {
    if (&h == &holes[2]) p.items.emplace_back(Comment{"deep holes"});
    for (const Move& m : drill_cycle_moves(at, known, h, 5)) {
      at = m.to, known = m.axes;
      p.items.emplace_back(m);
    }
  }
  Move away;
  away.to = {0, 0, 20};
  p.items.emplace_back(away);
  p.items.emplace_back(Spindle{SpindleDir::Off, 0});
  const std::vector<Move> built = moves_of(p);
  for (const char* name : {"linuxcnc", "fanuc", "grbl"}) {
    SCOPED_TRACE(name);
    const Dialect d = dialect_named(name);
    const std::string text = write(p, d);
    const bool cycles = std::string(name) != "grbl";
    EXPECT_EQ(text.find("G98 G81 X10") != std::string::npos, cycles) << text;
    EXPECT_EQ(text.find("G83 X30") != std::string::npos, cycles) << text;
    EXPECT_EQ(text.find("G80") != std::string::npos, cycles || d.preamble.find("G80") != std::string::npos);
    if (std::string(name) == "linuxcnc") {
      EXPECT_NE(text.find("\nX30 Y10\n"), std::string::npos) << "a repeated hole by X Y alone: " << text;
      EXPECT_NE(text.find("G83 X30 Y40 Z-25 R1 Q6\n"), std::string::npos) << text;
      EXPECT_NE(text.find("\nG80\nG0 X0 Y0 Z20\n"), std::string::npos) << text;
      const std::filesystem::path nc = std::filesystem::temp_directory_path() / "millnet_cycles_write.nc";
      std::ofstream(nc) << text;
      EXPECT_TRUE(millnet::testing::linuxcnc_accepts(nc.string())) << text;
    }
    if (std::string(name) == "grbl") EXPECT_TRUE(millnet::testing::grbl_errors(text).empty()) << text;
    const std::vector<Move> back = moves_of(read(text, name));
    ASSERT_EQ(back.size(), built.size());
    for (std::size_t k = 0; k < built.size(); ++k) {
      EXPECT_EQ(back[k].motion, built[k].motion) << k;
      for (std::size_t a = 0; a < 3; ++a) EXPECT_NEAR(back[k].to[a], built[k].to[a], 1e-9) << k;
    }
  }
  // A hole whose moves are not exactly a cycle's (its retract stops short of the Z it came from)
  // stays as moves; the next hole starts a series from where it is.
  Program q = p;
  for (Item& it : q.items)
    if (auto* m = std::get_if<Move>(&it);
        m != nullptr && m->to[0] == 10 && m->to[1] == 10 && m->to[2] == 5 && m->cycle != 0)
      m->to[2] = 4;
  const std::string text = write(q, linuxcnc());
  EXPECT_EQ(text.find("G81 X10"), std::string::npos) << text;
  EXPECT_NE(text.find("G0 Z1\nG1 Z-4 F300\nG0 Z4\nG0 X30 Z5\nG98 G81 X30 Y10 Z-4 R1\n(deep holes)\nG83 X30 Y40"),
            std::string::npos)
      << text;
}

// After a cycle block the controller stands over the last hole, not where the writer last stated
// X and Y: a move back to that earlier place states them again (the writer formats each axis's
// position once and must forget it across a cycle), and read back it goes there.
TEST(DrillCycles, AMoveBackToWhereTheToolStoodBeforeTheHoleStatesItsXAndY) {
  const Program p = read("G21 G90\nG0 X0 Y0 Z5\nG98 G81 X10 Y5 Z-2 R1 F100\nG80\nG0 X0 Y0\nM30\n", "drill.nc");
  const std::string text = write(p, linuxcnc());
  EXPECT_NE(text.find("G98 G81 X10 Y5 Z-2 R1 F100\nG80\nG0 X0 Y0\n"), std::string::npos) << text;
  const std::vector<Move> back = moves_of(read(text, "drill.nc"));
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.back().to[0], 0.0) << text;
  EXPECT_EQ(back.back().to[1], 0.0) << text;
  EXPECT_EQ(back.back().to[2], 5.0) << text;
}

TEST(DrillCycles, WhatLinuxCncRefusesIsOneLine) {
  const std::string pre = "G21 G90\nG0 X0 Y0 Z5\n";
  EXPECT_NE(error_of(pre + "G83 X1 Y1 Z-5 R1 F100\n").find("drill.nc:3: G83 without a Q word > 0"), std::string::npos);
  EXPECT_NE(error_of(pre + "G81 X1 Y1 Z2 R1 F100\n").find("R 1 is below the hole's bottom Z 2"), std::string::npos);
  EXPECT_NE(error_of(pre + "G81 X1 Y1 R1 F100\n").find("G81 without a Z word"), std::string::npos);
  EXPECT_NE(error_of(pre + "G81 X1 Y1 Z-1 F100\n").find("G81 without an R word"), std::string::npos);
  EXPECT_NE(error_of("G21 G90\nG0 X0 Y0 Z5\nG1 X1 F0\nG81 X1 Y1 Z-1 R1\n").find("no feed rate"), std::string::npos);
  EXPECT_NE(error_of(pre + "G91 G81 X1 Y1 Z-1 R1 F10\n").find("G81 in G91"), std::string::npos);
  EXPECT_NE(error_of(pre + "G83 X1 Y1 Z-100 R1 Q0.001 F100\n").find("makes more than 10000 pecks"), std::string::npos);
  std::string many = pre + "G83 X1 Y1 Z-99 R1 Q0.01 F100\n";  // 10,000 pecks a hole: allowed, 21 holes are not
  for (int k = 2; k <= 21; ++k) many += "X" + std::to_string(k) + "\n";
  EXPECT_NE(error_of(many).find("drill.nc:23: G83: the program's drilling cycles make more than 200000 pecks"),
            std::string::npos)
      << error_of(many);
  EXPECT_NE(error_of(pre + "G1 X1 Q2 F10\n").find("Q word outside a G83 cycle"), std::string::npos);
  EXPECT_NE(error_of(pre + "G1 G81 X1 Y1 Z-1 R1 F10\n").find("two G-codes of one modal group"), std::string::npos);
  EXPECT_NE(error_of("G21 G90\nG81 X1 Y1 Z-1 R1 F10\n").find("G81 from an unknown Z"), std::string::npos);
  // A cycle's modal Z and R carry to the next hole; G80 ends the cycle: axis words then need a motion.
  EXPECT_NE(error_of(pre + "G81 X1 Y1 Z-1 R1 F10\nX2\nG80\nX3\n").find("no motion mode"), std::string::npos);
  EXPECT_EQ(error_of(pre + "G81 X1 Y1 Z-1 R1 F10\nX2\nG80\nG0 X3\n"), "no error");
}
