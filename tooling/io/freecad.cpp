// FreeCAD's ToolBit files (.fctb) and tool libraries (.fctl), read into tooling::Tool.
//
// The keys, from FreeCAD's sources (src/Mod/CAM/Tools/Bit/*.fctb, Tools/Library/Default.fctl,
// Path/Tool/toolbit/models/base.py, toolbit/migration.py, shape/models/*.py,
// library/serializers/fctl.py):
//   bit      {"version": 2, "name": label, "shape": "endmill.fcstd" (older: a file name; newer: an id),
//             "shape-type": "Endmill" (newer files), "parameter": {...}, "attribute": {...}}
//   values   quantities as strings with their unit ("6.0000 mm", "0.2500 in", "119.0000 °") or plain
//            numbers (mm, degrees); Flutes an integer
//   shapes   endmill: Diameter, CuttingEdgeHeight, Length (overall), ShankDiameter, Flutes
//            ballend: the same; bullnose: + CornerRadius (older files: TorusRadius, or FlatRadius =
//            the flat bottom's radius, corner = Diameter/2 − FlatRadius, as FreeCAD's own migration);
//            drill: Diameter, Length, TipAngle, Flutes
//   Material "HSS" | "Carbide" (FreeCAD's default HSS), in "attribute" or "parameter"
//   library  {"version": 1, "tools": [{"nr": 1, "path": "5mm_Endmill.fctb"}, …]}: nr is the tool number
#include "json_access.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

