// The GRBL 1.1 dialect against an independent check of GRBL's grammar (tests/testing/grbl_check.hpp,
// GRBL's own rules and error numbers): the check fails on what GRBL refuses, and the writer's GRBL
// text of a program with every item kind passes it. The dialect registry lists both controllers.
#include "testing/moves.hpp"
#include "testing/grbl_check.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace millnet::gcode;
using millnet::testing::grbl_errors;
using millnet::testing::grbl_report;

namespace {

int first_code(const std::string& text) {
  const auto e = grbl_errors(text);
  return e.empty() ? -1 : e.front().code;
}

}  // namespace

TEST(GrblCheck, RefusesWhatGrblRefusesWithItsErrorNumber) {
  EXPECT_EQ(first_code("G21 G90\nG0 X1 Y2\nM30\n"), -1);
  EXPECT_EQ(first_code("T2 M6\n"), 20);                             // no tool changer
  EXPECT_EQ(first_code("G64 P0.01\n"), 20);                         // no path blending mode
  EXPECT_EQ(first_code("O100\n"), 20);                              // no O-words (subroutines)
  EXPECT_EQ(first_code("G0 G1 X1\n"), 24);                          // two motion codes on one line
  EXPECT_EQ(first_code("G90 G91 X1\n"), 21);                        // two distance modes
  EXPECT_EQ(first_code("G0 X1 X2\n"), 25);                          // repeated word
  EXPECT_EQ(first_code("G1 X1\n"), 22);                             // feed never set
  EXPECT_EQ(first_code("G0 X" + std::string(80, '1') + "\n"), 11);  // beyond the 80-byte line buffer
  EXPECT_EQ(first_code("(" + std::string(140, 'c') + ")\n"), 0);    // beyond the serial buffer
  EXPECT_EQ(first_code("G1 X10 Y0 F100\nG2 X0 Y0 I-5 J0\n"), -1);   // a half circle
  EXPECT_EQ(first_code("G1 X10 Y0 F100\nG2 X0 Y0 I-4 J0\n"), 33);   // end 2 mm off its circle
  EXPECT_EQ(first_code("G1 X10 F100 I3\n"), 36);                    // I unused by a line
  EXPECT_EQ(first_code("%\n"), 1);
  EXPECT_EQ(first_code("G0 X1.2.3\n"), 1);  // read_float stops at the second point
}

TEST(GrblDialect, EveryItemKindIsWrittenAsGrblAcceptsIt) {
  Program p;
  p.header = {"grbl sample (every item)", std::string(200, 'h')};  // a long header comment is cut
  Move arc = millnet::testing::move(Motion::ArcCCW, {20, 10, -1}, 300);
  arc.center = {20, 5};
  Move helix = millnet::testing::move(Motion::ArcCW, {10.12345, 10, -1.5}, 250.25);
  helix.center = {15.061725, 10};
  p.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}),
             ToolChange{2, "6 mm end mill (carbide)"},
             millnet::testing::move(Motion::Rapid, {10, 0, 5}),
             Spindle{SpindleDir::CW, 12000},
             millnet::testing::move(Motion::Line, {10, 0, -1}, 100),
             millnet::testing::move(Motion::Line, {20, 0, -1}, 300),
             arc,
             helix,
             Comment{"finish " + std::string(150, 'x')},
             millnet::testing::move(Motion::Rapid, {10.12345, 10, 5}),
             Pause{true},
             Spindle{SpindleDir::Off, 0},
             Pause{false}};
  const std::string text = write(p, grbl());
  const auto errors = grbl_errors(text);
  EXPECT_TRUE(errors.empty()) << grbl_report(errors) << text;
  EXPECT_EQ(text.find("M6"), std::string::npos) << text;
  EXPECT_NE(text.find("(tool change: load T2"), std::string::npos) << text;
  // LinuxCNC's text of the same program is not GRBL's: the check tells them apart.
  EXPECT_FALSE(grbl_errors(write(p, linuxcnc())).empty());
  // Read back, the GRBL text gives the same moves as the LinuxCNC text.
  const Program a = read(text, "a.nc"), b = read(write(p, linuxcnc()), "b.nc");
  std::vector<Move> ma, mb;
  for (const Item& i : a.items)
    if (const auto* m = std::get_if<Move>(&i)) ma.push_back(*m);
  for (const Item& i : b.items)
    if (const auto* m = std::get_if<Move>(&i)) mb.push_back(*m);
  ASSERT_EQ(ma.size(), mb.size());
  for (std::size_t k = 0; k < ma.size(); ++k) {
    EXPECT_EQ(ma[k].to, mb[k].to) << k;
    EXPECT_EQ(ma[k].motion, mb[k].motion) << k;
    EXPECT_EQ(ma[k].feed, mb[k].feed) << k;
  }
}

TEST(GrblDialect, AToolChangeReadsBackAsTheToolChangeItWasWrittenFrom) {
  Program p;
  p.items = {millnet::testing::move(Motion::Rapid, {0, 0, 5}),
             ToolChange{7, "bn2: D2 mm ball"},
             millnet::testing::move(Motion::Rapid, {1, 0, 5}),
             Pause{false},
             ToolChange{12, ""},
             millnet::testing::move(Motion::Rapid, {2, 0, 5})};
  const std::string text = write(p, grbl());
  const Program back = read(text, "g.nc");
  std::vector<int> numbers;
  std::size_t pauses = 0;
  for (const Item& i : back.items) {
    if (const auto* t = std::get_if<ToolChange>(&i)) numbers.push_back(t->number);
    if (std::holds_alternative<Pause>(i)) ++pauses;
  }
  EXPECT_EQ(numbers, (std::vector<int>{7, 12}));
  EXPECT_EQ(pauses, 1U);  // the M0 of each change belongs to it; the program's own pause stays
  EXPECT_EQ(std::get<ToolChange>(back.items[1]).description, "bn2: D2 mm ball");
  EXPECT_EQ(write(back, grbl()), text);  // written again: the same text
  // A comment that merely mentions a tool change stays a comment.
  const Program other = read("G0 Z5\n(tool change: load the vise)\nM0\n", "o.nc");
  EXPECT_TRUE(std::holds_alternative<Comment>(other.items[1]));
  EXPECT_TRUE(std::holds_alternative<Pause>(other.items[2]));
}

TEST(Dialects, TheRegistryNamesEachControllerOnce) {
  const std::vector<std::string> names = dialect_names();
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[0], "linuxcnc");
  EXPECT_EQ(names[1], "grbl");
  for (const std::string& n : names) EXPECT_EQ(dialect_named(n).name, n);
  try {
    (void)dialect_named("heidenhain");
    ADD_FAILURE() << "no error";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"linuxcnc\", \"grbl\""), std::string::npos) << e.what();
  }
}
