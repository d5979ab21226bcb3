// The dataset manifest (datasets_io, its one owner): exact bytes, write → read round trip, and errors
// that name the file and the key.
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/datasets/io/manifest.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using namespace millnet::datasets;
using namespace millnet::datasets_io;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millnet_test_manifest_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Two rows of a 2×2 grid from two parts, labels 1 and 3, one source file, a config echo.
Table tiny_table() {
  Table t;
  t.grid_n = 2;
  for (std::size_t k = 0; k < t.strategies.size(); ++k) t.strategies[k] = std::string(1, 's') + std::to_string(k + 1);
  t.strategies[0] = "a \"b\" \\ c";  // escaped in the manifest
  for (int r = 0; r < 2; ++r) {
    Row row;
    row.id = "r" + std::to_string(r);
    row.source = r == 0 ? "a" : "b";
    row.label = r == 0 ? 1 : 3;
    row.inputs = {0, 1, 2, 3.5};
    row.outputs = one_hot(row.label);
    t.rows.push_back(row);
  }
  t.sources.push_back({"a", "parts/a.stl", 1, 0xff, 84, 2, 1});
  t.config_json = R"({"grid": 2, "raster_mm": 0.5})";
  return t;
}

std::string error_of(const fs::path& p) {
  try {
    (void)read_manifest(p);
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Manifest, ExactBytes) {
  const Table t = tiny_table();
  const fs::path d = temp_dir("bytes");
  write_table(t, d);
  const std::string csv = millnet::read_file(d / "vectors.csv");
  EXPECT_EQ(csv, table_csv(t));
  const std::string expect =
      "{\n"
      "  \"format\": \"millnet-vectors\",\n"
      "  \"format_version\": 1,\n"
      "  \"program\": \"millnet\",\n"
      "  \"program_version\": \"" +
      manifest_of(t, csv).program_version +
      "\",\n"
      "  \"csv\": \"vectors.csv\",\n"
      "  \"csv_fnv1a64\": \"" +
      to_hex(fnv1a64(csv)) +
      "\",\n"
      "  \"csv_bytes\": " +
      std::to_string(csv.size()) +
      ",\n"
      "  \"grid\": 2,\n"
      "  \"inputs\": 4,\n"
      "  \"outputs\": 8,\n"
      "  \"aspect_column\": false,\n"
      "  \"counts\": {\"rows\": 2, \"parts\": 2, \"rows_per_label\": {\"1\": 1, \"3\": 1}},\n"
      "  \"strategies\": [\"a \\\"b\\\" \\\\ c\", \"s2\", \"s3\", \"s4\", \"s5\", \"s6\", \"s7\", \"s8\"],\n"
      "  \"hash\": \"fnv1a64\",\n"
      "  \"input_files\": [\n"
      "    {\"name\": \"a\", \"file\": \"parts/a.stl\", \"label\": 1, \"fnv1a64\": \"00000000000000ff\", \"bytes\": "
      "84, "
      "\"triangles\": 2, \"degenerate_triangles\": 1}\n"
      "  ],\n"
      "  \"config\": {\"grid\": 2, \"raster_mm\": 0.5}\n"
      "}\n";
  EXPECT_EQ(millnet::read_file(d / "manifest.json"), expect);
  EXPECT_FALSE(manifest_of(t, csv).program_version.empty());
}

TEST(Manifest, WriteThenReadGivesTheSameFields) {
  const Table t = tiny_table();
  const fs::path d = temp_dir("round_trip");
  write_table(t, d);
  const Manifest written = manifest_of(t, table_csv(t));
  const Manifest read = read_manifest(d / "manifest.json");
  // The config echo comes back as the same JSON value (compact text); every other field as written.
  EXPECT_EQ(nlohmann::json::parse(read.config_json), nlohmann::json::parse(written.config_json));
  Manifest same_text = read;
  same_text.config_json = written.config_json;
  EXPECT_EQ(same_text, written);
  // …and the fields are the table's.
  EXPECT_EQ(read.grid, 2);
  EXPECT_EQ(read.rows, 2u);
  EXPECT_EQ(read.parts, 2u);
  EXPECT_EQ(read.rows_per_label, (std::map<int, std::size_t>{{1, 1}, {3, 1}}));
  EXPECT_EQ(read.strategies[0], "a \"b\" \\ c");
  EXPECT_EQ(read.strategies.size(), 8u);
  ASSERT_EQ(read.input_files.size(), 1u);
  EXPECT_EQ(read.input_files[0], (ManifestFile{"a", "parts/a.stl", 1, "00000000000000ff", 84, 2, 1}));
  ASSERT_TRUE(read.raster_mm.has_value());
  EXPECT_EQ(*read.raster_mm, 0.5);
  EXPECT_EQ(read.csv_fnv1a64, to_hex(fnv1a64(millnet::read_file(d / "vectors.csv"))));

  // Without a config echo: "config": null, no raster, the same round trip.
  Table bare = tiny_table();
  bare.config_json.clear();
  bare.sources.clear();
  write_table(bare, d);
  const Manifest b = read_manifest(d / "manifest.json");
  EXPECT_EQ(b, manifest_of(bare, table_csv(bare)));
  EXPECT_EQ(b.config_json, "null");
  EXPECT_FALSE(b.raster_mm.has_value());
}

TEST(Manifest, ErrorsNameTheFileAndTheKey) {
  const fs::path d = temp_dir("errors");
  write_table(tiny_table(), d);
  const auto good = nlohmann::json::parse(millnet::read_file(d / "manifest.json"));
  const auto with = [&](const std::string& name, const auto& edit) {
    nlohmann::json j = good;
    edit(j);
    millnet::write_file_atomic(d / name, j.dump());
    return error_of(d / name);
  };
  const auto contains = [](const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; };
  std::string e = with("a.json", [](auto& j) { j["counts"]["rows"] = "two"; });
  EXPECT_TRUE(contains(e, "a.json: counts.rows: expected a count, got string")) << e;
  e = with("b.json", [](auto& j) { j["input_files"][0].erase("bytes"); });
  EXPECT_TRUE(contains(e, "b.json: input_files[0].bytes: missing key")) << e;
  e = with("c.json", [](auto& j) { j["format"] = "millnet-model"; });
  EXPECT_TRUE(contains(e, "c.json: format: expected \"millnet-vectors\", got \"millnet-model\"")) << e;
  e = with("d.json", [](auto& j) { j["format_version"] = 2; });
  EXPECT_TRUE(contains(e, "d.json: format_version: this millnet reads manifest version 1, the file is version 2")) << e;
  e = with("e.json", [](auto& j) { j["config"]["raster_mm"] = "fine"; });
  EXPECT_TRUE(contains(e, "e.json: config.raster_mm: expected a number, got string")) << e;
  e = with("f.json", [](auto& j) { j["counts"]["rows_per_label"]["x"] = 1; });
  EXPECT_TRUE(contains(e, "f.json: counts.rows_per_label.x: expected a label number as the key")) << e;
  millnet::write_file_atomic(d / "g.json", "{\"format\": ");
  EXPECT_TRUE(contains(error_of(d / "g.json"), "g.json: not valid JSON")) << error_of(d / "g.json");
  EXPECT_TRUE(contains(error_of(d / "none.json"), "none.json: no such file"));
}

// The streamed table (issue 10: rank 0 writes rows as they come in) is write_table's bytes, and it
// leaves nothing when it is not finished.
TEST(TableWriter, StreamedRowsAreWriteTablesBytes) {
  Table t = tiny_table();
  t.has_aspect = true;
  t.rows[1].aspect = 1.25;
  t.labelling_json = R"({"aim": "ra"})";
  const fs::path a = temp_dir("writer_whole"), b = temp_dir("writer_stream");
  write_table(t, a);
  {
    TableWriter w(b, t.grid_n, t.has_aspect, t.strategies);
    for (const Row& r : t.rows) w.add(r);
    EXPECT_EQ(w.rows(), 2u);
    EXPECT_FALSE(fs::exists(b / "vectors.csv"));  // a temporary until finish()
    w.finish(t.sources, t.config_json, t.labelling_json);
  }
  EXPECT_EQ(millnet::read_file(a / "vectors.csv"), millnet::read_file(b / "vectors.csv"));
  EXPECT_EQ(millnet::read_file(a / "manifest.json"), millnet::read_file(b / "manifest.json"));
}

TEST(TableWriter, RefusesRowsItCannotVouchForAndLeavesNothingUnfinished) {
  const Table t = tiny_table();
  const fs::path d = temp_dir("writer_bad");
  {
    TableWriter w(d, t.grid_n, false, t.strategies);
    w.add(t.rows[0]);
    EXPECT_THROW(w.add(t.rows[0]), millnet::Error);  // the same id twice
    w.add(t.rows[1]);
    Row back = t.rows[0];
    back.id = "r9";
    EXPECT_THROW(w.add(back), millnet::Error);  // source "a" again after "b": not consecutive
    Row short_row = t.rows[1];
    short_row.id = "r8";
    short_row.inputs.pop_back();
    EXPECT_THROW(w.add(short_row), millnet::Error);  // 3 inputs for a 2×2 grid
  }
  EXPECT_TRUE(fs::is_empty(d)) << "an unfinished writer left a file";
}
