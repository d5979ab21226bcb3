#include "millnet/datasets/io/labels.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

namespace millnet::datasets_io {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

struct LabelReader {
  std::string file;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw file_error(file, key + ": " + what);
  }
  const Json& at(const Json& obj, const std::string& key, const std::string& path) const {
    if (!obj.is_object())
      fail(path.empty() ? "(top level)" : path, std::string("expected an object, got ") + obj.type_name());
    const auto it = obj.find(key);
    if (it == obj.end()) fail(path.empty() ? key : path + "." + key, "missing key");
    return *it;
  }
  static std::string key(const std::string& path, const std::string& k) { return path.empty() ? k : path + "." + k; }
  std::string text(const Json& o, const std::string& k, const std::string& path) const {
    const Json& j = at(o, k, path);
    if (!j.is_string()) fail(key(path, k), std::string("expected a string, got ") + j.type_name());
    return j.get<std::string>();
  }
  long long integer(const Json& o, const std::string& k, const std::string& path, long long lo, long long hi) const {
    const Json& j = at(o, k, path);
    if (!j.is_number_integer()) fail(key(path, k), std::string("expected an integer, got ") + j.type_name());
    const auto v = j.get<long long>();
    if (v < lo || v > hi)
      fail(key(path, k), "expected " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(v));
    return v;
  }
  /// A number, or null for NaN where `nullable`.
  double number(const Json& o, const std::string& k, const std::string& path, bool nullable = false) const {
    const Json& j = at(o, k, path);
    if (nullable && j.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!j.is_number()) fail(key(path, k), std::string("expected a number, got ") + j.type_name());
    return j.get<double>();
  }
  bool boolean(const Json& o, const std::string& k, const std::string& path) const {
    const Json& j = at(o, k, path);
    if (!j.is_boolean()) fail(key(path, k), std::string("expected true or false, got ") + j.type_name());
    return j.get<bool>();
  }
  const Json& array(const Json& o, const std::string& k, const std::string& path) const {
    const Json& j = at(o, k, path);
    if (!j.is_array()) fail(key(path, k), std::string("expected an array, got ") + j.type_name());
    return j;
  }
};

Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json parse_settings(const std::string& text, const std::string& what) {
  try {
    return Json::parse(text);
  } catch (const std::exception& e) {
    throw Error(what + ": the settings are not valid JSON (" + json_error_text(e.what()) + ")");
  }
}

PartLabel part_of(const LabelReader& rd, const Json& j, const std::string& at) {
  PartLabel p;
  p.name = rd.text(j, "name", at);
  p.fnv1a64 = rd.text(j, "fnv1a64", at);
  p.bytes = static_cast<std::uintmax_t>(rd.integer(j, "bytes", at, 0, std::numeric_limits<long long>::max()));
  p.best = static_cast<int>(rd.integer(j, "best", at, 1, datasets::kStrategySlots));
  const Json& ss = rd.array(j, "strategies", at);
  for (std::size_t k = 0; k < ss.size(); ++k) {
    const std::string sat = at + ".strategies[" + std::to_string(k) + "]";
    StrategyLabel s;
    s.strategy = static_cast<int>(rd.integer(ss[k], "strategy", sat, 1, datasets::kStrategySlots));
    s.rank = static_cast<int>(rd.integer(ss[k], "rank", sat, 1, datasets::kStrategySlots));
    s.score = rd.number(ss[k], "score", sat);
    if (!(s.score >= 0 && s.score <= 1)) rd.fail(sat + ".score", "expected a number in [0, 1]");
    s.time_min = rd.number(ss[k], "time_kinematic_min", sat);
    s.spec_share = rd.number(ss[k], "spec_share", sat, true);
    s.meets_spec = rd.boolean(ss[k], "meets_spec", sat);
    s.max_gouge_mm = rd.number(ss[k], "max_gouge_mm", sat);
    s.ra_median_um = rd.number(ss[k], "ra_median_um", sat, true);
    s.ra_p90_um = rd.number(ss[k], "ra_p90_um", sat, true);
    s.uncut_area_mm2 = rd.number(ss[k], "uncut_area_mm2", sat);
    s.regret = rd.number(ss[k], "regret", sat, true);
    p.strategies.push_back(s);
  }
  return p;
}

