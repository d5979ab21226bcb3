#include "millnet/classifier/io/model_file.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"

namespace millnet::classifier_io {

using classifier::Edge;
using classifier::LooMode;
using classifier::Model;
using classifier::ModeOptimum;
using Eigen::Index;
using json = nlohmann::json;

namespace {

double finite(double v, const char* key) {
  if (!std::isfinite(v)) throw Error(std::string("save_model: ") + key + " is not finite (JSON cannot hold it)");
  return v;
}

json row_array(const Eigen::MatrixXd& M, Index r, const char* key) {
  json a = json::array();
  for (Index c = 0; c < M.cols(); ++c) a.push_back(finite(M(r, c), key));
  return a;
}

json matrix(const Eigen::MatrixXd& M, const char* key) {
  json a = json::array();
  for (Index r = 0; r < M.rows(); ++r) a.push_back(row_array(M, r, key));
  return a;
}

json optimum(const ModeOptimum& o) {
  return {{"alpha", finite(o.alpha, "loo optimum alpha")},
          {"rms", finite(o.rms, "loo optimum rms")},
          {"accuracy", finite(o.accuracy, "loo optimum accuracy")},
          {"edge", classifier::to_string(o.edge)},
          {"refine_evaluations", o.refine_evaluations}};
}

// Reader with the key path in every message.
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw file_error(file, key + ": " + what);
  }
  static std::string type_name(const json& j) { return j.type_name(); }
  const json& at(const json& obj, const std::string& key, const std::string& path) const {
    if (!obj.is_object()) fail(path.empty() ? "(top level)" : path, "expected an object, got " + type_name(obj));
    auto it = obj.find(key);
    const std::string full = path.empty() ? key : path + "." + key;
    if (it == obj.end()) fail(full, "missing key");
    return *it;
  }
  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number, got " + type_name(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "expected a finite number");
    return v;
  }
  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, got " + type_name(j));
    return j.get<std::string>();
  }
  const json& array(const json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, "expected an array, got " + type_name(j));
    return j;
  }
  Eigen::RowVectorXd vec(const json& j, const std::string& path, Index expect) const {
    array(j, path);
    if (expect >= 0 && static_cast<Index>(j.size()) != expect)
      fail(path, "expected " + std::to_string(expect) + " numbers, got " + std::to_string(j.size()));
    Eigen::RowVectorXd v(static_cast<Index>(j.size()));
    for (std::size_t i = 0; i < j.size(); ++i)
      v(static_cast<Index>(i)) = number(j[i], path + "[" + std::to_string(i) + "]");
    return v;
  }
  Eigen::MatrixXd mat(const json& j, const std::string& path, Index rows, Index cols) const {
    array(j, path);
    if (static_cast<Index>(j.size()) != rows)
      fail(path, "expected " + std::to_string(rows) + " rows, got " + std::to_string(j.size()));
    Eigen::MatrixXd M(rows, cols);
    for (Index r = 0; r < rows; ++r)
      M.row(r) = vec(j[static_cast<std::size_t>(r)], path + "[" + std::to_string(r) + "]", cols);
    return M;
  }
  std::vector<std::string> strings(const json& j, const std::string& path) const {
    array(j, path);
    std::vector<std::string> v;
    for (std::size_t i = 0; i < j.size(); ++i) v.push_back(string(j[i], path + "[" + std::to_string(i) + "]"));
    return v;
  }
  int integer(const json& j, const std::string& path) const {
    if (!j.is_number_integer()) fail(path, "expected an integer, got " + type_name(j));
    return j.get<int>();
  }
  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, "expected true or false, got " + type_name(j));
    return j.get<bool>();
  }
  Edge edge(const json& j, const std::string& path) const {
    const std::string s = string(j, path);
    if (s == "none") return Edge::None;
    if (s == "low") return Edge::Low;
    if (s == "high") return Edge::High;
    fail(path, "expected \"none\", \"low\" or \"high\", got \"" + s + "\"");
  }
  classifier::InputSpec input_spec(const json& j, const std::string& path, Index stored_inputs) const {
    classifier::InputSpec s;
    s.raster_mm = number(at(j, "raster_mm", path), path + ".raster_mm");
    if (!(s.raster_mm > 0)) fail(path + ".raster_mm", "expected a number > 0");
    s.grid = integer(at(j, "grid", path), path + ".grid");
    if (s.grid < 2) fail(path + ".grid", "expected an integer ≥ 2, got " + std::to_string(s.grid));
    s.aspect_feature = boolean(at(j, "aspect_feature", path), path + ".aspect_feature");
    if (j.contains("wall_share_copies")) {
      s.wall_share_copies = integer(at(j, "wall_share_copies", path), path + ".wall_share_copies");
      if (s.wall_share_copies < 1 || s.wall_share_copies > 1000)
        fail(path + ".wall_share_copies", "expected an integer in 1..1000, got " + std::to_string(s.wall_share_copies));
    }
    const int inputs = integer(at(j, "inputs", path), path + ".inputs");
    if (inputs != s.inputs())
      fail(path + ".inputs", "expected " + std::to_string(s.inputs()) + " (grid²" + (s.aspect_feature ? " + 1" : "") +
                                 (s.wall_share_copies > 0 ? " + " + std::to_string(s.wall_share_copies) : "") +
                                 "), got " + std::to_string(inputs));
    if (inputs != stored_inputs)
      fail(path + ".inputs",
           std::to_string(inputs) + " differs from the stored inputs' width " + std::to_string(stored_inputs));
    return s;
  }
  ModeOptimum optimum(const json& j, const std::string& path) const {
    ModeOptimum o;
    o.alpha = number(at(j, "alpha", path), path + ".alpha");
    o.rms = number(at(j, "rms", path), path + ".rms");
    o.accuracy = number(at(j, "accuracy", path), path + ".accuracy");
    o.edge = edge(at(j, "edge", path), path + ".edge");
    o.refine_evaluations = integer(at(j, "refine_evaluations", path), path + ".refine_evaluations");
    return o;
  }
};

}  // namespace

