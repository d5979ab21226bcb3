#include "config.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"
#include "millnet/pocket/io/pocket_io.hpp"

#include <cmath>
#include <optional>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
const char* kSchemaText =
#include "millnet_schema.inc"
    ;

std::string type_name(const Json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number_integer() || v.is_number_unsigned()) return "an integer";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  return "an object";
}

/// A value as the checker's messages show it: at most 40 characters, arrays and objects by their
/// size (never dumped whole: a 10 MB array or a deep value is not printed).
std::string shown(const Json& v) {
  if (v.is_array()) return "(" + std::to_string(v.size()) + " items)";
  if (v.is_object()) return "(" + std::to_string(v.size()) + " keys)";
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

class Checker {
public:
  Checker(const fs::path& base, std::string source, bool fill_defaults = true)
      : base_(base), source_(std::move(source)), fill_(fill_defaults) {}

  void check(Json& value, const Json& rule, const std::string& ptr) {
    const std::string type = rule.value("type", "");
    const std::string at = source_ + ": " + (ptr.empty() ? "/" : ptr);
    if (type == "object") {
      if (!value.is_object()) throw Error(at + ": expected an object, got " + type_name(value));
      const Json& props = rule.contains("properties") ? rule["properties"] : Json::object();
      for (auto it = value.begin(); it != value.end(); ++it) {
        if (!props.contains(it.key()))
          throw Error(at + (ptr.empty() ? "" : "/") + it.key() + ": unknown key (allowed here: " + allowed(props) +
                      ")");
      }
      for (auto it = props.begin(); it != props.end(); ++it) {
        const Json& sub = it.value();
        if (!value.contains(it.key())) {
          if (!fill_) {
            continue;
          } else if (sub.contains("default")) {
            value[it.key()] = sub["default"];
          } else if (sub.value("type", "") == "object") {
            value[it.key()] = Json::object();
          } else if (sub.value("required", false)) {
            throw Error(at + (ptr.empty() ? "" : "/") + it.key() + ": required key is missing");
          } else {
            continue;
          }
        }
        check(value[it.key()], sub, ptr + "/" + it.key());
      }
      return;
    }
    if (value.is_null() && rule.value("nullable", false)) return;
    if (type == "array") {
      if (!value.is_array()) throw Error(at + ": expected an array, got " + type_name(value));
      if (rule.contains("minItems") && value.size() < rule["minItems"].get<std::size_t>())
        throw Error(at + ": expected at least " + rule["minItems"].dump() + " items");
      if (rule.contains("maxItems") && value.size() > rule["maxItems"].get<std::size_t>())
        throw Error(at + ": expected at most " + rule["maxItems"].dump() + " items");
      if (rule.contains("items"))
        for (std::size_t i = 0; i < value.size(); ++i) check(value[i], rule["items"], ptr + "/" + std::to_string(i));
      return;
    }
    if (type == "number") {
      if (!value.is_number()) throw Error(at + ": expected a number, got " + type_name(value) + " " + shown(value));
      const double x = value.get<double>();
      if (!std::isfinite(x)) throw Error(at + ": expected a finite number");
      bounds(x, rule, at);
    } else if (type == "integer") {
      if (!(value.is_number_integer() || value.is_number_unsigned()))
        throw Error(at + ": expected an integer, got " + type_name(value) + " " + shown(value));
      bounds(value.get<double>(), rule, at);
    } else if (type == "boolean") {
      if (!value.is_boolean())
        throw Error(at + ": expected true or false, got " + type_name(value) + " " + shown(value));
    } else if (type == "string") {
      if (!value.is_string()) throw Error(at + ": expected a string, got " + type_name(value) + " " + shown(value));
      if (rule.value("format", "") == "path") {
        // An empty path resolved to the config's folder: "output": "" wrote into it (issue 15;
        // tests/corpus/config/output_empty.json).
        // Unless the key says "" means none ("allowEmpty": /cutting/tools_file).
        if (value.get<std::string>().find_first_not_of(" \t\r\n") == std::string::npos) {
          if (rule.value("allowEmpty", false)) {
            value = "";
            return;
          }
          throw Error(at + ": expected a path, got an empty string");
        }
        fs::path p = value.get<std::string>();
        if (!p.empty() && p.is_relative()) p = base_ / p;
        value = p.lexically_normal().string();
      }
    } else if (type == "number_or_string") {
      if (!value.is_number() && !value.is_string())
        throw Error(at + ": expected a number or a string, got " + type_name(value));
    } else if (type == "integer_or_string") {
      if (value.is_number_integer() || value.is_number_unsigned()) {
        bounds(value.get<double>(), rule, at);
      } else {
        const Json strings = rule.value("strings", Json::array());
        bool ok = value.is_string();
        if (ok) {
          ok = false;
          for (const auto& e : strings) ok = ok || e == value;
        }
        if (!ok)
          throw Error(at + ": expected an integer or one of " + strings.dump() + ", got " + type_name(value) + " " +
                      shown(value));
      }
    } else if (!type.empty()) {
      throw Error("schema: unknown type '" + type + "' at " + ptr);
    }
    if (rule.contains("enum")) {
      bool ok = false;
      for (const auto& e : rule["enum"]) ok = ok || e == value;
      if (!ok) throw Error(at + ": expected one of " + rule["enum"].dump() + ", got " + shown(value));
    }
  }

private:
  static std::string allowed(const Json& props) {
    std::string s;
    for (auto it = props.begin(); it != props.end(); ++it) s += (s.empty() ? "" : ", ") + it.key();
    return s.empty() ? "none" : s;
  }
  /// 100000 rather than 1e+05 for whole numbers.
  static std::string number(double x) {
    if (x == std::floor(x) && std::abs(x) < 1e15) return std::to_string(static_cast<long long>(x));
    return format_double(x);
  }
  static void bounds(double x, const Json& rule, const std::string& at) {
    if (rule.contains("minimum") && x < rule["minimum"].get<double>())
      throw Error(at + ": must be ≥ " + rule["minimum"].dump() + ", got " + number(x));
    if (rule.contains("exclusiveMinimum") && x <= rule["exclusiveMinimum"].get<double>())
      throw Error(at + ": must be > " + rule["exclusiveMinimum"].dump() + ", got " + number(x));
    if (rule.contains("maximum") && x > rule["maximum"].get<double>())
      throw Error(at + ": must be ≤ " + rule["maximum"].dump() + ", got " + number(x));
    if (rule.contains("exclusiveMaximum") && x >= rule["exclusiveMaximum"].get<double>())
      throw Error(at + ": must be < " + rule["exclusiveMaximum"].dump() + ", got " + number(x));
  }
  fs::path base_;
  std::string source_;
  bool fill_ = true;
};

// "dataset": {"recipe": FILE, …}: the recipe file supplies the dataset section (its relative paths
// resolve against its own folder); keys given inline beside "recipe" override it.
void merge_recipe(Json& config, const fs::path& base, const std::string& source) {
  if (!config.is_object() || !config.contains("dataset") || !config["dataset"].is_object()) return;
  Json& ds = config["dataset"];
  if (!ds.contains("recipe")) return;
  const Json& rule = schema()["properties"]["dataset"];
  Json inline_keys = ds;
  Checker(base, source, false).check(inline_keys, rule, "/dataset");
  const fs::path recipe_path = inline_keys["recipe"].get<std::string>();
  Json recipe = read_json(recipe_path);
  if (recipe.is_object() && recipe.contains("recipe"))
    throw file_error(recipe_path.string(), "/recipe: a recipe cannot name another recipe");
  Checker(recipe_path.parent_path(), recipe_path.string(), false).check(recipe, rule, "");
  recipe.merge_patch(inline_keys);
  ds = recipe;
}
}  // namespace

