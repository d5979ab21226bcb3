// Tool tables of LinuxCNC, FreeCAD and Fusion 360 (issue 40): files written by hand after each
// system's documentation and sources (tests/tooling/data/), read into tools with hand-checked values;
// LinuxCNC's table written back, read again and read by LinuxCNC's own interpreter; bad files
// refused in one line naming the file and the field.
#include "millnet/core/error.hpp"
#include "millnet/tooling/io/tool_tables.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <unistd.h>

namespace t = millnet::tooling;
namespace tio = millnet::tooling::io;
namespace fs = std::filesystem;

namespace {

const fs::path kData = fs::path("tests") / "tooling" / "data";

const t::Tool& numbered(const tio::ToolImport& imp, int number) {
  for (const t::Tool& x : imp.tools)
    if (x.number == number) return x;
  throw std::runtime_error("no T" + std::to_string(number));
}

bool any_note(const tio::ToolImport& imp, const std::string& part) {
  for (const std::string& n : imp.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

/// The message of the millnet::Error `f` throws ("" when it throws none).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "";
}

std::string lcnc_error(const std::string& text) {
  return error_of([&] { (void)tio::read_linuxcnc_tool_table(text, "shop.tbl"); });
}

}  // namespace

// --- LinuxCNC tool.tbl ------------------------------------------------------------------------

TEST(LinuxCncToolTable, ReadsTheHandWrittenTable) {
  const auto imp = tio::import_tool_file(kData / "linuxcnc" / "tool.tbl", tio::ToolFormat::LinuxCnc);
  ASSERT_EQ(imp.tools.size(), 5U);  // T0 (the empty spindle) is not a tool
  const t::Tool& t1 = numbered(imp, 1);
  EXPECT_EQ(t1.type, t::ToolType::Flat);
  EXPECT_DOUBLE_EQ(t1.diameter_mm, 6);
  EXPECT_EQ(t1.flutes, 3);
  EXPECT_EQ(t1.material, t::ToolMaterial::Carbide);
  EXPECT_EQ(t1.description, "6mm end mill 3F carbide");
  EXPECT_EQ(t1.id, "6mm-end-mill-3f-carbide");
  const t::Tool& t2 = numbered(imp, 2);
  EXPECT_EQ(t2.type, t::ToolType::Ball);
  EXPECT_DOUBLE_EQ(t2.corner_radius_mm, 1);
  EXPECT_EQ(t2.flutes, 2);
  const t::Tool& t3 = numbered(imp, 3);  // tab-separated words, P5
  EXPECT_EQ(t3.type, t::ToolType::Bull);
  EXPECT_DOUBLE_EQ(t3.diameter_mm, 10);
  EXPECT_DOUBLE_EQ(t3.corner_radius_mm, 1);
  EXPECT_EQ(t3.flutes, 4);
  const t::Tool& t4 = numbered(imp, 4);  // lower-case words, every offset word
  EXPECT_EQ(t4.type, t::ToolType::Drill);
  EXPECT_DOUBLE_EQ(t4.diameter_mm, 5);
  EXPECT_EQ(t4.material, t::ToolMaterial::HSS);
  const t::Tool& t5 = numbered(imp, 5);  // no comment at all
  EXPECT_EQ(t5.id, "t5");
  EXPECT_EQ(t5.type, t::ToolType::Flat);
  EXPECT_DOUBLE_EQ(t5.diameter_mm, 3.175);
  EXPECT_EQ(t5.length_offset_register(), 5);  // H = T in LinuxCNC
  // What was assumed is said, naming the tools.
  EXPECT_TRUE(any_note(imp, "no tool type in the comment (ball, bull, drill, end mill): taken as a flat end mill: T5"));
  EXPECT_TRUE(any_note(imp, "no flute count in the comment (e.g. '3F'): 2 flutes: T4, T5"));
  EXPECT_TRUE(any_note(imp, "lengths read as mm"));
  EXPECT_TRUE(any_note(imp, "T0 is LinuxCNC's empty spindle"));
  EXPECT_TRUE(any_note(imp, "pockets P are not kept"));
  EXPECT_TRUE(any_note(imp, "tabs"));  // LinuxCNC 2.9's reader splits on spaces only
}

TEST(LinuxCncToolTable, InchTableIsConvertedToMm) {
  const auto imp =
      tio::import_tool_file(kData / "linuxcnc" / "inch.tbl", tio::ToolFormat::LinuxCnc, tio::LengthUnit::Inch);
  ASSERT_EQ(imp.tools.size(), 3U);
  EXPECT_DOUBLE_EQ(numbered(imp, 1).diameter_mm, 3.175);   // 1/8 in
  EXPECT_DOUBLE_EQ(numbered(imp, 2).diameter_mm, 1.5875);  // 1/16 in
  EXPECT_DOUBLE_EQ(numbered(imp, 3).diameter_mm, 5.1054);  // #7 drill, 0.201 in
  EXPECT_EQ(numbered(imp, 3).type, t::ToolType::Drill);
  // Read as mm, the same table is suspicious and the notes say so.
  const auto as_mm = tio::import_tool_file(kData / "linuxcnc" / "inch.tbl", tio::ToolFormat::LinuxCnc);
  EXPECT_TRUE(any_note(as_mm, "is this an inch machine's table?"));
  EXPECT_FALSE(any_note(imp, "is this an inch machine's table?"));
}

TEST(LinuxCncToolTable, ExportFollowsLinuxCncsGrammar) {
  const auto imp = tio::import_tool_file(kData / "linuxcnc" / "tool.tbl", tio::ToolFormat::LinuxCnc);
  const tio::ToolTableText table = tio::linuxcnc_tool_table(imp.tools);
  std::istringstream in(table.text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind(";", 0), 0U) << "a header LinuxCNC ignores";
  // "T<n> P<n> D<number> Z0 ;<comment of at most 39 characters>", single spaces, sorted by T, P = T.
  const std::regex row(R"(T([0-9]+) P([0-9]+) D([0-9.e+-]+) Z0 ;([ -~]{1,39}))");
  int last = 0, rows = 0;
  while (std::getline(in, line)) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, row)) << line;
    EXPECT_EQ(m[1], m[2]) << line;
    EXPECT_GT(std::stoi(m[1]), last);
    last = std::stoi(m[1]);
    ++rows;
  }
  EXPECT_EQ(rows, 5);
  EXPECT_NE(table.text.find("T3 P3 D10 Z0 ;bull-nose-r1-4-flute: bull r1 4F\n"), std::string::npos) << table.text;
  EXPECT_NE(table.text.find("T4 P4 D5 Z0 ;5mm-drill-hss: drill 2F hss\n"), std::string::npos) << table.text;
}