Json part_json(const PartLabel& p) {
  Json ss = Json::array();
  for (const StrategyLabel& s : p.strategies)
    ss.push_back(Json{{"strategy", s.strategy},
                      {"rank", s.rank},
                      {"score", s.score},
                      {"time_kinematic_min", s.time_min},
                      {"spec_share", number_or_null(s.spec_share)},
                      {"meets_spec", s.meets_spec},
                      {"max_gouge_mm", s.max_gouge_mm},
                      {"ra_median_um", number_or_null(s.ra_median_um)},
                      {"ra_p90_um", number_or_null(s.ra_p90_um)},
                      {"uncut_area_mm2", s.uncut_area_mm2},
                      {"regret", number_or_null(s.regret)}});
  return Json{{"name", p.name}, {"fnv1a64", p.fnv1a64}, {"bytes", p.bytes}, {"best", p.best}, {"strategies", ss}};
}

}  // namespace

std::array<double, datasets::kStrategySlots> PartLabel::outputs() const {
  std::array<double, datasets::kStrategySlots> out{};
  for (const StrategyLabel& s : strategies)
    if (s.strategy >= 1 && s.strategy <= static_cast<int>(datasets::kStrategySlots))
      out[static_cast<std::size_t>(s.strategy - 1)] = s.score;
  return out;
}

const PartLabel* LabelFile::find(const std::string& name, const std::string& fnv1a64, std::uintmax_t bytes) const {
  for (const PartLabel& p : parts)
    if (p.name == name && p.fnv1a64 == fnv1a64 && p.bytes == bytes) return &p;
  return nullptr;
}

LabelFile read_labels(const fs::path& path) {
  const std::string text = read_file(path);
  check_json_nesting(text, path.string());
  Json j;
  try {
    j = Json::parse(text);
  } catch (const std::exception& e) {
    throw file_error(path.string(), "not valid JSON (" + json_error_text(e.what()) + ")");
  }
  const LabelReader rd{path.string()};
  if (rd.text(j, "format", "") != "millnet-labels") rd.fail("format", "expected \"millnet-labels\"");
  rd.integer(j, "format_version", "", kLabelsFormatVersion, kLabelsFormatVersion);
  LabelFile f;
  f.aim = rd.text(j, "aim", "");
  const Json& settings = rd.at(j, "settings", "");
  if (!settings.is_object()) rd.fail("settings", std::string("expected an object, got ") + settings.type_name());
  f.settings_json = settings.dump();
  const Json& parts = rd.array(j, "parts", "");
  for (std::size_t i = 0; i < parts.size(); ++i)
    f.parts.push_back(part_of(rd, parts[i], "parts[" + std::to_string(i) + "]"));
  return f;
}

std::string labels_text(const LabelFile& labels) {
  Json parts = Json::array();
  for (const PartLabel& p : labels.parts) parts.push_back(part_json(p));
  const Json j{{"format", "millnet-labels"},
               {"format_version", kLabelsFormatVersion},
               {"aim", labels.aim},
               {"settings", parse_settings(labels.settings_json, "labels")},
               {"parts", parts}};
  return j.dump(1) + "\n";
}

std::string part_label_text(const PartLabel& label) { return part_json(label).dump(); }

PartLabel parse_part_label(const std::string& text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const std::exception& e) {
    throw Error(source + ": not valid JSON (" + json_error_text(e.what()) + ")");
  }
  return part_of(LabelReader{source}, j, "");
}

void write_labels(const fs::path& path, const LabelFile& labels) { write_file_atomic(path, labels_text(labels)); }

}  // namespace millnet::datasets_io