void save_model(const Model& m, const std::filesystem::path& path) {
  const Index n = m.inputs.rows(), d = m.inputs.cols(), k = m.outputs.cols();
  if (m.outputs.rows() != n || static_cast<Index>(m.groups.size()) != n ||
      static_cast<Index>(m.strategies.size()) != k || m.normalizer.mean.size() != d || m.normalizer.std.size() != d)
    throw Error("save_model: inconsistent model shapes (inputs, outputs, groups, strategies, normalizer)");
  json j;
  j["format"] = "millnet-model";
  j["version"] = kModelFormatVersion;
  j["alpha"] = finite(m.alpha, "alpha");
  j["strategies"] = m.strategies;
  j["normalizer"] = {{"mean", row_array(m.normalizer.mean, 0, "normalizer.mean")},
                     {"std", row_array(m.normalizer.std, 0, "normalizer.std")}};
  j["stored"] = {{"inputs", matrix(m.inputs, "stored.inputs")},
                 {"outputs", matrix(m.outputs, "stored.outputs")},
                 {"groups", m.groups}};
  if (m.input_spec) {
    const classifier::InputSpec& s = *m.input_spec;
    if (s.inputs() != d)
      throw Error("save_model: the input spec's " + std::to_string(s.inputs()) +
                  " inputs differ from the stored inputs' " + std::to_string(d));
    j["features"] = {{"raster_mm", finite(s.raster_mm, "features.raster_mm")},
                     {"grid", s.grid},
                     {"inputs", s.inputs()},
                     {"aspect_feature", s.aspect_feature}};
    if (s.wall_share_copies > 0) j["features"]["wall_share_copies"] = s.wall_share_copies;  // older readers: absent
  }
  j["unfamiliar"] = {{"threshold", finite(m.unfamiliar_threshold, "unfamiliar.threshold")},
                     {"factor", finite(m.unfamiliar_factor, "unfamiliar.factor")},
                     {"percentile", finite(m.unfamiliar_percentile, "unfamiliar.percentile")}};
  json curve = json::array();
  for (const auto& p : m.loo.curve)
    curve.push_back({{"alpha", finite(p.alpha, "loo.curve.alpha")},
                     {"rms_part", finite(p.rms_part, "loo.curve.rms_part")},
                     {"rms_vector", finite(p.rms_vector, "loo.curve.rms_vector")},
                     {"accuracy_part", finite(p.accuracy_part, "loo.curve.accuracy_part")},
                     {"accuracy_vector", finite(p.accuracy_vector, "loo.curve.accuracy_vector")}});
  const auto& L = m.loo;
  j["loo"] = {{"mode", classifier::to_string(L.mode)},
              {"alpha", finite(L.alpha, "loo.alpha")},
              {"d2_scale", finite(L.d2_scale, "loo.d2_scale")},
              {"curve", curve},
              {"part", optimum(L.part)},
              {"vector", optimum(L.vector)},
              {"rms_part_at_alpha", finite(L.rms_part_at_alpha, "loo.rms_part_at_alpha")},
              {"rms_vector_at_alpha", finite(L.rms_vector_at_alpha, "loo.rms_vector_at_alpha")},
              {"accuracy_part_at_alpha", finite(L.accuracy_part_at_alpha, "loo.accuracy_part_at_alpha")},
              {"accuracy_vector_at_alpha", finite(L.accuracy_vector_at_alpha, "loo.accuracy_vector_at_alpha")},
              {"full_passes", L.full_passes},
              {"neighbour_cache_used", L.neighbour_cache_used}};
  j["criterion"] = classifier::to_string(m.criterion);
  if (!m.regret_curve.empty()) {
    json rc = json::array();
    for (const auto& [a, r] : m.regret_curve)
      rc.push_back(
          {{"alpha", finite(a, "regret_curve.alpha")}, {"mean_regret", finite(r, "regret_curve.mean_regret")}});
    j["regret_curve"] = rc;
  }
  const classifier::Calibration& c = m.calibration;
  j["calibration"] = {{"raw", c.raw},
                      {"right", c.right},
                      {"prior", c.prior},
                      {"threshold", finite(c.threshold, "calibration.threshold")}};
  if (!m.target_json.empty()) {
    try {
      j["target"] = json::parse(m.target_json);
    } catch (const json::exception& e) {
      throw Error(std::string("save_model: the target is not valid JSON (") + json_error_text(e.what()) + ")");
    }
  }
  // nlohmann writes doubles as the shortest text that round-trips (tested bit for bit).
  write_file_atomic(path, j.dump(1) + "\n");
}

