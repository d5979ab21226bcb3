#include "cutting.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/edit_distance.hpp"
#include "millnet/core/error.hpp"
#include "millnet/job/operations.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
const char* kToolsText =
#include "millnet_tools.inc"
    ;
const char* kToolsSchemaText =
#include "millnet_tools_schema.inc"
    ;
const char* kMaterialsText =
#include "millnet_materials.inc"
    ;
const char* kMaterialsSchemaText =
#include "millnet_materials_schema.inc"
    ;

template <class T>
const T& find_id(const std::vector<T>& items, const std::string& id, const std::string& what, const char* kind,
                 const std::string& source) {
  for (const T& t : items)
    if (t.id == id) return t;
  std::string best;
  std::size_t best_d = 4;
  for (const T& t : items) {
    const std::size_t d = edit_distance(id, t.id);
    if (d < best_d) {
      best_d = d;
      best = t.id;
    }
  }
  std::string msg = what + ": unknown " + kind + " id '" + id.substr(0, 60) + "'";
  if (!best.empty()) msg += " (did you mean '" + best + "'?)";
  msg += "; " + std::to_string(items.size()) + " " + kind + "s in " + source;
  throw Error(msg);
}

tooling::Tool tool_of(const Json& j) {
  tooling::Tool t;
  t.id = j["id"].get<std::string>();
  t.description = j["description"].get<std::string>();
  t.type = tooling::parse_tool_type(j["type"].get<std::string>());
  t.diameter_mm = j["diameter"].get<double>();
  t.corner_radius_mm = t.type == tooling::ToolType::Ball ? t.diameter_mm / 2 : j["corner_radius"].get<double>();
  t.flutes = j["flutes"].get<int>();
  t.flute_length_mm = j["flute_length"].get<double>();
  t.stickout_mm = j["stickout"].get<double>();
  t.material = tooling::parse_tool_material(j["tool_material"].get<std::string>());
  t.max_rpm = j["max_rpm"].get<double>();
  t.point_angle_deg = j["point_angle"].get<double>();
  t.number = j["number"].get<int>();
  t.length_offset = j["length_offset"].get<int>();
  t.holder_diameter_mm = j["holder_diameter"].get<double>();
  t.holder_length_mm = j["holder_length"].get<double>();
  return t;
}

std::vector<tooling::Tool> tools_of(const Json& doc) {
  std::vector<tooling::Tool> out;
  for (const Json& j : doc["tools"]) out.push_back(tool_of(j));
  return out;
}

std::vector<tooling::Material> materials_of(const Json& doc) {
  std::vector<tooling::Material> out;
  for (const Json& j : doc["materials"]) {
    tooling::Material m;
    m.id = j["id"].get<std::string>();
    m.name = j["name"].get<std::string>();
    for (const Json& r : j["cutting"])
      m.ranges.push_back({tooling::parse_tool_material(r["tool_material"].get<std::string>()), r["d_min"].get<double>(),
                          r["d_max"].get<double>(), r["vc"].get<double>(), r["fz"].get<double>(),
                          r["source"].get<std::string>()});
    out.push_back(std::move(m));
  }
  return out;
}

/// Adds `more` to `base`; an id already in base is replaced. Duplicate ids within one file are errors.
template <class T>
void merge(std::vector<T>& base, std::vector<T> more, const char* kind, const std::string& source) {
  for (std::size_t i = 0; i < more.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (more[i].id == more[k].id) throw Error(source + ": " + kind + " id '" + more[i].id + "' appears twice");
  for (T& t : more) {
    auto it = std::find_if(base.begin(), base.end(), [&](const T& b) { return b.id == t.id; });
    if (it != base.end())
      *it = std::move(t);
    else
      base.push_back(std::move(t));
  }
}

std::string fmt(double v, int decimals) {
  const double s = std::pow(10.0, decimals);
  return format_double(std::round(v * s) / s);
}
}  // namespace

void check_tool_library(Json& doc, const std::string& source) {
  static const Json rule = Json::parse(kToolsSchemaText);
  check_against(doc, rule, fs::path(source).parent_path(), source);
  const Json& tools = doc["tools"];
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const std::string at = source + ": /tools/" + std::to_string(i);
    tool_of(tools[i]).check(at);
    // One tool per tool-changer number within a file (0 = not assigned).
    if (const int n = tools[i]["number"].get<int>(); n > 0)
      for (std::size_t k = 0; k < i; ++k)
        if (tools[k]["number"].get<int>() == n)
          throw Error(at + "/number: T" + std::to_string(n) + " is also /tools/" + std::to_string(k) + " (" +
                      tools[k]["id"].get<std::string>().substr(0, 60) + "); a tool number appears once");
  }
}