namespace millnet::tooling::io {
using namespace detail;

namespace {

enum class Kind { Length, Angle };

std::string lower_ascii(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// A FreeCAD quantity in mm or degrees: a number, or a string "<number> <unit>".
std::optional<double> quantity(const Json& v, Kind kind) {
  if (v.is_number()) {
    const double x = v.get<double>();
    return std::isfinite(x) ? std::optional<double>(x) : std::nullopt;
  }
  if (!v.is_string()) return std::nullopt;
  std::string s = v.get<std::string>();
  // Some locales wrote a decimal comma ("6,0000 mm").
  if (s.find('.') == std::string::npos && std::count(s.begin(), s.end(), ',') == 1)
    std::replace(s.begin(), s.end(), ',', '.');
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return std::nullopt;
  const auto e = s.find_first_not_of("+-0123456789.eE", b);
  const auto number = parse_real(std::string_view(s).substr(b, e == std::string::npos ? std::string::npos : e - b));
  if (!number) return std::nullopt;
  std::string unit = e == std::string::npos ? std::string() : s.substr(e);
  unit.erase(0, unit.find_first_not_of(" \t"));
  unit.erase(unit.find_last_not_of(" \t") + 1);
  if (kind == Kind::Angle) {
    if (unit.empty() || unit == "\xC2\xB0" || unit == "deg") return *number;
    if (unit == "rad") return *number * 180 / std::numbers::pi;
    return std::nullopt;
  }
  static const std::map<std::string, double> mm_per{{"", 1},        {"mm", 1},           {"cm", 10},   {"m", 1000},
                                                    {"um", 1e-3},   {"\xC2\xB5m", 1e-3}, {"in", 25.4}, {"\"", 25.4},
                                                    {"inch", 25.4}, {"ft", 304.8}};
  const auto it = mm_per.find(unit);
  if (it == mm_per.end()) return std::nullopt;
  return to_mm(*number, it->second);
}

/// A bit's value: "parameter" first, then "attribute" (FreeCAD keeps some in either).
const Json* value(const Json& bit, const std::string& key, const std::string& source) {
  for (const char* group : {"parameter", "attribute"})
    if (const Json* g = member(bit, group, source, "")) {
      if (!g->is_object())
        throw file_error(source, std::string("/") + group + ": expected an object, got " + shown_json(*g));
      if (const Json* v = member(*g, key, source, std::string("/") + group)) return v;
    }
  return nullptr;
}

std::string where(const Json& bit, const std::string& key) {
  const Json* p = bit.contains("parameter") && bit["parameter"].is_object() && bit["parameter"].contains(key)
                      ? &bit["parameter"]
                      : nullptr;
  return std::string(p ? "/parameter/" : "/attribute/") + key;
}

std::optional<double> bit_quantity(const Json& bit, const std::string& key, Kind kind, const std::string& source) {
  const Json* v = value(bit, key, source);
  if (!v) return std::nullopt;
  const auto q = quantity(*v, kind);
  if (!q)
    throw file_error(source, where(bit, key) + ": " + shown_json(*v) + ": expected " +
                                 (kind == Kind::Length ? "a length like \"6.00 mm\" or \"0.25 in\""
                                                       : "an angle like \"118.00 \xC2\xB0\""));
  if (*q < 0) throw file_error(source, where(bit, key) + ": " + shown_json(*v) + " must not be negative");
  return q;
}

/// The shape millnet models for a bit's "shape-type" or "shape" ("bullnose.fcstd", "Ballend"), if any.
std::optional<ToolType> shape_type(const std::string& shape) {
  std::string s = lower_ascii(std::filesystem::path(shape).filename().string());
  if (const auto dot = s.rfind('.'); dot != std::string::npos && s.substr(dot) == ".fcstd") s.resize(dot);
  if (s == "endmill") return ToolType::Flat;
  if (s == "ballend") return ToolType::Ball;
  if (s == "bullnose" || s == "torus") return ToolType::Bull;
  if (s == "drill") return ToolType::Drill;
  return std::nullopt;
}

struct Bit {
  std::optional<Tool> tool;  ///< empty: a shape millnet does not model
  std::string shape;
};

Bit read_bit(const Json& doc, const std::string& source, const std::string& stem, IdMaker& ids, Notes& notes) {
  if (!doc.is_object()) throw file_error(source, "expected a ToolBit object {\"name\", \"shape\", \"parameter\"}");
  if (const auto v = opt_number(doc, "version", source, ""); v && *v != 1 && *v != 2)
    throw file_error(source, "/version: " + format_double(*v) + ": millnet reads ToolBit files of version 1 and 2");
  Bit out;
  const auto shape = opt_string(doc, "shape", source, "");
  const auto type_name = opt_string(doc, "shape-type", source, "");
  if (!shape && !type_name) throw file_error(source, "/shape: missing (e.g. \"endmill.fcstd\")");
  out.shape = type_name ? *type_name : *shape;
  std::optional<ToolType> type = type_name ? shape_type(*type_name) : std::nullopt;
  if (!type && shape) type = shape_type(*shape);
  if (!type) return out;
  const std::string name = opt_string(doc, "name", source, "").value_or("");
  Tool t;
  t.type = *type;
  t.description = name.empty() ? stem : name;
  t.id = ids.make(slug(t.description), slug(stem).empty() ? "bit" : slug(stem));
  const auto d = bit_quantity(doc, "Diameter", Kind::Length, source);
  if (!d) throw file_error(source, "/parameter/Diameter: missing (every bit needs its diameter)");
  if (!(*d > 0)) throw file_error(source, where(doc, "Diameter") + ": the diameter must be > 0");
  t.diameter_mm = *d;
  if (t.type == ToolType::Ball) t.corner_radius_mm = t.diameter_mm / 2;
  if (t.type == ToolType::Bull) {
    if (const auto r = bit_quantity(doc, "CornerRadius", Kind::Length, source)) {
      t.corner_radius_mm = *r;
    } else if (const auto tr = bit_quantity(doc, "TorusRadius", Kind::Length, source)) {
      t.corner_radius_mm = *tr;
    } else if (const auto flat = bit_quantity(doc, "FlatRadius", Kind::Length, source)) {
      t.corner_radius_mm = t.diameter_mm / 2 - *flat;  // FreeCAD's own migration (toolbit/migration.py)
      notes.add("corner radius = Diameter/2 - FlatRadius (an older bullnose bit)", t.id);
    } else {
      throw file_error(source, "/parameter/CornerRadius: missing (a bullnose bit needs its corner radius)");
    }
  }
  if (const auto h = bit_quantity(doc, "CuttingEdgeHeight", Kind::Length, source)) t.flute_length_mm = *h;
  if (t.type == ToolType::Drill) {
    if (const auto a = bit_quantity(doc, "TipAngle", Kind::Angle, source))
      t.point_angle_deg = *a;
    else
      notes.add("no TipAngle: 118 deg", t.id);
  }
  if (const Json* f = value(doc, "Flutes", source)) {
    std::optional<int> n;
    if (f->is_number_integer()) n = f->get<int>();
    if (f->is_number_float() && f->get<double>() == std::floor(f->get<double>()))
      n = static_cast<int>(f->get<double>());
    if (f->is_string()) n = parse_int(f->get<std::string>());
    if (!n || *n < 1 || *n > 64)
      throw file_error(source, where(doc, "Flutes") + ": " + shown_json(*f) + ": expected a whole number in [1, 64]");
    t.flutes = *n;
  } else {
    notes.add("no Flutes: 2", t.id);
  }
  if (const Json* m = value(doc, "Material", source)) {
    const std::string s = m->is_string() ? lower_ascii(m->get<std::string>()) : std::string();
    if (s == "hss")
      t.material = ToolMaterial::HSS;
    else if (s == "carbide")
      t.material = ToolMaterial::Carbide;
    else
      throw file_error(source, where(doc, "Material") + ": " + shown_json(*m) + ": expected \"HSS\" or \"Carbide\"");
  } else {
    t.material = ToolMaterial::HSS;
    notes.add("no Material: HSS (FreeCAD's default)", t.id);
  }
  t.check(source);
  out.tool = std::move(t);
  return out;
}

std::string stem_of(const std::string& source) { return std::filesystem::path(source).stem().string(); }

const char* kStickout =
    "stick-out not stated (a ToolBit's Length is the overall length, not the length out of the holder)";

}  // namespace

ToolImport read_freecad_toolbit(std::string_view text, const std::string& source) {
  const Json doc = parse_json(text, source);
  IdMaker ids;
  Notes notes;
  Bit bit = read_bit(doc, source, stem_of(source), ids, notes);
  if (!bit.tool)
    throw file_error(source, (doc.contains("shape-type") ? "/shape-type: " : "/shape: ") + in_quotes(bit.shape) +
                                 " is not a shape millnet models (endmill, ballend, bullnose, torus, drill)");
  notes.line(kStickout);
  ToolImport out;
  out.tools.push_back(std::move(*bit.tool));
  out.notes = notes.lines(source);
  return out;
}

ToolImport read_freecad_library(std::string_view text, const std::string& source, const BitLoader& load) {
  const Json doc = parse_json(text, source);
  const Json* list = member(doc, "tools", source, "");
  if (!list || !list->is_array())
    throw file_error(source, "/tools: expected the library's array of {\"nr\": N, \"path\": \"bit.fctb\"}");
  check_count(list->size(), source);
  ToolImport out;
  IdMaker ids;
  Notes notes;
  std::map<int, std::size_t> entry_of;  // tool number → its entry
  std::map<std::string, std::size_t> skipped;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const std::string at = "/tools/" + std::to_string(i);
    const Json& e = (*list)[i];
    // FreeCAD reads nr with int(), so "3" is 3 too.
    std::optional<int> nr;
    if (const Json* v = member(e, "nr", source, at); v && v->is_string())
      nr = parse_int(v->get<std::string>());
    else
      nr = opt_int(e, "nr", source, at, 0, kMaxToolNumber);
    if (!nr || *nr < 0 || *nr > kMaxToolNumber)
      throw file_error(
          source, at + "/nr: expected the tool number, a whole number in [0, " + std::to_string(kMaxToolNumber) + "]");
    const auto path = opt_string(e, "path", source, at);
    if (!path || path->empty())
      throw file_error(source, at + "/path: missing (the bit file, e.g. \"5mm_Endmill.fctb\")");
    Bit bit;
    try {
      const BitFile file = load(*path);
      bit = read_bit(parse_json(file.text, file.source), file.source, stem_of(*path), ids, notes);
    } catch (const Error& err) {
      throw file_error(source, at + " (nr " + std::to_string(*nr) + "): " + err.what());
    }
    if (!bit.tool) {
      ++skipped[bit.shape];
      continue;
    }
    if (*nr > 0) {
      if (const auto seen = entry_of.find(*nr); seen != entry_of.end())
        throw file_error(source, at + "/nr: " + std::to_string(*nr) + " is also /tools/" +
                                     std::to_string(seen->second) + "; a tool number appears once");
      entry_of.emplace(*nr, i);
    }
    bit.tool->number = *nr;
    out.tools.push_back(std::move(*bit.tool));
  }
  if (out.tools.empty())
    throw file_error(source,
                     "no endmill, ballend, bullnose or drill bit among its " + std::to_string(list->size()) + " tools");
  if (!skipped.empty()) {
    std::string s = "left out bits of shapes millnet does not model:";
    for (const auto& [shape, n] : skipped) s += " " + std::to_string(n) + " x " + shown(shape) + ",";
    s.pop_back();
    notes.line(s);
  }
  notes.line(kStickout);
  out.notes = notes.lines(source);
  return out;
}

}  // namespace millnet::tooling::io
