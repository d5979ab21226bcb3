// Fusion 360's tool library export (JSON), read into tooling::Tool.
//
// The keys, from Autodesk's Fusion API documentation (a tool's JSON as Tool.createFromJson takes it:
// "BMC", "description", "geometry" {"DC", "LB", "LCF", "NOF", "OAL", "SFDM", …}, "holder"
// {"segments": [{"height", "lower-diameter", "upper-diameter"}], "unit"}, "post-process" {"number",
// "length-offset", "diameter-offset", …}, "type", "unit") and exported libraries
// ({"data": [tool, …], "version": N}; entries of type "holder", "probe", "chamfer mill", … too):
//   DC diameter, RE corner radius, NOF flutes, LCF flute length, LB body length below the holder
//   (the stick-out), OAL overall length, SFDM shaft diameter, SIG drill point angle (degrees);
//   lengths in the tool's "unit" ("millimeters" | "inches"); BMC the tool's material ("carbide",
//   "hss", …). The holder is taken as its envelope: the largest segment diameter, the segments'
//   total height.
#include "json_access.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <map>

namespace millnet::tooling::io {
using namespace detail;

namespace {

constexpr double kFusionMmPerInch = 25.4;

std::optional<ToolType> fusion_type(const std::string& t) {
  if (t == "flat end mill") return ToolType::Flat;
  if (t == "ball end mill") return ToolType::Ball;
  if (t == "bull nose end mill") return ToolType::Bull;
  if (t == "drill") return ToolType::Drill;
  return std::nullopt;
}

/// mm per the unit of `obj` ("millimeters" | "inches"); `fallback` when it states none (a holder
/// without a unit has its tool's).
double unit_of(const Json& obj, const std::string& source, const std::string& at, std::optional<double> fallback) {
  const auto u = opt_string(obj, "unit", source, at);
  if (!u) {
    if (fallback) return *fallback;
    throw file_error(source, at + "/unit: missing (\"millimeters\" or \"inches\")");
  }
  if (*u == "millimeters") return 1;
  if (*u == "inches") return kFusionMmPerInch;
  throw file_error(source, at + "/unit: " + in_quotes(*u) + ": expected \"millimeters\" or \"inches\"");
}

std::optional<double> length(const Json& obj, const std::string& key, double k, const std::string& source,
                             const std::string& at) {
  const auto v = opt_number(obj, key, source, at);
  if (!v) return std::nullopt;
  if (*v < 0) throw file_error(source, at + "/" + key + ": " + format_double(*v) + " must not be negative");
  return to_mm(*v, k);
}

}  // namespace

ToolImport read_fusion_library(std::string_view text, const std::string& source) {
  const Json doc = parse_json(text, source);
  const Json* data = doc.is_object() ? member(doc, "data", source, "") : nullptr;
  if (!data || !data->is_array())
    throw file_error(source,
                     "/data: expected the library's array of tools (a Fusion 360 tool library export is "
                     "{\"data\": [...]})");
  check_count(data->size(), source);
  ToolImport out;
  IdMaker ids;
  Notes notes;
  std::map<int, std::size_t> entry_of;  // tool number → its entry
  std::map<std::string, std::size_t> skipped;
  for (std::size_t i = 0; i < data->size(); ++i) {
    const std::string at = "/data/" + std::to_string(i);
    const Json& e = (*data)[i];
    const auto type_name = opt_string(e, "type", source, at);
    if (!type_name) throw file_error(source, at + "/type: missing (e.g. \"flat end mill\")");
    const auto type = fusion_type(*type_name);
    if (!type) {
      ++skipped[*type_name];
      continue;
    }
    const double k = unit_of(e, source, at, std::nullopt);
    const Json* g = member(e, "geometry", source, at);
    if (!g || !g->is_object()) throw file_error(source, at + "/geometry: missing (the tool's DC, NOF, LCF, …)");
    const std::string ga = at + "/geometry";
    Tool t;
    t.type = *type;
    const auto dc = length(*g, "DC", k, source, ga);
    if (!dc) throw file_error(source, ga + "/DC: missing (the tool's diameter)");
    if (!(*dc > 0)) throw file_error(source, ga + "/DC: the diameter must be > 0");
    t.diameter_mm = *dc;
    const auto re = length(*g, "RE", k, source, ga);
    if (t.type == ToolType::Ball) t.corner_radius_mm = t.diameter_mm / 2;
    if (t.type == ToolType::Bull) {
      if (!re || !(*re > 0)) throw file_error(source, ga + "/RE: a bull nose end mill needs its corner radius > 0");
      t.corner_radius_mm = *re;
    }
    if (const auto nof = opt_int(*g, "NOF", source, ga, 1, 64))
      t.flutes = *nof;
    else
      notes.add("no NOF (flutes): 2", "/data/" + std::to_string(i));
    if (const auto lcf = length(*g, "LCF", k, source, ga)) t.flute_length_mm = *lcf;
    if (const auto lb = length(*g, "LB", k, source, ga)) t.stickout_mm = *lb;
    if (t.type == ToolType::Drill) {
      if (const auto sig = opt_number(*g, "SIG", source, ga))
        t.point_angle_deg = *sig;
      else
        notes.add("no SIG (point angle): 118 deg", "/data/" + std::to_string(i));
    }
    if (t.type == ToolType::Flat && re && *re > 0) {
      t.type = ToolType::Bull;  // a corner radius makes it a bull nose, whatever the label
      t.corner_radius_mm = *re;
      notes.add("flat end mill with a corner radius RE: taken as a bull nose", "/data/" + std::to_string(i));
    }
    const std::string bmc = opt_string(e, "BMC", source, at).value_or("");
    if (bmc == "hss") {
      t.material = ToolMaterial::HSS;
    } else {
      t.material = ToolMaterial::Carbide;
      if (bmc != "carbide")
        notes.add("BMC " + (bmc.empty() ? std::string("not stated") : in_quotes(bmc)) +
                      ": taken as carbide (millnet's cutting data know carbide and hss)",
                  "/data/" + std::to_string(i));
    }
    if (const Json* pp = member(e, "post-process", source, at)) {
      const std::string pa = at + "/post-process";
      t.number = opt_int(*pp, "number", source, pa, 0, kMaxToolNumber).value_or(0);
      const int h = opt_int(*pp, "length-offset", source, pa, 0, kMaxToolNumber).value_or(0);
      t.length_offset = h == t.number ? 0 : h;  // 0 = the tool's number
    }
    if (t.number > 0) {
      if (const auto seen = entry_of.find(t.number); seen != entry_of.end())
        throw file_error(source, at + "/post-process/number: " + std::to_string(t.number) + " is also /data/" +
                                     std::to_string(seen->second) + "; a tool number appears once");
      entry_of.emplace(t.number, i);
    } else {
      notes.add("no tool number (post-process/number): not assigned", "/data/" + std::to_string(i));
    }
    if (const Json* h = member(e, "holder", source, at)) {
      const std::string ha = at + "/holder";
      const double hk = unit_of(*h, source, ha, k);
      if (const Json* segs = member(*h, "segments", source, ha)) {
        if (!segs->is_array()) throw file_error(source, ha + "/segments: expected an array");
        for (std::size_t s = 0; s < segs->size(); ++s) {
          const std::string sa = ha + "/segments/" + std::to_string(s);
          t.holder_length_mm += length((*segs)[s], "height", hk, source, sa).value_or(0);
          for (const char* key : {"lower-diameter", "upper-diameter"})
            t.holder_diameter_mm = std::max(t.holder_diameter_mm, length((*segs)[s], key, hk, source, sa).value_or(0));
        }
      }
    }
    const std::string desc = opt_string(e, "description", source, at).value_or("");
    const std::string vendor = opt_string(e, "vendor", source, at).value_or("");
    const std::string product = opt_string(e, "product-id", source, at).value_or("");
    t.description = desc;
    if (!vendor.empty() || !product.empty())
      t.description += (desc.empty() ? "" : " ") + std::string("(") + vendor +
                       (vendor.empty() || product.empty() ? "" : " ") + product + ")";
    const std::string fallback = slug(*type_name) + (t.number > 0 ? "-t" + std::to_string(t.number) : "");
    t.id = ids.make(slug(desc).empty() ? slug(product) : slug(desc), fallback);
    t.check(source + ": " + at);
    out.tools.push_back(std::move(t));
  }
  if (out.tools.empty())
    throw file_error(
        source, "no flat, ball or bull nose end mill or drill among its " + std::to_string(data->size()) + " entries");
  if (!skipped.empty()) {
    std::string s = "left out entries millnet does not model (it has flat, ball and bull nose end mills and drills):";
    for (const auto& [type, n] : skipped) s += " " + std::to_string(n) + " x " + shown(type) + ",";
    s.pop_back();
    notes.line(s);
  }
  out.notes = notes.lines(source);
  return out;
}

}  // namespace millnet::tooling::io