void check_material_table(Json& doc, const std::string& source) {
  static const Json rule = Json::parse(kMaterialsSchemaText);
  check_against(doc, rule, fs::path(source).parent_path(), source);
  for (std::size_t i = 0; i < doc["materials"].size(); ++i)
    for (std::size_t k = 0; k < doc["materials"][i]["cutting"].size(); ++k) {
      const Json& r = doc["materials"][i]["cutting"][k];
      if (!(r["d_min"].get<double>() < r["d_max"].get<double>()))
        throw Error(source + ": /materials/" + std::to_string(i) + "/cutting/" + std::to_string(k) +
                    ": d_min must be below d_max");
    }
}

const tooling::Tool& ToolLibrary::tool(const std::string& id, const std::string& what) const {
  return find_id(tools, id, what, "tool", tools_source);
}

const tooling::Material& ToolLibrary::material(const std::string& id, const std::string& what) const {
  return find_id(materials, id, what, "material", materials_source);
}

ToolLibrary tool_library(const Json& config) {
  // The built-in library, parsed and checked once per process.
  static const ToolLibrary built_in = [] {
    ToolLibrary b;
    Json t = Json::parse(kToolsText);
    check_tool_library(t, "built-in configs/tools.json");
    merge(b.tools, tools_of(t), "tool", "built-in configs/tools.json");
    b.tool_sources.assign(b.tools.size(), b.tools_source);
    Json m = Json::parse(kMaterialsText);
    check_material_table(m, "built-in configs/materials.json");
    merge(b.materials, materials_of(m), "material", "built-in configs/materials.json");
    return b;
  }();
  ToolLibrary lib = built_in;
  const Json& c = config["cutting"];
  if (const std::string f = c["tools_file"].get<std::string>(); !f.empty()) {
    Json t = read_json(f);
    check_tool_library(t, f);
    std::vector<tooling::Tool> shop = tools_of(t);
    std::vector<std::string> shop_ids;
    for (const tooling::Tool& s : shop) shop_ids.push_back(s.id);
    merge(lib.tools, std::move(shop), "tool", f);
    lib.tool_sources.resize(lib.tools.size());
    for (std::size_t i = 0; i < lib.tools.size(); ++i)
      if (std::find(shop_ids.begin(), shop_ids.end(), lib.tools[i].id) != shop_ids.end()) lib.tool_sources[i] = f;
    lib.tools_source += " + " + f;
  }
  if (const std::string f = c["materials_file"].get<std::string>(); !f.empty()) {
    Json m = read_json(f);
    check_material_table(m, f);
    merge(lib.materials, materials_of(m), "material", f);
    lib.materials_source += " + " + f;
  }
  return lib;
}

std::vector<tooling::Tool> machine_tools(const ToolLibrary& lib, std::vector<std::string>& notes) {
  const std::string built_in = ToolLibrary{}.tools_source;
  auto from_shop = [&](std::size_t i) { return i < lib.tool_sources.size() && lib.tool_sources[i] != built_in; };
  // The shop's tool on a built-in tool's number, if any (lib.tools.size() when none).
  auto shop_twin = [&](std::size_t i) {
    for (std::size_t k = 0; k < lib.tools.size(); ++k)
      if (from_shop(k) && lib.tools[k].number == lib.tools[i].number) return k;
    return lib.tools.size();
  };
  std::vector<tooling::Tool> out;
  for (std::size_t i = 0; i < lib.tools.size(); ++i) {
    const tooling::Tool& t = lib.tools[i];
    if (!from_shop(i) && t.number > 0) {
      if (const std::size_t k = shop_twin(i); k < lib.tools.size()) {
        notes.push_back("built-in tool " + t.id + " (T" + std::to_string(t.number) + ") left out: T" +
                        std::to_string(t.number) + " is " + lib.tools[k].id + " of " + lib.tool_sources[k]);
        continue;
      }
    }
    out.push_back(t);
  }
  return out;
}

