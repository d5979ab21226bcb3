// Model-vector table: CSV round trip bit for bit, manifest contents, and clear errors on bad CSV.
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/datasets/io/manifest.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

namespace fs = std::filesystem;
using namespace millnet::datasets;
using millnet::datasets_io::write_table;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millnet_test_datasets_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Table small_table(int n, bool aspect) {
  Table t;
  t.grid_n = n;
  t.has_aspect = aspect;
  const double awkward[] = {
      0.1, 1e-300, -0.0, 1.0 / 3.0, 5e-324, std::numeric_limits<double>::max(), -2.5e17, 123.456789012345678};
  int k = 0;
  for (int r = 0; r < 3; ++r) {
    Row row;
    row.id = "part,\"" + std::to_string(r) + "\"#" + std::to_string(r + 1);  // needs quoting
    row.source = r < 2 ? "p1" : "p 2";
    row.label = r + 1;
    row.axis = r == 2 ? millnet::augment::Axis::Y : millnet::augment::Axis::X;
    row.angle_deg = -50.0 + 10.0 * r + 0.1;
    row.flip = r == 1;
    for (int i = 0; i < n * n; ++i) row.inputs.push_back(awkward[k++ % 8] * (i % 3 ? 1 : -1));
    row.outputs = one_hot(row.label);
    row.aspect = 1.0 / (r + 3.0);
    t.rows.push_back(row);
  }
  return t;
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

std::string error_of(const fs::path& p) {
  try {
    (void)read_table(p);
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Table, HeaderIsExactlyTheDocumentedColumns) {
  const auto cols = column_names(15, false);
  ASSERT_EQ(cols.size(), 6u + 225u + 8u);
  EXPECT_EQ(cols[0], "id");
  EXPECT_EQ(cols[5], "flip");
  EXPECT_EQ(cols[6], "in_1_1");
  EXPECT_EQ(cols[7], "in_1_2");
  EXPECT_EQ(cols[6 + 15], "in_2_1");  // row-major: row = y
  EXPECT_EQ(cols[6 + 224], "in_15_15");
  EXPECT_EQ(cols[231], "out_1");
  EXPECT_EQ(cols[238], "out_8");
  EXPECT_EQ(column_names(15, true).back(), "aspect");
}

TEST(Table, StrategyNamesAreThePapersFivePlusThreeSpare) {
  const auto s = default_strategy_names();
  EXPECT_EQ(s[0], "profile + Z finishing, slope mode");
  EXPECT_EQ(s[3], "Z-level finishing");
  EXPECT_EQ(s[4], "profile finishing, equidistant, constant in-feed");
  EXPECT_EQ(s[5], "spare 6");
  EXPECT_EQ(s[7], "spare 8");
}

TEST(Table, OneHot) {
  const auto o = one_hot(3);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(o[k], k == 2 ? 1.0 : 0.0);
  for (double v : one_hot(0)) EXPECT_EQ(v, 0.0);
  EXPECT_THROW((void)one_hot(9), millnet::Error);
}

TEST(Table, RoundTripIsBitForBitIncludingAwkwardDoubles) {
  for (const bool aspect : {false, true}) {
    const Table t = small_table(4, aspect);
    const fs::path d = temp_dir(aspect ? "rt_aspect" : "rt");
    write_table(t, d);
    const Table u = read_table(d / "vectors.csv");
    ASSERT_EQ(u.grid_n, 4);
    ASSERT_EQ(u.has_aspect, aspect);
    ASSERT_EQ(u.rows.size(), t.rows.size());
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const Row &a = t.rows[r], &b = u.rows[r];
      EXPECT_EQ(a.id, b.id);
      EXPECT_EQ(a.source, b.source);
      EXPECT_EQ(a.label, b.label);
      EXPECT_EQ(a.axis, b.axis);
      EXPECT_EQ(a.flip, b.flip);
      EXPECT_TRUE(same_bits(a.angle_deg, b.angle_deg));
      ASSERT_EQ(b.inputs.size(), 16u);
      for (std::size_t k = 0; k < 16; ++k) EXPECT_TRUE(same_bits(a.inputs[k], b.inputs[k])) << r << "," << k;
      for (std::size_t k = 0; k < 8; ++k) EXPECT_TRUE(same_bits(a.outputs[k], b.outputs[k]));
      if (aspect) {
        EXPECT_TRUE(same_bits(a.aspect, b.aspect));
      }
    }
    // -0.0 keeps its sign (inputs[2] is awkward[2] = -0.0 times +1).
    ASSERT_TRUE(std::signbit(t.rows[0].inputs[2]));
    EXPECT_TRUE(std::signbit(u.rows[0].inputs[2]));
    // Writing what was read gives the same bytes.
    EXPECT_EQ(table_csv(u), millnet::read_file(d / "vectors.csv"));
  }
}

// Issue 39 §3: the optional wall_share column (after aspect when both are there) round-trips bit for
// bit, the manifest says it is there, and a share outside [0, 1] names its line and column.
TEST(Table, TheWallShareColumnRoundTripsAndIsChecked) {
  for (const bool aspect : {false, true}) {
    Table t = small_table(4, aspect);
    t.has_wall_share = true;
    for (std::size_t r = 0; r < t.rows.size(); ++r) t.rows[r].wall_share = 0.1 * static_cast<double>(r % 3) + 1e-17;
    const fs::path d = temp_dir(aspect ? "rt_wall_aspect" : "rt_wall");
    write_table(t, d);
    const std::string csv = millnet::read_file(d / "vectors.csv");
    EXPECT_NE(csv.substr(0, csv.find('\n')).rfind(aspect ? ",out_8,aspect,wall_share" : ",out_8,wall_share"),
              std::string::npos);
    const Table u = read_table(d / "vectors.csv");
    ASSERT_TRUE(u.has_wall_share);
    ASSERT_EQ(u.has_aspect, aspect);
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      EXPECT_TRUE(same_bits(t.rows[r].wall_share, u.rows[r].wall_share)) << r;
      if (aspect) {
        EXPECT_TRUE(same_bits(t.rows[r].aspect, u.rows[r].aspect)) << r;
      }
    }
    EXPECT_EQ(table_csv(u), csv);
    EXPECT_NE(millnet::read_file(d / "manifest.json").find("\"wall_share_column\": true"), std::string::npos);
    std::string bad = csv;
    const auto eol = bad.find('\n', bad.find('\n') + 1);  // the first row ends with its wall share
    bad.replace(bad.rfind(',', eol) + 1, eol - bad.rfind(',', eol) - 1, "1.5");
    const fs::path b = d / "bad.csv";
    millnet::write_file_atomic(b, bad);
    try {
      (void)read_table(b);
      ADD_FAILURE() << "a wall share of 1.5 was read";
    } catch (const millnet::Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.csv:2: "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("'wall_share'"), std::string::npos) << e.what();
    }
  }
}

