// End-to-end tests of the learning commands through the built executable: `sample` on an analytic
// ramp, `dataset` (columns, determinism across runs and thread counts), `train` (model keys checked
// against statistics the test computes itself from vectors.csv, LOO curve, filtration/verification
// table) and `predict` on files, a folder and a broken file in one batch.
#include "cli_runner.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace {

namespace fs = std::filesystem;
using millnet::testing::fresh_dir;
using millnet::testing::list_files;
using millnet::testing::run_millnet;
using millnet::testing::slurp;
using nlohmann::json;

using Csv = std::vector<std::vector<std::string>>;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string c;
  std::istringstream in(line);
  while (std::getline(in, c, ',')) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

Csv read_csv(const fs::path& p) {
  Csv rows;
  std::istringstream in(slurp(p));
  std::string line;
  while (std::getline(in, line)) rows.push_back(split(line));
  return rows;
}

std::size_t column(const std::vector<std::string>& head, const std::string& name) {
  for (std::size_t k = 0; k < head.size(); ++k)
    if (head[k] == name) return k;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

bool is_png(const fs::path& p) {
  const cv::Mat m = cv::imread(p.string(), cv::IMREAD_UNCHANGED);
  return !m.empty() && m.cols > 50 && m.rows > 50;
}

/// A small, fast learning config: the generator's five families, 2 parts each at resolution 40,
/// three rotations about x (no flip) ⇒ 30 vectors; prediction with two rotations about z.
void write_config(const fs::path& dir) {
  std::ofstream(dir / "c.json") << R"({
  "seed": 7,
  "dataset": {
    "parts_dir": "parts",
    "generate": {"seed": 11, "per_family": 2, "resolution": 40},
    "augment": {"angles_deg": [-10, 0, 10], "axes": ["x"], "flip": false}
  },
  "train": {"loo": "part"},
  "predict": {"augment": {"angles_deg": [0, 10], "axes": ["z"], "flip": false}}
})";
}

void write_file(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

}  // namespace

