// gcode::write: exact text per dialect, and LinuxCNC's own interpreter accepts what it writes.
#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"
#include "testing/grbl_check.hpp"
#include "testing/linuxcnc.hpp"
#include "testing/moves.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace millnet::gcode;

namespace {
Move arc(Motion m, Point3 to, std::array<double, 2> c, double feed) {
  Move x = millnet::testing::move(m, to, feed);
  x.center = c;
  return x;
}
/// A small program with every item kind: rapids, a plunge, lines, both arcs (one helical), feeds
/// changing, spindle, a tool change, pauses, comments.
Program sample() {
  Program p;
  p.header = {"sample (test)", "units mm"};
  p.items = {
      millnet::testing::move(Motion::Rapid, {0, 0, 5}, 0, kZ),
      ToolChange{2, "6 mm end mill"},
      millnet::testing::move(Motion::Rapid, {10, 0, 5}),
      Spindle{SpindleDir::CW, 12000},
      millnet::testing::move(Motion::Line, {10, 0, -1}, 100),
      millnet::testing::move(Motion::Line, {20, 0, -1}, 300),
      arc(Motion::ArcCCW, {20, 10, -1}, {20, 5}, 300),
      arc(Motion::ArcCW, {10.12345, 10, -1.5}, {15.061725, 10}, 250.25),
      Comment{"finish"},
      millnet::testing::move(Motion::Rapid, {10.12345, 10, 5}),
      Pause{true},
      Spindle{SpindleDir::Off, 12000},
      Pause{false},
  };
  return p;
}
const char* const kSampleLinuxcnc =
    "(sample [test])\n"
    "(units mm)\n"
    "G21 G90 G17 G94\n"
    "G0 Z5\n"
    "T2 M6 (6 mm end mill)\n"
    "G0 X10 Y0\n"
    "M3 S12000\n"
    "G1 Z-1 F100\n"
    "G1 X20 F300\n"
    "G3 X20 Y10 I0 J5\n"
    "G2 X10.1235 Y10 Z-1.5 I-4.9383 J0 F250.2\n"
    "(finish)\n"
    "G0 Z5\n"
    "M1\n"
    "M5\n"
    "M0\n"
    "M30\n";
}  // namespace

TEST(GcodeWriter, LinuxcncExactText) { EXPECT_EQ(write(sample(), linuxcnc()), kSampleLinuxcnc); }

TEST(GcodeWriter, GrblHasNoToolChangeAndNoOptionalStop) {
  const std::string t = write(sample(), grbl());
  EXPECT_EQ(t.find("M6"), std::string::npos);
  EXPECT_EQ(t.find("M1\n"), std::string::npos);
  EXPECT_NE(t.find("(tool change: load T2 6 mm end mill, then resume)\nM0\n"), std::string::npos) << t;
  EXPECT_NE(t.find("G0 Z5\nM0\nM5\nM0\nM30\n"), std::string::npos) << t;
  Program p;
  p.items = {Comment{std::string(200, 'x')}};
  const std::string c = write(p, grbl());
  std::string cut(62, 'x');  // "(" + 60 × x + ")"
  cut.front() = '(';
  cut.back() = ')';
  EXPECT_NE(c.find(cut), std::string::npos) << c;
  EXPECT_EQ(c.find(std::string(61, 'x')), std::string::npos);
}

// Issue 42 §10: a newline in a file stem ended the title comment and left "t.stl)" as a line of
// its own; control bytes and parentheses in any comment or tool description stay on their line.
TEST(GcodeWriter, CommentsStayOneLine) {
  Program p;
  p.header = {"millnet finish par\nt.stl (a\r\x7f\tb)"};
  p.items = {ToolChange{3, "tool\nname (x)"}, Comment{std::string("nul\0byte", 8)}};
  for (const Dialect& d : {linuxcnc(), grbl()}) {
    const std::string t = write(p, d);
    EXPECT_NE(t.find("(millnet finish par?t.stl [a???b])\n"), std::string::npos) << t;
    EXPECT_NE(t.find("(nul?byte)\n"), std::string::npos) << t;
    EXPECT_NE(t.find("tool?name [x]"), std::string::npos) << t;
    EXPECT_NO_THROW((void)read(t, "comments.nc")) << t;
  }
}