CuttingSettings cutting_settings(const Json& config, const std::optional<std::string>& material_flag) {
  const Json& c = config["cutting"];
  CuttingSettings s;
  s.library_feeds = c["feeds"].get<std::string>() == "library";
  if (material_flag) {
    s.material_id = *material_flag;
    s.material_key = "--material";
    s.material_from = "flag --material";
  } else {
    s.material_id = c["material"].get<std::string>();
    s.material_key = "/cutting/material";
    s.material_from = "config /cutting/material";
  }
  const Json& m = config["machine"];
  s.machine.max_rpm = m["max_spindle_rpm"].get<double>();
  s.machine.min_rpm = m["min_spindle_rpm"].get<double>();
  s.machine.max_feed_mm_min = m["max_feed_mm_min"].get<double>();
  if (s.machine.min_rpm > s.machine.max_rpm) throw Error("/machine/min_spindle_rpm exceeds /machine/max_spindle_rpm");
  s.factors.slot = c["slot_factor"].get<double>();
  s.factors.plunge = c["plunge_factor"].get<double>();
  s.factors.ramp = c["ramp_factor"].get<double>();
  s.factors.max_chip_thinning = c["max_chip_thinning"].get<double>();
  s.overrides.vc_m_min = c["vc_m_min"].get<double>();
  s.overrides.fz_mm = c["fz_mm"].get<double>();
  s.inline_flutes = c["inline_flutes"].get<int>();
  s.inline_stickout_mm = c["inline_stickout_mm"].get<double>();
  s.inline_material = tooling::parse_tool_material(c["inline_tool_material"].get<std::string>());
  return s;
}

tooling::Tool inline_tool(tooling::ToolType type, double d, double r, const CuttingSettings& cs,
                          const ToolLibrary& library) {
  tooling::Tool t;
  t.type = type;
  t.diameter_mm = d;
  t.corner_radius_mm = type == tooling::ToolType::Ball ? d / 2 : type == tooling::ToolType::Bull ? r : 0.0;
  t.flutes = cs.inline_flutes;
  t.material = cs.inline_material;
  t.stickout_mm = cs.inline_stickout_mm;
  const tooling::Tool* same = job::longest_of_shape(library.tools, type, d, t.corner_radius_mm);
  if (same != nullptr) {
    t.stickout_mm = same->stickout_mm;
    t.flute_length_mm = same->flute_length_mm;
    t.holder_diameter_mm = same->holder_diameter_mm;
    t.holder_length_mm = same->holder_length_mm;
  }
  return t;
}

tooling::Cutter cutter_of(const tooling::Tool& t) {
  if (t.type == tooling::ToolType::Drill) throw Error("tool " + t.id + " is a drill: it cannot mill");
  return t.cutter();
}

Json CuttingRecord::to_json() const {
  Json j = Json::object();
  j["mode"] = library_feeds ? "library" : "fixed";
  Json t = Json::object();
  t["id"] = tool.id;
  t["label"] = tool.label();
  t["from"] = tool_from;
  t["type"] = tooling::to_string(tool.type);
  t["diameter_mm"] = tool.diameter_mm;
  t["corner_radius_mm"] = tool.corner_radius_mm;
  t["flutes"] = tool.flutes;
  t["flute_length_mm"] = tool.flute_length_mm;
  t["stickout_mm"] = tool.stickout_mm;
  t["tool_material"] = tooling::to_string(tool.material);
  t["max_rpm"] = tool.max_rpm;
  j["tool"] = t;
  if (library_feeds) {
    j["material"] = {{"id", material_id}, {"from", material_from}};
    j["vc_m_min"] = data.vc_m_min;
    j["fz_mm"] = data.fz_mm;
    j["table_source"] = data.source;
    j["axial_depth_mm"] = data.axial_depth_mm;
    j["d_eff_mm"] = data.d_eff_mm;
    j["rpm_computed"] = data.rpm_computed;
    j["rpm_limited_by"] = data.rpm_limited_by;
    j["feed_limited_by_machine"] = data.feed_limited;
    j["max_chip_thinning"] = data.max_chip_thinning;
  }
  Json figs = Json::object();
  for (const auto& [k, f] : figures) figs[k] = {{"value", f.value}, {"from", f.source}};
  j["figures"] = figs;
  return j;
}

std::vector<std::string> CuttingRecord::header() const {
  std::vector<std::string> h;
  if (!library_feeds && tool.id.empty()) return h;
  h.push_back("tool: " + tool.label());
  if (library_feeds) {
    std::string s = "cutting data: " + material_id + ", Vc " + fmt(data.vc_m_min, 1) + " m/min, fz " +
                    fmt(data.fz_mm, 4) + " mm, D_eff " + fmt(data.d_eff_mm, 3) + " mm at a_p " +
                    fmt(data.axial_depth_mm, 3) + " mm";
    if (!data.rpm_limited_by.empty()) s += "; speed limited by " + data.rpm_limited_by;
    h.push_back(s);
  }
  return h;
}

}  // namespace millnet::app