TEST(Table, ManifestHasCountsHashesAndStrategies) {
  Table t = small_table(3, false);
  t.sources.push_back({"p1", "parts/p1.stl", 1, 0x0123456789abcdefULL, 1234, 20, 1});
  t.config_json = R"({"grid": 3})";
  const fs::path d = temp_dir("manifest");
  write_table(t, d);
  const auto m = nlohmann::json::parse(millnet::read_file(d / "manifest.json"));
  EXPECT_EQ(m["counts"]["rows"], 3);
  EXPECT_EQ(m["counts"]["parts"], 2);
  EXPECT_EQ(m["counts"]["rows_per_label"]["2"], 1);
  EXPECT_EQ(m["grid"], 3);
  EXPECT_EQ(m["inputs"], 9);
  EXPECT_EQ(m["strategies"].size(), 8u);
  EXPECT_EQ(m["strategies"][1], "3D/profile finishing");
  EXPECT_EQ(m["input_files"][0]["fnv1a64"], "0123456789abcdef");
  EXPECT_EQ(m["input_files"][0]["bytes"], 1234);
  EXPECT_EQ(m["config"]["grid"], 3);
  EXPECT_FALSE(m["program_version"].get<std::string>().empty());
  // The manifest's hash is the hash of the CSV on disk.
  EXPECT_EQ(m["csv_fnv1a64"], to_hex(fnv1a64(millnet::read_file(d / "vectors.csv"))));
}

TEST(Hash, Fnv1a64KnownValues) {
  // Reference values of the FNV-1a 64 specification (Fowler/Noll/Vo test vectors).
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
  EXPECT_EQ(fnv1a64("bar", fnv1a64("foo")), fnv1a64("foobar"));
  EXPECT_EQ(to_hex(0xaf63dc4c8601ec8cULL), "af63dc4c8601ec8c");
}