TEST(LinuxCncToolTable, RoundTripGivesTheSameTools) {
  const auto first = tio::import_tool_file(kData / "linuxcnc" / "tool.tbl", tio::ToolFormat::LinuxCnc);
  const auto again = tio::read_linuxcnc_tool_table(tio::linuxcnc_tool_table(first.tools).text, "exported.tbl");
  ASSERT_EQ(again.tools.size(), first.tools.size());
  for (const t::Tool& a : first.tools) {
    SCOPED_TRACE(a.id);
    const t::Tool& b = numbered(again, a.number);
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.type, a.type);
    EXPECT_EQ(b.diameter_mm, a.diameter_mm);
    EXPECT_EQ(b.corner_radius_mm, a.corner_radius_mm);
    EXPECT_EQ(b.flutes, a.flutes);
    EXPECT_EQ(b.material, a.material);
    EXPECT_EQ(b.length_offset_register(), a.length_offset_register());
  }
  // The second time the comments say type and flutes (and hss; carbide is the reader's default).
  EXPECT_FALSE(any_note(again, "no tool type"));
  EXPECT_FALSE(any_note(again, "no flute count"));
}

TEST(LinuxCncToolTable, ExportIsReadByLinuxCncsInterpreter) {
  if (!fs::exists("/usr/bin/rs274")) GTEST_SKIP() << "/usr/bin/rs274 (linuxcnc-uspace) missing";
  const auto imp = tio::import_tool_file(kData / "linuxcnc" / "tool.tbl", tio::ToolFormat::LinuxCnc);
  std::vector<t::Tool> tools = imp.tools;
  tools[0].id = "a-rather-long-tool-id-from-a-shop-library";  // shortened to fit LinuxCNC's comment
  const tio::ToolTableText table = tio::linuxcnc_tool_table(tools);
  EXPECT_FALSE(table.notes.empty());
  const fs::path dir = fs::temp_directory_path() / ("millnet_tool_tbl_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "tool.tbl") << table.text;
  // Each tool loaded and its diameter read back from LinuxCNC's tool data (#5410).
  std::ofstream prog(dir / "check.ngc");
  for (const t::Tool& x : tools)
    prog << "T" << x.number << " M6\nG43 H" << x.number << "\n(debug, T" << x.number << " D=#5410)\n";
  prog << "M30\n";
  prog.close();
  const std::string cmd = "cd '" + dir.string() + "' && /usr/bin/rs274 -t tool.tbl -g check.ngc </dev/null 2>&1";
  std::string out;
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    ::pclose(p);
  }
  fs::remove_all(dir);
  EXPECT_EQ(out.find("Unrecognized"), std::string::npos) << out;
  EXPECT_EQ(out.find("truncated"), std::string::npos) << out;
  for (const t::Tool& x : tools) {
    char want[64];
    std::snprintf(want, sizeof want, "T%d D=%f", x.number, x.diameter_mm);
    EXPECT_NE(out.find(want), std::string::npos) << want << "\n" << out;
  }
}

