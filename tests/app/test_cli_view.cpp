// millnet view as a user runs it: the page of any G-code file (one or several programs), the same
// bytes twice, and one clear line with nothing written for an unreadable program, a missing file or
// a bad tool.
#include "app/cli_runner.hpp"
#include "millnet/report/page_data.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;

nlohmann::json page_data(const fs::path& html) { return nlohmann::json::parse(report::page_data_json(slurp(html))); }

int lines_of(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(CliView, PageOfOneAndOfTwoProgramsSameBytesTwice) {
  const fs::path d = fresh_dir("cli_view");
  std::ofstream(d / "a.nc") << "G21 G90 G17\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F100\nG1 X20 F600\nG2 X20 Y10 I0 J5\nG0 Z5\nM30\n";
  std::ofstream(d / "b.nc") << "G21 G90 G17\nG0 Z5\nG0 X5 Y5\nG1 Z-2 F100\nG1 X15 F500\nG0 Z5\nM30\n";
  const auto r = run_millnet("view a.nc --tool ball:4 --quiet --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = page_data(d / "o" / "a.html");
  ASSERT_EQ(j["programs"].size(), 1u);
  EXPECT_EQ(j["programs"][0]["moves"], 6);
  EXPECT_EQ(j["tool"]["d"], 4);
  EXPECT_EQ(j["tool"]["r"], 2);
  EXPECT_EQ(j["programs"][0]["text"]["4"], "G1 Z-1 F100");
  const std::string first = slurp(d / "o" / "a.html");
  ASSERT_EQ(run_millnet("view a.nc --tool ball:4 --quiet --out o", d).code, 0);
  EXPECT_EQ(slurp(d / "o" / "a.html"), first);
  const auto two = run_millnet("view a.nc b.nc --quiet --out o2", d);
  ASSERT_EQ(two.code, 0) << two.err;
  const auto j2 = page_data(d / "o2" / "a.html");
  ASSERT_EQ(j2["programs"].size(), 2u);
  EXPECT_NE(j2["programs"][0]["colour"], j2["programs"][1]["colour"]);
}

TEST(CliView, BadInputGetsOneLineAndNoPage) {
  const fs::path d = fresh_dir("cli_view_bad");
  std::ofstream(d / "bad.nc") << "G21 G90 G17\nG1 X1 Q7 F100\nM30\n";
  std::ofstream(d / "a.nc") << "G21\nG0 Z5\nM30\n";
  const auto bad = run_millnet("view bad.nc --out o", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(lines_of(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("bad.nc"), std::string::npos) << bad.err;
  const auto missing = run_millnet("view nothere.nc --out o", d);
  EXPECT_EQ(missing.code, 1);
  EXPECT_EQ(lines_of(missing.err), 1) << missing.err;
  EXPECT_NE(missing.err.find("nothere.nc"), std::string::npos) << missing.err;
  const auto tool = run_millnet("view a.nc --tool sphere:2 --out o", d);
  EXPECT_EQ(tool.code, 1);
  EXPECT_EQ(lines_of(tool.err), 1) << tool.err;
  EXPECT_NE(tool.err.find("--tool"), std::string::npos) << tool.err;
  EXPECT_EQ(list_files(d / "o"), "");
}

}  // namespace
}  // namespace millnet::testing