TEST(Table, BadCsvErrorsNameFileLineAndColumn) {
  const fs::path d = temp_dir("bad");
  write_table(small_table(2, false), d);
  const std::string good = millnet::read_file(d / "vectors.csv");
  const auto lines = [&] {
    std::vector<std::string> v;
    std::size_t p = 0;
    while (p < good.size()) {
      const auto e = good.find('\n', p);
      v.push_back(good.substr(p, e - p));
      p = e + 1;
    }
    return v;
  }();
  ASSERT_EQ(lines.size(), 4u);
  auto write = [&](const std::string& name, std::vector<std::string> ls) {
    std::string s;
    for (auto& l : ls) s += l + "\n";
    millnet::write_file_atomic(d / name, s);
    return (d / name);
  };
  // Wrong column count on line 3.
  {
    auto ls = lines;
    ls[2] += ",7";
    const auto p = write("extra.csv", ls);
    const auto e = error_of(p);
    EXPECT_NE(e.find(p.string() + ":3:"), std::string::npos) << e;
    EXPECT_NE(e.find("fields"), std::string::npos) << e;
  }
  // Non-number in column in_2_1 on line 4.
  {
    auto ls = lines;
    const auto header = column_names(2, false);
    auto& l = ls[3];
    // Replace field 8 (in_2_1) of 18, found from the end (the quoted id contains a comma).
    std::size_t p = l.size();
    for (int k = 0; k < 10; ++k) p = l.rfind(',', p - 1);
    ++p;
    const auto q = l.find(',', p);
    l = l.substr(0, p) + "abc" + l.substr(q);
    const auto f = write("nan.csv", ls);
    const auto e = error_of(f);
    EXPECT_NE(e.find(f.string() + ":4:"), std::string::npos) << e;
    EXPECT_NE(e.find("in_2_1"), std::string::npos) << e;
    EXPECT_NE(e.find("abc"), std::string::npos) << e;
  }
  // Missing header column out_8.
  {
    auto ls = lines;
    ls[0] = ls[0].substr(0, ls[0].rfind(','));
    const auto f = write("noout8.csv", ls);
    const auto e = error_of(f);
    EXPECT_NE(e.find(f.string() + ":1:"), std::string::npos) << e;
    EXPECT_NE(e.find("out_8"), std::string::npos) << e;
  }
  // Missing grid column in_1_2.
  {
    auto ls = lines;
    auto& h = ls[0];
    const auto p = h.find("in_1_2,");
    h.erase(p, 7);
    const auto f = write("noin12.csv", ls);
    const auto e = error_of(f);
    EXPECT_NE(e.find(":1:"), std::string::npos) << e;
    EXPECT_NE(e.find("missing column 'in_1_2'"), std::string::npos) << e;
  }
  // Misspelled fixed column.
  {
    auto ls = lines;
    ls[0].replace(ls[0].find("label"), 5, "lable");
    const auto e = error_of(write("lable.csv", ls));
    EXPECT_NE(e.find("'lable', expected 'label'"), std::string::npos) << e;
  }
  // Label that disagrees with the one-hot outputs, label out of range, bad axis, bad flip.
  {
    auto ls = lines;
    ls[1].replace(ls[1].find(",1,x,"), 5, ",2,x,");
    const auto e = error_of(write("label.csv", ls));
    EXPECT_NE(e.find(":2:"), std::string::npos) << e;
    EXPECT_NE(e.find("disagrees"), std::string::npos) << e;
  }
  {
    auto ls = lines;
    ls[1].replace(ls[1].find(",1,x,"), 5, ",9,x,");
    EXPECT_NE(error_of(write("label9.csv", ls)).find("column 'label'"), std::string::npos);
  }
  {
    auto ls = lines;
    ls[1].replace(ls[1].find(",1,x,"), 5, ",1,q,");
    EXPECT_NE(error_of(write("axis.csv", ls)).find("column 'axis'"), std::string::npos);
  }
  // Duplicate id, empty file, no rows, missing file.
  {
    auto ls = lines;
    ls.push_back(ls[1]);
    const auto e = error_of(write("dup.csv", ls));
    EXPECT_NE(e.find(":5:"), std::string::npos) << e;
    EXPECT_NE(e.find("duplicate id"), std::string::npos) << e;
  }
  EXPECT_NE(error_of(write("header_only.csv", {lines[0]})).find("no rows"), std::string::npos);
  EXPECT_NE(error_of(d / "does_not_exist.csv").find("does_not_exist.csv"), std::string::npos);
}

TEST(Table, WriteRefusesInconsistentRows) {
  Table t = small_table(2, false);
  t.rows[1].inputs.pop_back();
  const fs::path d = temp_dir("inconsistent");
  EXPECT_THROW(write_table(t, d), millnet::Error);
  Table u = small_table(2, false);
  u.rows[2].id = u.rows[0].id;
  EXPECT_THROW((void)table_csv(u), millnet::Error);
  // Nothing was left behind by the refused write.
  EXPECT_FALSE(fs::exists(d / "vectors.csv"));
  EXPECT_FALSE(fs::exists(d / "manifest.json"));
}