TEST(LinuxCncToolTable, ExportRefusesToolsWithoutOrWithSharedNumbers) {
  const auto imp = tio::import_tool_file(kData / "linuxcnc" / "tool.tbl", tio::ToolFormat::LinuxCnc);
  std::vector<t::Tool> tools = imp.tools;
  tools[1].number = 0;
  EXPECT_NE(error_of([&] { (void)tio::linuxcnc_tool_table(tools); }).find("1 tool(s) without a number (T): '2mm-ball"),
            std::string::npos);
  tools[1].number = 1;
  EXPECT_NE(error_of([&] { (void)tio::linuxcnc_tool_table(tools); }).find("T1 is both"), std::string::npos);
  tools[1].number = 1001;
  EXPECT_NE(error_of([&] { (void)tio::linuxcnc_tool_table(tools); }).find("pockets go up to 1000"), std::string::npos);
  EXPECT_NE(error_of([&] { (void)tio::linuxcnc_tool_table({}); }).find("no tools"), std::string::npos);
}

TEST(LinuxCncToolTable, ExportSaysWhatTheTableCannotHold) {
  t::Tool x;
  x.id = "em8";
  x.diameter_mm = 8;
  x.number = 5;
  x.length_offset = 25;
  const auto table = tio::linuxcnc_tool_table({x});
  ASSERT_EQ(table.notes.size(), 1U);
  EXPECT_NE(table.notes[0].find("length offset H25 not written"), std::string::npos);
}