TEST(CliLearn, SampleWritesTheAnalyticRampGrid) {
  // A tilted plane z = 0.5·x + 0.25·y over [0,30]×[0,20] (ASCII STL): heights above its lowest point
  // (0 at the origin) are linear, so the raster + bilinear grid must be exact:
  // row i ↔ y = 20·i/14 (min y first), column j ↔ x = 30·j/14 (min x first).
  const auto d = fresh_dir("cli_learn_sample");
  std::ofstream(d / "ramp.stl") << "solid ramp\n"
                                   "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 30 0 15\nvertex 30 20 20\n"
                                   "endloop\nendfacet\n"
                                   "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 30 20 20\nvertex 0 20 5\n"
                                   "endloop\nendfacet\nendsolid ramp\n";
  const auto r = run_millnet("sample --mesh ramp.stl --quiet --out S", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Csv g = read_csv(d / "S" / "ramp.grid.csv");
  ASSERT_EQ(g.size(), 15u);
  double worst = 0;
  for (std::size_t i = 0; i < 15; ++i) {
    ASSERT_EQ(g[i].size(), 15u) << "row " << i;
    for (std::size_t j = 0; j < 15; ++j) {
      const double expect = 0.5 * 30.0 * static_cast<double>(j) / 14 + 0.25 * 20.0 * static_cast<double>(i) / 14;
      worst = std::max(worst, std::abs(std::stod(g[i][j]) - expect));
    }
  }
  // A linear surface is reproduced exactly by the raster and the bilinear grid, edges included
  // (the grid spans the footprint corner to corner); only rounding remains.
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(std::stod(g[7][7]), 0.5 * 15 + 0.25 * 10, 1e-6);  // an interior point: exact
  EXPECT_TRUE(is_png(d / "S" / "ramp.png"));
  // The 3D page (issue 16): the grid as a surface of 15 × 15 nodes, cells of 30/14 × 20/14 mm
  // centred on the nodes, so the first node sits at the footprint's corner (0, 0).
  const std::string page = slurp(d / "S" / "ramp.html");
  const auto surf = page.find("\"surface\":{");
  ASSERT_NE(surf, std::string::npos);
  const auto num_after = [&](const std::string& key) {
    const auto k = page.find("\"" + key + "\":", surf);
    return k == std::string::npos ? std::nan("") : std::stod(page.substr(k + key.size() + 3, 24));
  };
  EXPECT_EQ(num_after("rows"), 15);
  EXPECT_EQ(num_after("cols"), 15);
  constexpr double kPageMm = 5e-4 + 1e-12;  // the page writes mm to 0.001
  EXPECT_NEAR(num_after("cell"), 30.0 / 14, kPageMm);
  EXPECT_NEAR(num_after("celly"), 20.0 / 14, kPageMm);
  EXPECT_NEAR(num_after("x0") + 0.5 * 30.0 / 14, 0, kPageMm);
  EXPECT_NEAR(num_after("y0") + 0.5 * 20.0 / 14, 0, kPageMm);
  EXPECT_NE(page.find("\"layer\":\"height grid\"", surf), std::string::npos);
  // --grid changes the shape; the same command gives the same bytes.
  ASSERT_EQ(run_millnet("sample --mesh ramp.stl --grid 5 --quiet --out S5", d).code, 0);
  const Csv g5 = read_csv(d / "S5" / "ramp.grid.csv");
  ASSERT_EQ(g5.size(), 5u);
  EXPECT_EQ(g5[0].size(), 5u);
  EXPECT_NEAR(std::stod(g5[2][2]), 0.5 * 15 + 0.25 * 10, 1e-6);
  ASSERT_EQ(run_millnet("sample --mesh ramp.stl --quiet --out S2", d).code, 0);
  EXPECT_EQ(slurp(d / "S" / "ramp.grid.csv"), slurp(d / "S2" / "ramp.grid.csv"));
}

TEST(CliLearn, DatasetTrainPredictEndToEnd) {
  const auto d = fresh_dir("cli_learn_e2e");
  write_config(d);

  // ---- dataset: columns, determinism across runs and thread counts.
  auto r = run_millnet("dataset --config c.json --quiet --out D", d);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(d / "D" / "manifest.json")) << list_files(d / "D");
  EXPECT_TRUE(json::parse(slurp(d / "D" / "manifest.json")).is_object());
  const std::string vectors = slurp(d / "D" / "vectors.csv");
  const Csv table = read_csv(d / "D" / "vectors.csv");
  ASSERT_GE(table.size(), 2u);
  const auto& head = table[0];
  const std::vector<std::string> first = {"id", "source", "label", "axis", "angle", "flip", "in_1_1"};
  ASSERT_GE(head.size(), first.size() + 8);
  EXPECT_EQ(std::vector<std::string>(head.begin(), head.begin() + 7), first);
  const std::size_t c_in = column(head, "in_1_1"), c_last_in = column(head, "in_15_15"), c_out1 = column(head, "out_1"),
                    c_out8 = column(head, "out_8"), c_source = column(head, "source"), c_label = column(head, "label"),
                    c_angle = column(head, "angle");
  EXPECT_EQ(c_last_in - c_in + 1, 225u);
  EXPECT_EQ(c_out8 - c_out1 + 1, 8u);
  // 5 families × 2 parts × 3 angles; every row one-hot at its label; three variants per source.
  const std::size_t n = table.size() - 1;
  EXPECT_EQ(n, 30u);
  std::map<std::string, int> per_source, label_of;
  for (std::size_t i = 1; i < table.size(); ++i) {
    const auto& row = table[i];
    ASSERT_EQ(row.size(), head.size()) << "row " << i;
    ++per_source[row[c_source]];
    const int label = std::stoi(row[c_label]);
    label_of[row[c_source]] = label;
    for (std::size_t k = 0; k < 8; ++k)
      EXPECT_EQ(std::stod(row[c_out1 + k]), k + 1 == static_cast<std::size_t>(label) ? 1.0 : 0.0);
    double lo = 1e300;
    for (std::size_t k = c_in; k <= c_last_in; ++k) lo = std::min(lo, std::stod(row[k]));
    EXPECT_GE(lo, -1e-9) << "heights are above the part's lowest point";
    const double angle = std::stod(row[c_angle]);
    EXPECT_TRUE(angle == -10 || angle == 0 || angle == 10) << angle;
  }
  EXPECT_EQ(per_source.size(), 10u);
  for (const auto& [s, k] : per_source) EXPECT_EQ(k, 3) << s;
  r = run_millnet("dataset --config c.json --quiet --out D2", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(slurp(d / "D2" / "vectors.csv") == vectors) << "second run differs";
  ASSERT_EQ(run_millnet("dataset --config c.json --threads 1 --quiet --out T1", d).code, 0);
  ASSERT_EQ(run_millnet("dataset --config c.json --threads 2 --quiet --out T2", d).code, 0);
  EXPECT_TRUE(slurp(d / "T1" / "vectors.csv") == slurp(d / "T2" / "vectors.csv")) << "threads 1 vs 2 differ";
  EXPECT_TRUE(slurp(d / "T1" / "vectors.csv") == vectors);

  // ---- train: model keys against the test's own statistics of vectors.csv.
  r = run_millnet("train --dataset D/vectors.csv --config c.json --quiet --out M", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const json model = json::parse(slurp(d / "M" / "model.json"));
  ASSERT_TRUE(model.contains("alpha"));
  EXPECT_GT(model["alpha"].get<double>(), 0);
  ASSERT_TRUE(model.contains("strategies"));
  EXPECT_EQ(model["strategies"].size(), 8u);
  ASSERT_TRUE(model.contains("normalizer") && model["normalizer"].contains("mean") &&
              model["normalizer"].contains("std"));
  const auto& mean = model["normalizer"]["mean"];
  const auto& sd = model["normalizer"]["std"];
  ASSERT_EQ(mean.size(), 225u);
  ASSERT_EQ(sd.size(), 225u);
  for (std::size_t k : {std::size_t{0}, std::size_t{112}, std::size_t{224}}) {
    double s = 0, s2 = 0;
    for (std::size_t i = 1; i < table.size(); ++i) s += std::stod(table[i][c_in + k]);
    const double mu = s / static_cast<double>(n);
    for (std::size_t i = 1; i < table.size(); ++i) s2 += std::pow(std::stod(table[i][c_in + k]) - mu, 2);
    EXPECT_NEAR(mean[k].get<double>(), mu, 1e-9 * (1 + std::abs(mu))) << "input " << k;
    // Population or sample standard deviation (both are z-scores; the model must carry one of them).
    const double pop = std::sqrt(s2 / static_cast<double>(n)), smp = std::sqrt(s2 / static_cast<double>(n - 1));
    const double got = sd[k].get<double>();
    EXPECT_TRUE(std::abs(got - pop) < 1e-9 * (1 + pop) || std::abs(got - smp) < 1e-9 * (1 + smp))
        << "input " << k << ": std " << got << " vs " << pop << " / " << smp;
  }
  // LOO curve.
  const Csv curve = read_csv(d / "M" / "loo_curve.csv");
  ASSERT_GE(curve.size(), 10u) << "a scan of at least 9 alphas";
  ASSERT_GE(curve[0].size(), 2u);
  EXPECT_EQ(curve[0][0], "alpha");
  EXPECT_EQ(curve[0][1], "rms");
  for (std::size_t i = 2; i < curve.size(); ++i) EXPECT_GT(std::stod(curve[i][0]), std::stod(curve[i - 1][0]));
  // Filtration / verification: one row per vector, outputs summing to 1 (one-hot outputs averaged
  // with normalized weights).
  const Csv ver = read_csv(d / "M" / "verification.csv");
  ASSERT_EQ(ver.size(), n + 1);
  std::vector<std::string> expect_head = {"id", "source"};
  for (int k = 1; k <= 8; ++k) expect_head.push_back("filtration_" + std::to_string(k));
  for (int k = 1; k <= 8; ++k) expect_head.push_back("verification_" + std::to_string(k));
  EXPECT_EQ(ver[0], expect_head);
  for (std::size_t i = 1; i < ver.size(); ++i) {
    ASSERT_EQ(ver[i].size(), 18u);
    EXPECT_EQ(ver[i][1], table[i][c_source]);
    double f = 0, v = 0;
    for (std::size_t k = 0; k < 8; ++k) {
      f += std::stod(ver[i][2 + k]);
      v += std::stod(ver[i][10 + k]);
    }
    EXPECT_NEAR(f, 1, 1e-6) << "row " << i;
    EXPECT_NEAR(v, 1, 1e-6) << "row " << i;
  }

  // ---- predict: two files, a folder, one broken file; the batch goes on.
  fs::create_directories(d / "folder");
  fs::copy_file(d / "parts" / (per_source.begin()->first + ".stl"), d / "part1.stl");
  const std::string in_folder_a = std::next(per_source.begin(), 3)->first,
                    in_folder_b = std::next(per_source.begin(), 7)->first;
  fs::copy_file(d / "parts" / (in_folder_a + ".stl"), d / "folder" / (in_folder_a + ".stl"));
  fs::copy_file(d / "parts" / (in_folder_b + ".stl"), d / "folder" / (in_folder_b + ".stl"));
  {
    std::ofstream junk(d / "junk.stl", std::ios::binary);
    for (int i = 0; i < 700; ++i) junk.put(static_cast<char>((i * 131) % 253));
  }
  r = run_millnet("predict --model M --config c.json --quiet --out P part1.stl folder/ junk.stl", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("junk.stl"), std::string::npos) << r.err;
  const json pred = json::parse(slurp(d / "P" / "predictions.json"));
  ASSERT_EQ(pred["parts"].size(), 4u);
  std::map<std::string, json> by_name;
  for (const auto& p : pred["parts"]) by_name[p["part"].get<std::string>()] = p;
  ASSERT_TRUE(by_name.count("junk"));
  EXPECT_EQ(by_name["junk"]["status"], "error");
  EXPECT_FALSE(fs::exists(d / "P" / "junk.png"));
  const std::map<std::string, std::string> good = {
      {"part1", per_source.begin()->first}, {in_folder_a, in_folder_a}, {in_folder_b, in_folder_b}};
  for (const auto& [name, source] : good) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(by_name.count(name)) << pred.dump().substr(0, 500);
    const json& p = by_name[name];
    EXPECT_EQ(p["status"], "ok");
    EXPECT_TRUE(is_png(d / "P" / (name + ".png"))) << list_files(d / "P");
    // The z-rotation by 0° is the same sampling as the stored x-rotation by 0°: distance 0 to it.
    EXPECT_NEAR(p["d2_min"].get<double>(), 0, 1e-9);
    EXPECT_FALSE(p["unfamiliar"].get<bool>());
    // A training part is recognised as its own family.
    EXPECT_EQ(p["top"].get<int>(), label_of[source]);
    const double c = p["consistency"].get<double>();
    EXPECT_TRUE(c == 0.5 || c == 1.0) << c;  // two variants
  }
  const Csv pcsv = read_csv(d / "P" / "predictions.csv");
  EXPECT_EQ(pcsv.size(), 5u);
  EXPECT_EQ(pcsv[0][0], "part");
}

TEST(CliLearn, ModelFolderDescribesItself) {
  const auto d = fresh_dir("cli_learn_model_folder");
  write_config(d);
  ASSERT_EQ(run_millnet("dataset --config c.json --quiet --out D", d).code, 0);
  auto r = run_millnet("train --dataset D/vectors.csv --config c.json --quiet --out M", d);
  ASSERT_EQ(r.code, 0) << r.err;
  // model.json carries sampling.json's raster and grid under "features".
  const json model = json::parse(slurp(d / "M" / "model.json"));
  const json sampling = json::parse(slurp(d / "M" / "sampling.json"));
  ASSERT_TRUE(model.contains("features")) << model.dump().substr(0, 300);
  EXPECT_EQ(model["features"]["grid"], sampling["grid"]);
  EXPECT_EQ(model["features"]["raster_mm"].get<double>(), sampling["raster_mm"].get<double>());
  EXPECT_EQ(model["features"]["inputs"], sampling["inputs"]);
  EXPECT_EQ(model["features"]["aspect_feature"], false);

  fs::copy_file(d / "parts" / (fs::directory_iterator(d / "parts")->path().filename()), d / "part.stl");
  r = run_millnet("predict --model M --config c.json --quiet --out P part.stl", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string reference = slurp(d / "P" / "predictions.csv");
  const auto folder = [&](const std::string& name) {
    fs::copy(d / "M", d / name);
    return d / name;
  };
  // model.json's features win: no sampling.json, or a wrong one, predicts the same.
  fs::remove(folder("M_self") / "sampling.json");
  write_file(folder("M_wrong") / "sampling.json", R"({"grid": 5, "raster_mm": 7})");
  for (const std::string m : {"M_self", "M_wrong"}) {
    r = run_millnet("predict --model " + m + " --config c.json --quiet --out P_" + m + " part.stl", d);
    EXPECT_EQ(r.code, 0) << m << ": " << r.err;
    EXPECT_EQ(slurp(d / ("P_" + m) / "predictions.csv"), reference) << m;
  }
  // A folder from before "features": sampling.json is read (a wrong one now breaks the prediction).
  json old = model;
  old.erase("features");
  write_file(folder("M_old") / "model.json", old.dump(1) + "\n");
  write_file(folder("M_old_wrong") / "model.json", old.dump(1) + "\n");
  write_file(d / "M_old_wrong" / "sampling.json", R"({"grid": 5, "raster_mm": 7})");
  r = run_millnet("predict --model M_old --config c.json --quiet --out P_old part.stl", d);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(d / "P_old" / "predictions.csv"), reference);
  r = run_millnet("predict --model M_old_wrong --config c.json --quiet --out P_old_wrong part.stl", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(slurp(d / "P_old_wrong" / "predictions.csv"), reference);
  // Neither features nor sampling.json: the error names the file and the key.
  fs::remove(folder("M_none") / "sampling.json");
  write_file(d / "M_none" / "model.json", old.dump(1) + "\n");
  r = run_millnet("predict --model M_none --config c.json --quiet --out P_none part.stl", d);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("sampling.json"), std::string::npos) << r.err;
}
