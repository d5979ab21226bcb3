// JSON parsing and typed access for the FreeCAD and Fusion readers.
#include "json_access.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"

#include <cmath>

namespace millnet::tooling::io::detail {

Json parse_json(std::string_view text, const std::string& source) {
  check_size(text.size(), source);
  check_json_nesting(text, source);
  try {
    return Json::parse(text.begin(), text.end());
  } catch (const Json::exception& e) {
    throw file_error(source, "malformed JSON: " + json_error_text(e.what()));
  }
}

std::string shown_json(const Json& v) {
  if (v.is_string()) return "\"" + shown(v.get<std::string>()) + "\"";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return shown(v.dump());
}

const Json* member(const Json& obj, const std::string& key, const std::string& source, const std::string& at) {
  if (!obj.is_object()) throw file_error(source, at + ": expected an object, got " + shown_json(obj));
  const auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return nullptr;
  return &*it;
}

std::optional<double> opt_number(const Json& obj, const std::string& key, const std::string& source,
                                 const std::string& at) {
  const Json* v = member(obj, key, source, at);
  if (!v) return std::nullopt;
  if (!v->is_number() || !std::isfinite(v->get<double>()))
    throw file_error(source, at + "/" + key + ": expected a number, got " + shown_json(*v));
  return v->get<double>();
}

std::optional<std::string> opt_string(const Json& obj, const std::string& key, const std::string& source,
                                      const std::string& at) {
  const Json* v = member(obj, key, source, at);
  if (!v) return std::nullopt;
  if (!v->is_string()) throw file_error(source, at + "/" + key + ": expected a string, got " + shown_json(*v));
  return v->get<std::string>();
}

std::optional<int> opt_int(const Json& obj, const std::string& key, const std::string& source, const std::string& at,
                           int lo, int hi) {
  const auto v = opt_number(obj, key, source, at);
  if (!v) return std::nullopt;
  if (*v != std::floor(*v) || *v < lo || *v > hi)
    throw file_error(source, at + "/" + key + ": expected a whole number in [" + std::to_string(lo) + ", " +
                                 std::to_string(hi) + "], got " + shown_json(*member(obj, key, source, at)));
  return static_cast<int>(*v);
}

}  // namespace millnet::tooling::io::detail