TEST(LinuxCncToolTable, BadLinesAreRefusedNamingTheLineAndTheWord) {
  EXPECT_NE(lcnc_error("T1 P1 D6\nT2 P2 Z1 ;no diameter\n").find("shop.tbl:2: T2: no D word"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D-6\n").find("shop.tbl:1: T1: diameter D-6 must be > 0"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D0\n").find("shop.tbl:1: T1: diameter D0 must be > 0"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D6 R1\n").find("shop.tbl:1: word 'R1' is not a tool-table word"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D6\n\nT1 P2 D8\n").find("shop.tbl:3: T1 is also line 1"), std::string::npos);
  EXPECT_NE(lcnc_error("T1.5 P1 D6\n").find("shop.tbl:1: word 'T1.5': T takes a whole number"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 Dnan\n").find("shop.tbl:1: word 'Dnan': D takes a finite number"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D1e999\n").find("shop.tbl:1: word 'D1e999'"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 Dinf\n").find("word 'Dinf'"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 D6\n").find("shop.tbl:1: no P word"), std::string::npos);
  EXPECT_NE(lcnc_error("P1 D6\n").find("shop.tbl:1: no T word"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D6 D7\n").find("shop.tbl:1: word D is given twice"), std::string::npos);
  EXPECT_NE(lcnc_error("T-1 P1 D6\n").find("shop.tbl:1: T-1"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1001 D6\n").find("shop.tbl:1: P1001"), std::string::npos);
  EXPECT_NE(
      lcnc_error("T1 P1 D6 ;bull nose\n").find("shop.tbl:1: T1: the comment names a bull nose but no corner radius"),
      std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D6 ;bull r4\n").find("shop.tbl:1 bull-r4: corner radius"), std::string::npos);
  EXPECT_NE(lcnc_error("   1      1   +0.511   0.125  1/8 end mill\n").find("shop.tbl:1: word '1'"), std::string::npos)
      << "the table format of LinuxCNC before 2.4";
  EXPECT_NE(lcnc_error("; only comments\n\n").find("shop.tbl: no tools"), std::string::npos);
  EXPECT_NE(lcnc_error("T1 P1 D6 ;" + std::string(300, 'x') + "\n").find("shop.tbl:1: 310 characters"),
            std::string::npos);
}

TEST(LinuxCncToolTable, InputIsBounded) {
  std::string big;
  for (int i = 1; i <= 10001; ++i) big += "T" + std::to_string(i) + " P1 D6\n";
  EXPECT_NE(lcnc_error(big).find("more than 10000 tools"), std::string::npos);
  EXPECT_NE(lcnc_error(std::string(tio::kMaxToolFileBytes + 1, ';')).find("the limit for a tool table is 8 MiB"),
            std::string::npos);
}

// --- FreeCAD ToolBits ----------------------------------------------------------------------------

TEST(FreeCadToolBit, ReadsEachShapeWithHandCheckedValues) {
  const fs::path bits = kData / "freecad" / "Bit";
  auto one = [&](const char* f) {
    const auto imp = tio::import_tool_file(bits / f, tio::ToolFormat::FreeCad);
    EXPECT_EQ(imp.tools.size(), 1U);
    return imp;
  };
  const auto em = one("6mm_Endmill.fctb");
  EXPECT_EQ(em.tools[0].id, "6mm-endmill");
  EXPECT_EQ(em.tools[0].type, t::ToolType::Flat);
  EXPECT_DOUBLE_EQ(em.tools[0].diameter_mm, 6);
  EXPECT_DOUBLE_EQ(em.tools[0].flute_length_mm, 20);
  EXPECT_EQ(em.tools[0].flutes, 3);
  EXPECT_EQ(em.tools[0].material, t::ToolMaterial::Carbide);
  EXPECT_EQ(em.tools[0].number, 0);  // a bit's number is its library's
  EXPECT_TRUE(any_note(em, "stick-out not stated"));
  const auto ball = one("6mm_Ball_End.fctb");  // Flutes "2" and Material in "attribute"
  EXPECT_EQ(ball.tools[0].type, t::ToolType::Ball);
  EXPECT_DOUBLE_EQ(ball.tools[0].corner_radius_mm, 3);
  EXPECT_EQ(ball.tools[0].flutes, 2);
  EXPECT_EQ(ball.tools[0].material, t::ToolMaterial::HSS);
  const auto bull = one("6mm_Bullnose.fctb");
  EXPECT_EQ(bull.tools[0].type, t::ToolType::Bull);
  EXPECT_DOUBLE_EQ(bull.tools[0].corner_radius_mm, 1.5);
  EXPECT_EQ(bull.tools[0].flutes, 4);
  EXPECT_TRUE(any_note(bull, "no Material: HSS (FreeCAD's default)"));
  const auto old = one("Old_Bullnose.fctb");  // corner = 10/2 - FlatRadius 4
  EXPECT_DOUBLE_EQ(old.tools[0].corner_radius_mm, 1);
  EXPECT_TRUE(any_note(old, "Diameter/2 - FlatRadius"));
  const auto drill = one("5mm_Drill.fctb");
  EXPECT_EQ(drill.tools[0].type, t::ToolType::Drill);
  EXPECT_DOUBLE_EQ(drill.tools[0].point_angle_deg, 119);
  EXPECT_DOUBLE_EQ(drill.tools[0].cutter().point_angle_deg, 119);
  const auto inch = one("Quarter_Inch_Endmill.fctb");
  EXPECT_DOUBLE_EQ(inch.tools[0].diameter_mm, 6.35);
  EXPECT_DOUBLE_EQ(inch.tools[0].flute_length_mm, 19.05);
  EXPECT_EQ(inch.tools[0].description, "1/4\" Endmill");
}

TEST(FreeCadToolBit, LibraryNumbersTheBitsItNames) {
  const auto imp = tio::import_tool_file(kData / "freecad" / "Library" / "Shop.fctl", tio::ToolFormat::FreeCad);
  ASSERT_EQ(imp.tools.size(), 5U);  // the v-bit is left out
  EXPECT_EQ(numbered(imp, 1).id, "6mm-endmill");
  EXPECT_EQ(numbered(imp, 2).type, t::ToolType::Drill);
  EXPECT_EQ(numbered(imp, 3).type, t::ToolType::Ball);
  EXPECT_DOUBLE_EQ(numbered(imp, 4).corner_radius_mm, 1.5);
  EXPECT_DOUBLE_EQ(numbered(imp, 12).diameter_mm, 6.35);
  EXPECT_TRUE(any_note(imp, "left out bits of shapes millnet does not model: 1 x v-bit.fcstd"));
  // The export of an imported library is a LinuxCNC table of the same numbers.
  const auto again = tio::read_linuxcnc_tool_table(tio::linuxcnc_tool_table(imp.tools).text, "x.tbl");
  EXPECT_EQ(numbered(again, 12).diameter_mm, 6.35);
  EXPECT_EQ(numbered(again, 4).corner_radius_mm, 1.5);
}

TEST(FreeCadToolBit, BadBitsAreRefusedNamingTheFileAndTheKey) {
  auto bit_error = [](const std::string& text) {
    return error_of([&] { (void)tio::read_freecad_toolbit(text, "x.fctb"); });
  };
  const std::string head = R"({"version": 2, "name": "x", "shape": "endmill.fcstd", "parameter": )";
  EXPECT_NE(bit_error(head + R"({"Length": "50 mm"}})").find("x.fctb: /parameter/Diameter: missing"),
            std::string::npos);
  EXPECT_NE(
      bit_error(head + R"({"Diameter": "-6 mm"}})").find("x.fctb: /parameter/Diameter: \"-6 mm\" must not be negative"),
      std::string::npos);
  EXPECT_NE(bit_error(head + R"({"Diameter": "6 furlongs"}})")
                .find("x.fctb: /parameter/Diameter: \"6 furlongs\": expected a length"),
            std::string::npos);
  EXPECT_NE(bit_error(head + R"({"Diameter": "nan mm"}})").find("/parameter/Diameter"), std::string::npos);
  EXPECT_NE(bit_error(head + R"({"Diameter": "6 mm", "Flutes": 2.5}})").find("x.fctb: /parameter/Flutes: 2.5"),
            std::string::npos);
  EXPECT_NE(bit_error(head + R"({"Diameter": "6 mm"}, "attribute": {"Material": "Diamond"}})")
                .find("x.fctb: /attribute/Material: \"Diamond\": expected \"HSS\" or \"Carbide\""),
            std::string::npos);
  EXPECT_NE(bit_error(head + R"({"Diameter": "6 mm",)").find("x.fctb: malformed JSON"), std::string::npos);
  EXPECT_NE(
      bit_error(R"({"version": 3, "shape": "endmill", "parameter": {"Diameter": 6}})").find("x.fctb: /version: 3"),
      std::string::npos);
  EXPECT_NE(bit_error(R"({"shape": "bullnose.fcstd", "parameter": {"Diameter": "6 mm"}})")
                .find("x.fctb: /parameter/CornerRadius: missing"),
            std::string::npos);
  EXPECT_NE(bit_error(R"({"shape": "v-bit.fcstd", "parameter": {"Diameter": "6 mm"}})")
                .find("x.fctb: /shape: 'v-bit.fcstd' is not a shape millnet models"),
            std::string::npos);
  EXPECT_NE(bit_error(R"({"name": "x", "parameter": {"Diameter": "6 mm"}})").find("x.fctb: /shape: missing"),
            std::string::npos);
}

TEST(FreeCadToolBit, BadLibrariesAreRefusedNamingTheEntry) {
  const tio::BitLoader load = [](const std::string& path) -> tio::BitFile {
    if (path == "em.fctb") return {R"({"shape": "endmill", "parameter": {"Diameter": "6 mm"}})", "Bit/em.fctb"};
    if (path == "bad.fctb") return {R"({"shape": "endmill", "parameter": {}})", "Bit/bad.fctb"};
    throw millnet::Error("bit file '" + path + "' not found");
  };
  auto lib_error = [&](const std::string& text) {
    return error_of([&] { (void)tio::read_freecad_library(text, "shop.fctl", load); });
  };
  EXPECT_NE(lib_error(R"({"tools": [{"nr": 1, "path": "em.fctb"}, {"nr": 1, "path": "em.fctb"}]})")
                .find("shop.fctl: /tools/1/nr: 1 is also /tools/0"),
            std::string::npos);
  EXPECT_NE(lib_error(R"({"tools": [{"nr": 2, "path": "gone.fctb"}]})")
                .find("shop.fctl: /tools/0 (nr 2): bit file 'gone.fctb' not found"),
            std::string::npos);
  EXPECT_NE(lib_error(R"({"tools": [{"nr": 3, "path": "bad.fctb"}]})")
                .find("shop.fctl: /tools/0 (nr 3): Bit/bad.fctb: /parameter/Diameter: missing"),
            std::string::npos);
  EXPECT_NE(lib_error(R"({"tools": [{"nr": -1, "path": "em.fctb"}]})").find("shop.fctl: /tools/0/nr"),
            std::string::npos);
  EXPECT_NE(lib_error(R"({"tools": [{"nr": 1}]})").find("shop.fctl: /tools/0/path: missing"), std::string::npos);
  EXPECT_NE(lib_error(R"({"bits": []})").find("shop.fctl: /tools: expected"), std::string::npos);
  // "nr" as FreeCAD reads it, with int(): "4" is 4.
  const auto ok = tio::read_freecad_library(R"({"tools": [{"nr": "4", "path": "em.fctb"}]})", "shop.fctl", load);
  EXPECT_EQ(ok.tools.at(0).number, 4);
}

// --- Fusion 360 tool library --------------------------------------------------------------------

TEST(FusionToolLibrary, ReadsTheHandWrittenLibrary) {
  const auto imp = tio::import_tool_file(kData / "fusion" / "library.json", tio::ToolFormat::Fusion);
  ASSERT_EQ(imp.tools.size(), 4U);  // the holder entry and the chamfer mill are left out
  const t::Tool& em = numbered(imp, 2);
  EXPECT_EQ(em.id, "10mm-end-mill-ally");
  EXPECT_EQ(em.type, t::ToolType::Flat);
  EXPECT_DOUBLE_EQ(em.diameter_mm, 10);
  EXPECT_EQ(em.flutes, 3);
  EXPECT_DOUBLE_EQ(em.flute_length_mm, 35);
  EXPECT_DOUBLE_EQ(em.stickout_mm, 50);  // LB, the length below the holder
  EXPECT_EQ(em.material, t::ToolMaterial::HSS);
  EXPECT_EQ(em.length_offset, 0);               // length-offset 2 = its number
  EXPECT_DOUBLE_EQ(em.holder_length_mm, 50);    // 20 + 30
  EXPECT_DOUBLE_EQ(em.holder_diameter_mm, 32);  // the largest segment
  const t::Tool& ball = numbered(imp, 3);       // inches
  EXPECT_EQ(ball.type, t::ToolType::Ball);
  EXPECT_DOUBLE_EQ(ball.diameter_mm, 6.35);
  EXPECT_DOUBLE_EQ(ball.corner_radius_mm, 3.175);
  EXPECT_DOUBLE_EQ(ball.flute_length_mm, 12.7);
  EXPECT_DOUBLE_EQ(ball.stickout_mm, 31.75);
  EXPECT_EQ(ball.length_offset, 13);
  EXPECT_EQ(ball.length_offset_register(), 13);
  EXPECT_DOUBLE_EQ(ball.holder_length_mm, 63.5);
  EXPECT_DOUBLE_EQ(ball.holder_diameter_mm, 31.75);
  EXPECT_EQ(ball.description, "1/4 ball (Helical 81608)");
  const t::Tool& bull = numbered(imp, 4);
  EXPECT_EQ(bull.type, t::ToolType::Bull);
  EXPECT_DOUBLE_EQ(bull.corner_radius_mm, 1);
  EXPECT_EQ(bull.flutes, 4);
  EXPECT_EQ(bull.material, t::ToolMaterial::Carbide);
  const t::Tool& drill = numbered(imp, 5);
  EXPECT_EQ(drill.type, t::ToolType::Drill);
  EXPECT_DOUBLE_EQ(drill.diameter_mm, 6.8);
  EXPECT_DOUBLE_EQ(drill.point_angle_deg, 135);
  EXPECT_TRUE(any_note(imp, "left out entries millnet does not model"));
  EXPECT_TRUE(any_note(imp, "1 x chamfer mill, 1 x holder"));
}

TEST(FusionToolLibrary, BadEntriesAreRefusedNamingTheFileAndTheKey) {
  auto fusion_error = [](const std::string& tool) {
    return error_of([&] { (void)tio::read_fusion_library(R"({"data": [)" + tool + "]}", "lib.json"); });
  };
  const std::string ok_geometry = R"("geometry": {"DC": 6, "NOF": 2})";
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "feet", )" + ok_geometry + "}")
                .find("lib.json: /data/0/unit: 'feet': expected \"millimeters\" or \"inches\""),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", )" + ok_geometry + "}").find("lib.json: /data/0/unit: missing"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"NOF": 2}})")
                .find("lib.json: /data/0/geometry/DC: missing"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": "6"}})")
                .find("lib.json: /data/0/geometry/DC: expected a number, got \"6\""),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 6, "LCF": -1}})")
                .find("lib.json: /data/0/geometry/LCF: -1 must not be negative"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 0}})")
                .find("lib.json: /data/0/geometry/DC: the diameter must be > 0"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "bull nose end mill", "unit": "millimeters", )" + ok_geometry + "}")
                .find("lib.json: /data/0/geometry/RE: a bull nose end mill needs its corner radius"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 6, "NOF": 2.5}})")
                .find("lib.json: /data/0/geometry/NOF: expected a whole number in [1, 64], got 2.5"),
            std::string::npos);
  const std::string t2 =
      R"({"type": "drill", "unit": "millimeters", "geometry": {"DC": 5}, "post-process": {"number": 2}})";
  EXPECT_NE(fusion_error(t2 + "," + t2).find("lib.json: /data/1/post-process/number: 2 is also /data/0"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 6},
                            "holder": {"segments": [{"height": 40, "lower-diameter": 4, "upper-diameter": 4}]}})")
                .find("lib.json: /data/0 flat-end-mill: holder diameter 4 mm is narrower than the tool (6 mm)"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 1e999}})")
                .find("lib.json: malformed JSON"),
            std::string::npos);
  EXPECT_NE(fusion_error(R"({"unit": "millimeters"})").find("lib.json: /data/0/type: missing"), std::string::npos);
  EXPECT_NE(fusion_error(R"({"type": "holder"})").find("lib.json: no flat, ball or bull nose end mill or drill"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              (void)tio::read_fusion_library(R"([{"type": "drill"}])", "lib.json");
            }).find("lib.json: /data: expected the library's array"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              (void)tio::read_fusion_library(std::string(70, '[') + std::string(70, ']'), "lib.json");
            }).find("lib.json:1: JSON nested deeper than 64 levels"),
            std::string::npos);
}

TEST(ToolFiles, UnknownFormatAndMissingFileAreNamed) {
  EXPECT_NE(error_of([] { (void)tio::parse_tool_format("heidenhain"); }).find("expected linuxcnc, freecad or fusion"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              (void)tio::import_tool_file("no/such/tool.tbl", tio::ToolFormat::LinuxCnc);
            }).find("no/such/tool.tbl: no such file"),
            std::string::npos);
}