TEST(GcodeWriter, NumberFormat) {
  EXPECT_EQ(format_number(-0.00001, 4), "0");
  EXPECT_EQ(format_number(2.50, 4), "2.5");
  EXPECT_EQ(format_number(3.0, 4), "3");
  EXPECT_EQ(format_number(-1.23456, 4), "-1.2346");
  EXPECT_EQ(format_number(12000, 0), "12000");
  EXPECT_EQ(format_number(1.5, 6), "1.5");
  EXPECT_EQ(format_number(0.00005, 4), "0.0001");  // 5.000000000000000409e-05: above the tie
  EXPECT_EQ(format_number(0.125, 2), "0.12");      // an exact tie: to even, as printf
}

// The number writer (std::to_chars) writes what printf("%.*f") writes, trimmed: random values of
// every magnitude a program holds, exact ties and their neighbours, at 0–6 decimals.
TEST(GcodeWriter, NumberFormatIsPrintfs) {
  std::srand(7);
  auto printf_trimmed = [](double v, int d) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "%.*f", d, v);
    std::string s(buf);
    if (s.find('.') != std::string::npos) {
      while (s.back() == '0') s.pop_back();
      if (s.back() == '.') s.pop_back();
    }
    return s == "-0" ? std::string("0") : s;
  };
  for (int k = 0; k < 200000; ++k) {
    const double mag = std::pow(10.0, std::rand() % 9 - 4);
    double v = (static_cast<double>(std::rand()) / RAND_MAX - 0.5) * 2 * mag;
    const int d = k % 7;
    if (k % 5 == 0) v = std::round(v * std::pow(10.0, d + 1)) / std::pow(10.0, d + 1);  // ties at d + 1
    if (k % 11 == 0) v = std::nextafter(v, k % 2 == 0 ? 1e9 : -1e9);
    ASSERT_EQ(format_number(v, d), printf_trimmed(v, d)) << v << " at " << d;
  }
}

TEST(GcodeWriter, Errors) {
  Program p;
  p.items = {millnet::testing::move(Motion::Line, {std::nan(""), 0, 0}, 100)};
  EXPECT_THROW((void)write(p, linuxcnc()), millnet::Error);
  EXPECT_THROW((void)write(Program{}, linuxcnc(2)), millnet::Error);
  EXPECT_THROW((void)dialect_named("heidenhain"), millnet::Error);
  EXPECT_EQ(dialect_named("grbl").name, "grbl");
}

TEST(GcodeWriter, FileIsWrittenWhole) {
  const auto dir = std::filesystem::temp_directory_path() / ("millnet_gcode_w_" + std::to_string(::getpid()));
  const auto f = dir / "a.nc";
  write_program(f, sample(), linuxcnc());
  std::ifstream in(f);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, kSampleLinuxcnc);
  std::filesystem::remove_all(dir);
}

TEST(GcodeWriter, RoundTripWriteReadWrite) {
  for (const Dialect& d : {linuxcnc(), linuxcnc(6), grbl()}) {
    const std::string once = write(sample(), d);
    const Program back = read(once, "sample.nc");
    EXPECT_EQ(back.items.size(), back.source_line.size());
    EXPECT_EQ(write(back, d), once) << d.name;
  }
}