Model load_model(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  check_json_nesting(text, path.string());
  Reader rd{path.string()};
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw file_error(path.string(), "not valid JSON (" + json_error_text(e.what()) + ")");
  }
  if (!j.is_object()) rd.fail("(top level)", "expected an object, got " + Reader::type_name(j));
  if (rd.string(rd.at(j, "format", ""), "format") != "millnet-model")
    rd.fail("format", "expected \"millnet-model\", got \"" + j["format"].get<std::string>() + "\"");
  const int version = rd.integer(rd.at(j, "version", ""), "version");
  if (version != kModelFormatVersion)
    rd.fail("version", "this millnet reads model format version " + std::to_string(kModelFormatVersion) +
                           ", the file is version " + std::to_string(version));
  Model m;
  m.alpha = rd.number(rd.at(j, "alpha", ""), "alpha");
  if (!(m.alpha > 0)) rd.fail("alpha", "expected a number > 0");
  m.strategies = rd.strings(rd.at(j, "strategies", ""), "strategies");
  const auto k = static_cast<Index>(m.strategies.size());
  if (k < 1) rd.fail("strategies", "expected at least one strategy name");
  const json& nz = rd.at(j, "normalizer", "");
  m.normalizer.mean = rd.vec(rd.at(nz, "mean", "normalizer"), "normalizer.mean", -1);
  const Index d = m.normalizer.mean.size();
  if (d < 1) rd.fail("normalizer.mean", "expected at least one number");
  m.normalizer.std = rd.vec(rd.at(nz, "std", "normalizer"), "normalizer.std", d);
  for (Index c = 0; c < d; ++c)
    if (!(m.normalizer.std(c) > 0)) rd.fail("normalizer.std[" + std::to_string(c) + "]", "expected a number > 0");
  const json& st = rd.at(j, "stored", "");
  m.groups = rd.strings(rd.at(st, "groups", "stored"), "stored.groups");
  const auto n = static_cast<Index>(m.groups.size());
  if (n < 1) rd.fail("stored.groups", "expected at least one stored vector");
  m.inputs = rd.mat(rd.at(st, "inputs", "stored"), "stored.inputs", n, d);
  m.outputs = rd.mat(rd.at(st, "outputs", "stored"), "stored.outputs", n, k);
  const json& un = rd.at(j, "unfamiliar", "");
  m.unfamiliar_threshold = rd.number(rd.at(un, "threshold", "unfamiliar"), "unfamiliar.threshold");
  m.unfamiliar_factor = rd.number(rd.at(un, "factor", "unfamiliar"), "unfamiliar.factor");
  m.unfamiliar_percentile = rd.number(rd.at(un, "percentile", "unfamiliar"), "unfamiliar.percentile");
  if (j.contains("features")) m.input_spec = rd.input_spec(j["features"], "features", d);
  const json& lo = rd.at(j, "loo", "");
  auto& L = m.loo;
  const std::string mode = rd.string(rd.at(lo, "mode", "loo"), "loo.mode");
  if (mode != "part" && mode != "vector") rd.fail("loo.mode", "expected \"part\" or \"vector\", got \"" + mode + "\"");
  L.mode = classifier::loo_mode_from_string(mode);
  L.alpha = rd.number(rd.at(lo, "alpha", "loo"), "loo.alpha");
  L.d2_scale = rd.number(rd.at(lo, "d2_scale", "loo"), "loo.d2_scale");
  const json& curve = rd.array(rd.at(lo, "curve", "loo"), "loo.curve");
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const std::string p = "loo.curve[" + std::to_string(i) + "]";
    classifier::CurvePoint c;
    c.alpha = rd.number(rd.at(curve[i], "alpha", p), p + ".alpha");
    c.rms_part = rd.number(rd.at(curve[i], "rms_part", p), p + ".rms_part");
    c.rms_vector = rd.number(rd.at(curve[i], "rms_vector", p), p + ".rms_vector");
    c.accuracy_part = rd.number(rd.at(curve[i], "accuracy_part", p), p + ".accuracy_part");
    c.accuracy_vector = rd.number(rd.at(curve[i], "accuracy_vector", p), p + ".accuracy_vector");
    L.curve.push_back(c);
  }
  L.part = rd.optimum(rd.at(lo, "part", "loo"), "loo.part");
  L.vector = rd.optimum(rd.at(lo, "vector", "loo"), "loo.vector");
  L.rms_part_at_alpha = rd.number(rd.at(lo, "rms_part_at_alpha", "loo"), "loo.rms_part_at_alpha");
  L.rms_vector_at_alpha = rd.number(rd.at(lo, "rms_vector_at_alpha", "loo"), "loo.rms_vector_at_alpha");
  L.accuracy_part_at_alpha = rd.number(rd.at(lo, "accuracy_part_at_alpha", "loo"), "loo.accuracy_part_at_alpha");
  L.accuracy_vector_at_alpha = rd.number(rd.at(lo, "accuracy_vector_at_alpha", "loo"), "loo.accuracy_vector_at_alpha");
  L.full_passes = rd.integer(rd.at(lo, "full_passes", "loo"), "loo.full_passes");
  L.neighbour_cache_used = rd.boolean(rd.at(lo, "neighbour_cache_used", "loo"), "loo.neighbour_cache_used");
  // Written since issue 39; absent from older files (Rms, no calibration, no target).
  if (j.contains("criterion")) {
    const std::string c = rd.string(j["criterion"], "criterion");
    if (c != "rms" && c != "regret") rd.fail("criterion", "expected \"rms\" or \"regret\", got \"" + c + "\"");
    m.criterion = c == "regret" ? classifier::Criterion::Regret : classifier::Criterion::Rms;
  }
  if (j.contains("regret_curve")) {
    const json& rc = rd.array(j["regret_curve"], "regret_curve");
    for (std::size_t i = 0; i < rc.size(); ++i) {
      const std::string p = "regret_curve[" + std::to_string(i) + "]";
      m.regret_curve.emplace_back(rd.number(rd.at(rc[i], "alpha", p), p + ".alpha"),
                                  rd.number(rd.at(rc[i], "mean_regret", p), p + ".mean_regret"));
    }
  }
  if (j.contains("calibration")) {
    const json& cj = j["calibration"];
    classifier::Calibration& c = m.calibration;
    const Eigen::RowVectorXd raw = rd.vec(rd.at(cj, "raw", "calibration"), "calibration.raw", -1);
    const Eigen::RowVectorXd right = rd.vec(rd.at(cj, "right", "calibration"), "calibration.right", raw.size());
    const Eigen::RowVectorXd prior =
        rd.vec(rd.at(cj, "prior", "calibration"), "calibration.prior", raw.size() == 0 ? -1 : k);
    c.raw.assign(raw.data(), raw.data() + raw.size());
    c.right.assign(right.data(), right.data() + right.size());
    c.prior.assign(prior.data(), prior.data() + prior.size());
    for (std::size_t i = 0; i < c.right.size(); ++i)
      if (!(c.right[i] >= 0 && c.right[i] <= 1) || (i > 0 && (c.raw[i] < c.raw[i - 1] || c.right[i] < c.right[i - 1])))
        rd.fail("calibration", "expected ascending raw values and non-decreasing shares in [0, 1]");
    c.threshold = rd.number(rd.at(cj, "threshold", "calibration"), "calibration.threshold");
  }
  if (j.contains("target")) {
    if (!j["target"].is_object()) rd.fail("target", "expected an object, got " + Reader::type_name(j["target"]));
    m.target_json = j["target"].dump();
  }
  return m;
}

}  // namespace millnet::classifier_io
