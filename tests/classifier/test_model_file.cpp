// Model file (classifier_io): bit-exact round trip and clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <unistd.h>

#include "millnet/classifier/network.hpp"
#include "millnet/classifier/io/model_file.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

using namespace millnet;
using namespace millnet::classifier;
using Eigen::MatrixXd;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  fs::path d = fs::temp_directory_path() / ("millnet_classifier_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

bool same_bits(const MatrixXd& a, const MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

Model small_model() {
  std::mt19937_64 rng(77);
  std::normal_distribution<double> N01;
  MatrixXd X(24, 5), Y = MatrixXd::Zero(24, 3);
  std::vector<std::string> g;
  for (Eigen::Index i = 0; i < 24; ++i) {
    for (Eigen::Index k = 0; k < 5; ++k) X(i, k) = 3.0 * static_cast<double>(i % 3) + N01(rng) * 0.3;
    Y(i, i % 3) = 1;
    g.push_back("part " + std::to_string(i / 4) + " \"quoted\" é");
  }
  Model m = train({X, Y, g, {"profile + Z", "3D", "scallöp"}});
  // awkward doubles: must survive text
  m.inputs(0, 0) = 1.0 / 3.0;
  m.inputs(0, 1) = 5e-324;  // smallest subnormal
  m.inputs(0, 2) = -1.7976931348623157e308;
  m.inputs(0, 3) = 0.1 + 0.2;
  m.inputs(0, 4) = -0.0;
  return m;
}

void write(const fs::path& p, const std::string& s) { std::ofstream(p) << s; }

std::string error_of(const fs::path& p) {
  try {
    (void)classifier_io::load_model(p);
  } catch (const millnet::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(ModelFile, RoundTripIsBitExact) {
  const Model m = small_model();
  const fs::path p = temp_dir() / "model.json";
  classifier_io::save_model(m, p);
  const Model r = classifier_io::load_model(p);
  EXPECT_TRUE(same_bits(m.alpha, r.alpha));
  EXPECT_TRUE(same_bits(m.inputs, r.inputs));
  EXPECT_TRUE(same_bits(m.outputs, r.outputs));
  EXPECT_TRUE(same_bits(MatrixXd(m.normalizer.mean), MatrixXd(r.normalizer.mean)));
  EXPECT_TRUE(same_bits(MatrixXd(m.normalizer.std), MatrixXd(r.normalizer.std)));
  EXPECT_EQ(m.groups, r.groups);
  EXPECT_EQ(m.strategies, r.strategies);
  EXPECT_TRUE(same_bits(m.unfamiliar_threshold, r.unfamiliar_threshold));
  ASSERT_EQ(m.loo.curve.size(), r.loo.curve.size());
  for (std::size_t i = 0; i < m.loo.curve.size(); ++i) {
    EXPECT_TRUE(same_bits(m.loo.curve[i].alpha, r.loo.curve[i].alpha));
    EXPECT_TRUE(same_bits(m.loo.curve[i].rms_part, r.loo.curve[i].rms_part));
    EXPECT_TRUE(same_bits(m.loo.curve[i].rms_vector, r.loo.curve[i].rms_vector));
  }
  EXPECT_TRUE(same_bits(m.loo.part.alpha, r.loo.part.alpha));
  EXPECT_TRUE(same_bits(m.loo.vector.rms, r.loo.vector.rms));
  EXPECT_EQ(m.loo.part.edge, r.loo.part.edge);
  EXPECT_EQ(m.loo.mode, r.loo.mode);
  EXPECT_TRUE(same_bits(m.loo.rms_part_at_alpha, r.loo.rms_part_at_alpha));
  EXPECT_TRUE(std::signbit(r.inputs(0, 4)));
  // a loaded model predicts exactly like the original
  const MatrixXd q = m.inputs.bottomRows(5).array() + 0.25;
  EXPECT_TRUE(same_bits(predict(m, q).probabilities, predict(r, q).probabilities));
  // saving again gives the same bytes
  const fs::path p2 = temp_dir() / "model2.json";
  classifier_io::save_model(r, p2);
  EXPECT_EQ(read_file(p), read_file(p2));
}

TEST(ModelFile, BadFilesNameFileAndKey) {
  const fs::path dir = temp_dir();
  const Model m = small_model();
  const fs::path good = dir / "good.json";
  classifier_io::save_model(m, good);
  const std::string text = read_file(good);
  auto variant = [&](const std::string& name, const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    const fs::path p = dir / name;
    write(p, t);
    return error_of(p);
  };
  auto has = [](const std::string& msg, const std::string& part) {
    EXPECT_NE(msg.find(part), std::string::npos) << "message: " << msg << "\nexpected to contain: " << part;
  };
  std::string e = error_of(dir / "missing.json");
  has(e, "missing.json");
  write(dir / "garbage.json", "{\"format\": ");
  e = error_of(dir / "garbage.json");
  has(e, "garbage.json");
  has(e, "not valid JSON");
  e = variant("fmt.json", "\"millnet-model\"", "\"something-else\"");
  has(e, "fmt.json");
  has(e, "format");
  e = variant("ver.json", "\"version\": 1", "\"version\": 2");
  has(e, "version 1");
  has(e, "version 2");
  e = variant("alpha.json", "\"alpha\":", "\"alpha_x\":");
  has(e, "alpha");
  has(e, "missing key");
  e = variant("type.json", "0.3333333333333333", "\"x\"");  // stored.inputs(0, 0) = 1/3
  has(e, "stored.inputs[0][0]");
  has(e, "expected a number, got string");
  e = variant("shape.json", "\"strategies\": [", "\"strategies\": [\"extra\",");
  has(e, "stored.outputs[0]");
  has(e, "expected 4 numbers");
  // the good file still loads
  EXPECT_NO_THROW((void)classifier_io::load_model(good));
  fs::remove_all(dir);
}

TEST(ModelFile, FeaturesAreOneAddedKeyThatRoundTrips) {
  const fs::path dir = temp_dir();
  Model m = small_model();  // 5 inputs: a 2×2 grid and the aspect
  classifier_io::save_model(m, dir / "bare.json");
  EXPECT_FALSE(classifier_io::load_model(dir / "bare.json").input_spec.has_value());
  m.input_spec = InputSpec{0.5, 2, true};
  classifier_io::save_model(m, dir / "features.json");
  const Model r = classifier_io::load_model(dir / "features.json");
  ASSERT_TRUE(r.input_spec.has_value());
  EXPECT_EQ(*r.input_spec, *m.input_spec);
  // The file is the one without features plus the "features" object (keys sorted: after "alpha").
  std::string expect = read_file(dir / "bare.json");
  const auto at = expect.find("\n \"format\"");
  ASSERT_NE(at, std::string::npos);
  expect.insert(
      at,
      "\n \"features\": {\n  \"aspect_feature\": true,\n  \"grid\": 2,\n  \"inputs\": 5,\n  \"raster_mm\": 0.5\n },");
  EXPECT_EQ(read_file(dir / "features.json"), expect);
  // A spec that does not describe the stored inputs is refused on save and on load.
  Model wrong = m;
  wrong.input_spec = InputSpec{0.5, 3, false};
  EXPECT_THROW(classifier_io::save_model(wrong, dir / "wrong.json"), millnet::Error);
  std::string text = read_file(dir / "features.json");
  text.replace(text.find("\"grid\": 2"), 9, "\"grid\": 3");
  write(dir / "grid.json", text);
  std::string e = error_of(dir / "grid.json");
  EXPECT_NE(e.find("grid.json: features.inputs: expected 10 (grid² + 1), got 5"), std::string::npos) << e;
  text = read_file(dir / "features.json");
  text.replace(text.find("\"raster_mm\": 0.5"), 17, "\"raster_mm\": -1.0");
  write(dir / "raster.json", text);
  e = error_of(dir / "raster.json");
  EXPECT_NE(e.find("raster.json: features.raster_mm: expected a number > 0"), std::string::npos) << e;
  fs::remove_all(dir);
}

// Issue 39 §3: a model that learns from the wall share says how many copies follow the heights
// (2×2 grid + 1 copy = the small model's 5 inputs); a count that does not make the stored width is
// refused, naming it.
TEST(ModelFile, TheWallShareCopiesRoundTripAndMustMakeTheStoredWidth) {
  const fs::path dir = temp_dir();
  Model m = small_model();
  m.input_spec = InputSpec{0.5, 2, false, 1};
  classifier_io::save_model(m, dir / "wall.json");
  const Model r = classifier_io::load_model(dir / "wall.json");
  ASSERT_TRUE(r.input_spec.has_value());
  EXPECT_EQ(r.input_spec->wall_share_copies, 1);
  EXPECT_EQ(*r.input_spec, *m.input_spec);
  std::string text = read_file(dir / "wall.json");
  ASSERT_NE(text.find("\"wall_share_copies\": 1"), std::string::npos) << text;
  text.replace(text.find("\"wall_share_copies\": 1"), 22, "\"wall_share_copies\": 2");
  write(dir / "two.json", text);
  const std::string e = error_of(dir / "two.json");
  EXPECT_NE(e.find("two.json: features.inputs: expected 6 (grid² + 2), got 5"), std::string::npos) << e;
  fs::remove_all(dir);
}

TEST(ModelFile, NonFiniteIsRefusedAndNothingIsWritten) {
  Model m = small_model();
  m.inputs(2, 2) = std::numeric_limits<double>::quiet_NaN();
  const fs::path p = temp_dir() / "nan.json";
  fs::remove(p);
  EXPECT_THROW(classifier_io::save_model(m, p), millnet::Error);
  EXPECT_FALSE(fs::exists(p));
  fs::remove_all(temp_dir());
}