TEST(GcodeWriter, LinuxcncInterpreterAcceptsWrittenPrograms) {
  if (!std::filesystem::exists("/usr/bin/rs274")) GTEST_SKIP() << "/usr/bin/rs274 (linuxcnc-uspace) missing";
  const auto dir = std::filesystem::temp_directory_path() / ("millnet_gcode_rs_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Program helix;  // a helical entry and a full circle, as pocket writes them
  helix.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}, 0, kZ),
                 millnet::testing::move(Motion::Rapid, {3, 0, 5}),
                 Spindle{SpindleDir::CW, 10000},
                 millnet::testing::move(Motion::Line, {3, 0, 1}, 200),
                 arc(Motion::ArcCCW, {-3, 0, 0.5}, {0, 0}, 200),
                 arc(Motion::ArcCCW, {3, 0, 0}, {0, 0}, 200),
                 arc(Motion::ArcCCW, {-3, 0, -0.5}, {0, 0}, 200),
                 arc(Motion::ArcCCW, {3, 0, -1}, {0, 0}, 200),
                 arc(Motion::ArcCW, {3, 0, -2}, {0, 0}, 400),  // a full circle
                 millnet::testing::move(Motion::Rapid, {3, 0, 5}),
                 Spindle{SpindleDir::Off, 0}};
  int k = 0;
  const Program programs[] = {helix, sample()};
  for (const Program& prog : programs) {
    for (const Dialect& d : {linuxcnc(), grbl()}) {
      std::string name = "p";
      name += std::to_string(k++);
      name += ".nc";
      const auto f = dir / name;
      write_program(f, prog, d);
      EXPECT_EQ(millnet::testing::linuxcnc_status(f.string()), 0) << d.name << "\n" << write(prog, d);
    }
  }
  std::filesystem::remove_all(dir);
}

// Inch output (issue 38): G20, coordinates and arc offsets in inches with one more decimal, feeds
// in in/min; read back (G20 converted to mm) the same moves within half an increment (0.0000127 in
// = 0.000127 mm), and accepted by LinuxCNC's interpreter and the GRBL grammar.
TEST(GcodeWriter, InchProgramsReadBackToTheSameMovesInMillimetres) {
  const Dialect in = in_inches(linuxcnc());
  EXPECT_EQ(in.decimals, 5);
  EXPECT_EQ(in_inches(fanuc()).decimals, 4);
  EXPECT_EQ(in_inches(in).decimals, 5);  // once
  const std::string text = write(sample(), in);
  EXPECT_NE(text.find("G20 G90 G17 G94\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("G21"), std::string::npos) << text;
  EXPECT_NE(text.find("(units: inch [G20], feeds in/min)"), std::string::npos) << text;
  // 10 mm = 0.393700787 in, 300 mm/min = 11.811 in/min; the arc's I −4.938275 mm = −0.194420 in.
  EXPECT_NE(text.find("G0 X0.3937 Y0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("G1 X0.7874 F11.81\n"), std::string::npos) << text;
  EXPECT_NE(text.find("I-0.19442 J0 F9.85\n"), std::string::npos) << text;
  const Program mm = read(write(sample(), linuxcnc(8)), "mm.nc");
  const Program inch = read(text, "inch.nc");
  ASSERT_EQ(mm.items.size(), inch.items.size());
  std::size_t moves = 0;
  for (std::size_t i = 0; i < mm.items.size(); ++i) {
    const auto* a = std::get_if<Move>(&mm.items[i]);
    const auto* b = std::get_if<Move>(&inch.items[i]);
    ASSERT_EQ(a == nullptr, b == nullptr) << i;
    if (a == nullptr) continue;
    ++moves;
    EXPECT_EQ(a->motion, b->motion);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(a->to[k], b->to[k], 0.5e-5 * 25.4 + 1e-12) << i;
    for (std::size_t k = 0; k < 2; ++k) EXPECT_NEAR(a->center[k], b->center[k], 1e-5 * 25.4 + 1e-12) << i;
    EXPECT_NEAR(a->feed, b->feed, 0.005 * 25.4 + 1e-9) << i;
  }
  EXPECT_EQ(moves, 7u);
  const auto errors = millnet::testing::grbl_errors(write(sample(), in_inches(grbl())));
  EXPECT_TRUE(errors.empty()) << millnet::testing::grbl_report(errors);
  if (!std::filesystem::exists("/usr/bin/rs274")) GTEST_SKIP() << "/usr/bin/rs274 (linuxcnc-uspace) missing";
  const auto f = std::filesystem::temp_directory_path() / ("millnet_inch_" + std::to_string(::getpid()) + ".nc");
  write_program(f, sample(), in);
  EXPECT_EQ(millnet::testing::linuxcnc_status(f.string()), 0) << text;
  std::filesystem::remove(f);
}