const Json& schema() {
  static const Json s = Json::parse(kSchemaText);
  return s;
}

Json read_json(const fs::path& path) {
  const std::string text = read_file(path);
  check_json_nesting(text, path.string());
  try {
    return Json::parse(text);
  } catch (const Json::out_of_range& e) {  // a number too large for a double ("1e309")
    throw file_error(path.string(), "invalid JSON: " + json_error_text(e.what()));
  } catch (const Json::parse_error& e) {
    // nlohmann reports a byte offset; turn it into line:column.
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string what = e.what();
    const auto pos = what.find("syntax error");
    throw line_error(path.string(), static_cast<long>(line),
                     std::to_string(col) + ": invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos)));
  }
}

void check_config(Json& config, const fs::path& base, const std::string& source) {
  merge_recipe(config, base, source);
  Checker(base, source).check(config, schema(), "");
}

void check_against(Json& doc, const Json& rule, const fs::path& base, const std::string& source) {
  Checker(base, source).check(doc, rule, "");
}

void check_pocket_file(const pocket::PocketFile& file, const std::string& source) {
  Json values = Json::object();
  const std::pair<const char*, const std::optional<double>*> keys[] = {{"tool_diameter", &file.tool_diameter},
                                                                       {"stepover", &file.stepover},
                                                                       {"depth", &file.depth},
                                                                       {"safe_z", &file.safe_z},
                                                                       {"step_down", &file.step_down},
                                                                       {"stock_to_leave", &file.stock_to_leave},
                                                                       {"feed_slot", &file.feed_slot},
                                                                       {"feed_half", &file.feed_half},
                                                                       {"feed_plunge", &file.feed_plunge},
                                                                       {"spindle_rpm", &file.spindle_rpm}};
  for (const auto& [k, v] : keys)
    if (v->has_value()) values[k] = **v;
  Checker(fs::path(source).parent_path(), source, false).check(values, schema()["properties"]["pocket"], "");
}

Json load_config(const fs::path& path) {
  Json config = read_json(path);
  fs::path base = fs::absolute(path).parent_path();
  check_config(config, base, path.string());
  return config;
}

Json default_config(const fs::path& base) {
  Json config = Json::object();
  check_config(config, base, "(defaults)");
  return config;
}

}  // namespace millnet::app
