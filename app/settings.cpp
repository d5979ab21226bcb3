#include "settings.hpp"

#include "json_settings.hpp"
#include "cli.hpp"
#include "text.hpp"

#include <cmath>

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/job/tool_choice.hpp"

#include <algorithm>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

augment::AugmentParams augment_from(const Json& a) {
  augment::AugmentParams p;
  p.angles_deg = a["angles_deg"].get<std::vector<double>>();
  p.axes.clear();
  for (const auto& s : a["axes"]) p.axes.push_back(augment::parse_axis(s.get<std::string>()));
  p.flip = a["flip"].get<bool>();
  return p;
}

Json explicit_pocket_section(const std::string& config_path) {
  if (config_path.empty()) return Json::object();
  const Json raw = read_json(config_path);
  if (raw.is_object() && raw.contains("pocket") && raw["pocket"].is_object()) return raw["pocket"];
  return Json::object();
}

namespace {

/// A spindle speed or feed the program would run at, against the machine's limit: one line naming
/// where the figure came from, the limit's key and the excess.
void check_machine_limit(const CuttingSettings& cs, const std::string& key, const Figure& f) {
  const bool rpm = key == "spindle_rpm";
  const double lim = rpm ? cs.machine.max_rpm : cs.machine.max_feed_mm_min;
  if (f.value > lim * (1 + 1e-12))
    throw Error(f.source + ": " + key + " " + format_double(f.value) + (rpm ? " rpm" : " mm/min") +
                " exceeds the machine's " + (rpm ? "/machine/max_spindle_rpm " : "/machine/max_feed_mm_min ") +
                format_double(lim) + " by " + format_double(f.value - lim));
}

/// `dst` = the figure the user wrote, else `computed`; recorded in rec.figures with its source.
void take(CuttingRecord& rec, const char* key, double& dst, double computed, const std::optional<Figure>& written,
          const std::string& why) {
  dst = written ? written->value : computed;
  rec.figures.push_back({key, {dst, written ? written->source : why}});
}

/// Library mode: the material's row for rec.tool, the cutting data at axial depth `ap` (a written
/// spindle speed as the override), into rec; returns the figures' source "library: <material> × <tool>".
std::string library_data(CuttingRecord& rec, const CuttingSettings& cs, const ToolLibrary& lib, double ap,
                         const std::optional<Figure>& written_rpm) {
  const tooling::Material& mat = lib.material(cs.material_id, cs.material_key);
  rec.material_id = mat.id;
  rec.material_from = cs.material_from;
  tooling::Overrides ov = cs.overrides;
  if (written_rpm) ov.rpm = written_rpm->value;
  rec.data = tooling::cutting_data(rec.tool, mat, ap, cs.machine, cs.factors, ov);
  return "library: " + mat.id + " × " + (rec.tool.id.empty() ? std::string("inline tool") : rec.tool.id);
}

/// The roughing tool and its cutting data (issue 17): which tool (flag, config, pocket file, inline
/// or library), then spindle speed and feeds from tool × material × machine in library mode, each
/// figure the user wrote taking its place. Fills `record` (when given) with every figure's source.
void apply_cutting_data(pocket::CutParams& c, const Json& config, const Json& explicit_pocket,
                        const pocket::PocketFile* file, const PocketFlags& flags, CuttingRecord* record) {
  const Json& pc = config["pocket"];
  const CuttingSettings cs = cutting_settings(config, flags.material);
  CuttingRecord rec;
  rec.library_feeds = cs.library_feeds;
  const bool file_d =
      file && file->tool_diameter && !explicit_pocket.contains("tool_diameter") && !explicit_pocket.contains("tool");
  const ToolLibrary lib = tool_library(config);
  if (flags.tool_id) {
    rec.tool = lib.tool(*flags.tool_id, "--tool");
    rec.tool_from = "flag --tool";
  } else if (flags.tool_diameter) {
    rec.tool = inline_tool(tooling::ToolType::Flat, c.tool.diameter, 0, cs, lib);
    rec.tool_from = "flag --tool-diameter";
  } else if (file_d) {
    rec.tool = inline_tool(tooling::ToolType::Flat, c.tool.diameter, 0, cs, lib);
    rec.tool_from = "pocket file tool_diameter";
  } else if (explicit_pocket.contains("tool_diameter") && !explicit_pocket.contains("tool")) {
    rec.tool = inline_tool(tooling::ToolType::Flat, c.tool.diameter, 0, cs, lib);
    rec.tool_from = "config /pocket/tool_diameter";
  } else if (const std::string id = pc["tool"].get<std::string>(); !id.empty()) {
    rec.tool = lib.tool(id, "/pocket/tool");
    rec.tool_from = "config /pocket/tool";
    if (explicit_pocket.contains("tool_diameter") && std::abs(c.tool.diameter - rec.tool.diameter_mm) > 1e-9)
      throw Error("/pocket/tool " + id + " is D" + format_double(rec.tool.diameter_mm) +
                  " mm but /pocket/tool_diameter is " + format_double(c.tool.diameter) + " mm: write one of them");
  } else {
    rec.tool = inline_tool(tooling::ToolType::Flat, c.tool.diameter, 0, cs, lib);
    rec.tool_from = "config /pocket/tool_diameter";
  }
  const tooling::Tool& tool = rec.tool;
  if (tool.type == tooling::ToolType::Ball || tool.type == tooling::ToolType::Drill)
    throw Error(rec.tool_from + ": " + tool.label() + " cannot rough a pocket: give a flat or bull-nose end mill");
  c.tool = tool.cutter();
  const double ap = std::min(c.step_down, c.depth);
  if (tool.flute_length_mm > 0 && ap > tool.flute_length_mm)
    throw Error(tool.label() + ": its flute length " + format_double(tool.flute_length_mm) +
                " mm is shorter than the depth of cut per level " + format_double(ap) + " mm by " +
                format_double(ap - tool.flute_length_mm) + " mm (lower --step-down / /pocket/step_down)");
  job::check_reach(tool.cutter(), tool.label(), c.depth, "the pocket");

  // A figure the user wrote: config key, or the pocket file's own key (as cut_params picks them).
  auto written = [&](const char* key, const std::optional<double>& from_file) -> std::optional<Figure> {
    if (explicit_pocket.contains(key)) return Figure{pc[key].get<double>(), std::string("config /pocket/") + key};
    if (from_file) return Figure{*from_file, std::string("pocket file ") + key};
    return std::nullopt;
  };
  const std::optional<double> none;
  const auto w_rpm = written("spindle_rpm", file ? file->spindle_rpm : none);
  const auto w_half = written("feed_half", file ? file->feed_half : none);
  const auto w_slot = written("feed_slot", file ? file->feed_slot : none);
  const auto w_plunge = written("feed_plunge", file ? file->feed_plunge : none);
  const auto w_min = written("feed_min", none);
  const auto w_max = written("feed_max", none);
  if (w_rpm) check_machine_limit(cs, "spindle_rpm", *w_rpm);  // before the speed is used, naming its key
  if (cs.library_feeds) {
    const std::string src = library_data(rec, cs, lib, ap, w_rpm);
    const tooling::CuttingData& d = rec.data;
    take(rec, "spindle_rpm", c.spindle_rpm, d.rpm, w_rpm,
         src + (d.rpm_limited_by.empty() ? "" : ", limited by " + d.rpm_limited_by));
    take(rec, "feed_half", c.feed_half, d.feed_mm_min, w_half, src + ": fz·z·n");
    take(rec, "feed_slot", c.feed_slot, d.feed_slot_mm_min, w_slot, src + ": feed_half × /cutting/slot_factor");
    take(rec, "feed_plunge", c.feed_plunge, d.feed_plunge_mm_min, w_plunge,
         src + ": feed_half × /cutting/plunge_factor");
    take(rec, "feed_entry", c.feed_entry, d.feed_ramp_mm_min, w_plunge, src + ": feed_half × /cutting/ramp_factor");
    take(rec, "feed_min", c.feed_min, std::min(c.feed_slot, c.feed_half), w_min,
         "the slot feed (eq. 9 at full engagement)");
    take(rec, "feed_max", c.feed_max, std::max(d.feed_max_mm_min, c.feed_half), w_max,
         "feed_half × /cutting/max_chip_thinning, at most /machine/max_feed_mm_min");
    c.max_chip_thinning = cs.factors.max_chip_thinning > 1 ? cs.factors.max_chip_thinning : 0.0;
  } else {  // the values cut_params picked (config, pocket file) in the same order as `written`
    const std::pair<const char*, double*> keys[] = {{"spindle_rpm", &c.spindle_rpm}, {"feed_half", &c.feed_half},
                                                    {"feed_slot", &c.feed_slot},     {"feed_plunge", &c.feed_plunge},
                                                    {"feed_min", &c.feed_min},       {"feed_max", &c.feed_max}};
    const std::optional<Figure>* w[] = {&w_rpm, &w_half, &w_slot, &w_plunge, &w_min, &w_max};
    for (std::size_t k = 0; k < std::size(keys); ++k)
      take(rec, keys[k].first, *keys[k].second, *keys[k].second, *w[k],
           std::string("config /pocket/") + keys[k].first + " (fixed feeds)");
  }
  // Written figures and the fixed ones stay within the machine: say which and by how much.
  for (const auto& [key, f] : rec.figures) check_machine_limit(cs, key, f);
  c.header = rec.header();
  if (record) *record = std::move(rec);
}

}  // namespace

pocket::CutParams cut_params(const Json& config, const Json& explicit_pocket, const pocket::PocketFile* file,
                             const PocketFlags& flags, CuttingRecord* record) {
  const Json& pc = config["pocket"];
  pocket::CutParams c;
  auto pick = [&](double& dst, const char* key, const std::optional<double>& from_file,
                  const std::optional<double>& flag) {
    dst = pc[key].get<double>();                                        // config (explicit or default)
    if (from_file && !explicit_pocket.contains(key)) dst = *from_file;  // the pocket file's own key
    if (flag) dst = *flag;                                              // the command line
  };
  const std::optional<double> none;
  pick(c.tool.diameter, "tool_diameter", file ? file->tool_diameter : none, flags.tool_diameter);
  pick(c.stepover, "stepover", file ? file->stepover : none, flags.stepover);
  pick(c.stock_to_leave, "stock_to_leave", file ? file->stock_to_leave : none, flags.stock_to_leave);
  pick(c.depth, "depth", file ? file->depth : none, flags.depth);
  pick(c.step_down, "step_down", file ? file->step_down : none, flags.step_down);
  pick(c.safe_z, "safe_z", file ? file->safe_z : none, flags.safe_z);
  pick(c.feed_slot, "feed_slot", file ? file->feed_slot : none, none);
  pick(c.feed_half, "feed_half", file ? file->feed_half : none, none);
  pick(c.feed_plunge, "feed_plunge", file ? file->feed_plunge : none, none);
  pick(c.spindle_rpm, "spindle_rpm", file ? file->spindle_rpm : none, none);
  c.feed_min = pc["feed_min"].get<double>();
  c.feed_max = pc["feed_max"].get<double>();
  c.feed_grid = pc["feed_grid"].get<double>();
  c.feed_adjust = pc["feed_adjust"].get<bool>();
  c.feed_pool_short_steps = pc["feed_map_pooling"].get<bool>();
  c.rapid_rate = pc["rapid_rate"].get<double>();
  apply_cutting_data(c, config, explicit_pocket, file, flags, record);
  if (pc["air_feed"].get<bool>()) {
    // A move that cuts no feed-map cell may graze a sliver up to a cell wide: at that radial
    // engagement the chip thins by tooling::chip_thinning_factor, so this feed keeps it nominal.
    const double cell = c.feed_grid > 0 ? c.feed_grid : c.tool.diameter / 10;
    const double ae = std::min(cell, c.tool.diameter / 2);
    c.feed_air = std::min(c.feed_half * tooling::chip_thinning_factor(c.tool.diameter, ae),
                          config["machine"]["max_feed_mm_min"].get<double>());
    c.feed_air = std::max(c.feed_air, c.feed_half);
  }
  if (c.stepover > c.tool.diameter)
    throw Error("stepover " + format_double(c.stepover) + " mm exceeds the tool diameter " +
                format_double(c.tool.diameter) + " mm: ridges of material would be left between passes");
  if (c.feed_min > c.feed_max) throw Error("/pocket/feed_min exceeds /pocket/feed_max");
  return c;
}

gcode::MotionModel motion_model(const Json& config) {
  const Json& m = config["machine"];
  gcode::MotionModel mm;
  mm.acceleration_mm_s2 = m["acceleration_mm_s2"].get<double>();
  mm.junction_deviation_mm = m["junction_deviation_mm"].get<double>();
  mm.rapid_mm_min = m["rapid_mm_min"].get<double>();
  mm.max_feed_mm_min = m["max_feed_mm_min"].get<double>();
  return mm;
}

pocket::MachiningOptions machining_options(const PlannerChoice& choice, const Json& config) {
  pocket::MachiningOptions mo;
  mo.entry = choice.entry;
  mo.entry_angle_deg = choice.entry_angle_deg;
  mo.ramp_clearance_mm = choice.ramp_clearance_mm;
  mo.contour = choice.contour;
  mo.link_walls = choice.link_walls;
  mo.machine = motion_model(config);
  return mo;
}

namespace {

/// Sets "section/key" of the pocket section to a string.
void set_setting(Json& pocket, std::string_view path, std::string_view value) {
  Json* at = &pocket;
  for (std::size_t b = 0; b <= path.size();) {
    std::size_t e = path.find('/', b);
    if (e == std::string_view::npos) e = path.size();
    at = &(*at)[std::string(path.substr(b, e - b))];
    b = e + 1;
  }
  *at = std::string(value);
}

/// --angle checked as /pocket/zigzag/angle is, in the config's terms: "auto" or a number.
Json angle_flag(const std::string& angle) {
  const std::optional<double> deg = pocket::parse_zigzag_angle(angle, "--angle");
  return deg ? Json(*deg) : Json(angle);
}

}  // namespace

PlannerChoice planner_choice(const Json& config, const pocket::CutParams& cut, const PocketFlags& flags,
                             const pocket::CompareRun* run) {
  Json pc = config["pocket"];
  if (run)
    for (const auto& [path, value] : run->defaults) set_setting(pc, path, value);
  if (flags.partition) pc["zigzag"]["partition"] = *flags.partition;
  if (flags.angle) pc["zigzag"]["angle"] = angle_flag(*flags.angle);
  if (run)
    for (const auto& [path, value] : run->overrides) set_setting(pc, path, value);
  PlannerChoice ch;
  ch.name = flags.planner.value_or(pc["planner"].get<std::string>());
  ch.spec =
      pocket::planner_named(ch.name).parse(JsonSettings(pc, "/pocket"), {&cut, config["seed"].get<std::uint64_t>()});
  ch.entry = pocket::parse_entry(flags.entry.value_or(pc["entry"].get<std::string>()));
  ch.contour = !flags.no_contour && (flags.contour || pc["contour"].get<bool>());
  ch.link_walls = pc["link_walls"].get<bool>();
  ch.entry_angle_deg = pc["entry_angle"].get<double>();
  ch.ramp_clearance_mm = pc["ramp_clearance"].get<double>();
  return ch;
}

gcode::StockBlock stock_block(const Json& config) {
  const Json& r = config["rough"];
  gcode::StockBlock b;
  b.margin_mm = r["margin_mm"].get<double>();
  if (!r["stock_offsets_mm"].is_null()) b.offsets_mm = r["stock_offsets_mm"].get<std::array<double, 4>>();
  if (!r["stock_size_mm"].is_null()) b.size_mm = r["stock_size_mm"].get<std::array<double, 2>>();
  if (b.offsets_mm && b.size_mm)
    throw Error("/rough/stock_offsets_mm and /rough/stock_size_mm both given: write one of them");
  return b;
}

gcode::Dialect post_dialect(const Json& config, const std::optional<std::string>& flag) {
  gcode::Dialect d = gcode::dialect_named(flag.value_or(config["machine"]["post"].get<std::string>()));
  const std::string origin = config["machine"]["work_origin"].get<std::string>();
  d.origin_at = origin == "stock_corner"   ? gcode::WorkOrigin::StockCorner
                : origin == "stock_centre" ? gcode::WorkOrigin::StockCentre
                                           : gcode::WorkOrigin::PartCorner;
  d.stock = stock_block(config);
  return config["machine"]["program_units"].get<std::string>() == "inch" ? gcode::in_inches(d) : d;
}

rough::Params rough_params(const Json& config, const Json& explicit_pocket, const PocketFlags& given,
                           CuttingRecord* record) {
  // What a shop would choose where neither the config nor a flag says (issue 38): the fastest
  // complete planner on roughing levels (docs/roughing.md: offset 59.0 min, SOM 59.7, zigzag 72.9,
  // adaptive 127.8 on the five default test parts) and stock left for the finishing.
  PocketFlags flags = given;
  if (!flags.planner && !explicit_pocket.contains("planner")) flags.planner = std::string(kRoughPlanner);
  if (!flags.stock_to_leave && !explicit_pocket.contains("stock_to_leave")) flags.stock_to_leave = kRoughStockToLeaveMm;
  const Json& r = config["rough"];
  rough::Params p;
  p.stock = stock_block(config);
  p.top_allowance_mm = r["top_allowance_mm"].get<double>();
  p.raster_mm = r["raster_mm"].get<double>();
  p.contour_tolerance_mm = r["contour_tolerance_mm"].get<double>();
  p.floor_allowance_mm = r["floor_allowance_mm"].get<double>();
  p.flat_levels = r["flat_levels"].get<bool>();
  p.flat_levels_everywhere = r["flat_levels_everywhere"].get<bool>();
  p.flat_min_area_mm2 = r["flat_min_area_mm2"].get<double>();
  p.flat_max_angle_deg = r["flat_max_angle_deg"].get<double>();
  p.cut = cut_params(config, explicit_pocket, nullptr, flags, record);
  const PlannerChoice choice = planner_choice(config, p.cut, flags);
  p.planner = choice.spec;
  p.machining = machining_options(choice, config);  // contour: the wall pass per level region (rough adds it, issue 11)
  p.limits = work_limits();
  return p;
}

tooling::Cutter parse_tool(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  auto num = [&](std::size_t i) {
    try {
      std::size_t used = 0;
      const double v = std::stod(parts.at(i), &used);
      if (used != parts[i].size()) throw std::invalid_argument("trailing");
      return v;
    } catch (const std::exception&) {
      throw Error("--tool '" + text + "': expected ball:D, flat:D or bull:D:r (mm)");
    }
  };
  tooling::Cutter c;
  if (parts.size() == 2 && parts[0] == "ball")
    c = tooling::Cutter::ball(num(1));
  else if (parts.size() == 2 && parts[0] == "flat")
    c = tooling::Cutter::flat(num(1));
  else if (parts.size() == 3 && parts[0] == "bull")
    c = tooling::Cutter::bull(num(1), num(2));
  else
    throw Error("--tool '" + text + "': expected ball:D, flat:D or bull:D:r (mm)");
  c.check();
  return c;
}

tooling::Cutter tool_arg(const std::string& text, const Json& config, bool drills) {
  if (text.find(':') != std::string::npos) return parse_tool(text);
  const ToolLibrary lib = tool_library(config);  // kept: the tool is a reference into it
  const tooling::Tool& t = lib.tool(text, "--tool");
  return drills && t.type == tooling::ToolType::Drill ? t.cutter() : cutter_of(t);
}

namespace {

/// The cutting data of the finishing tool rec.tool: spindle and feeds into `p`, each figure's source
/// into `rec` (a figure written in /finish wins).
void finish_tool_data(CuttingRecord& rec, finish::FinishParams& p, FinishSettings::Thinning& thinning,
                      const Json& config, const CuttingSettings& cs, const ToolLibrary& lib) {
  const Json& f = config["finish"];
  rec.library_feeds = cs.library_feeds;
  rec.figures.clear();
  auto written = [&](const char* key) -> std::optional<Figure> {
    if (f[key].is_null()) return std::nullopt;
    return Figure{f[key].get<double>(), std::string("config /finish/") + key};
  };
  const auto w_rpm = written("spindle_rpm"), w_feed = written("feed_mm_min"), w_plunge = written("plunge_feed_mm_min");
  if (w_rpm) check_machine_limit(cs, "spindle_rpm", *w_rpm);  // before the speed is used, naming its key
  if (cs.library_feeds) {
    // The axial depth of a finishing cut is the stock it removes over the design surface.
    const std::string src = library_data(rec, cs, lib, config["simulate"]["allowance_mm"].get<double>(), w_rpm);
    const tooling::CuttingData& d = rec.data;
    take(rec, "spindle_rpm", p.spindle_rpm, d.rpm, w_rpm,
         src + (d.rpm_limited_by.empty() ? "" : ", limited by " + d.rpm_limited_by));
    take(rec, "feed_mm_min", p.feed_mm_min, d.feed_mm_min, w_feed, src + ": fz·z·n at D_eff");
    take(rec, "plunge_feed_mm_min", p.plunge_feed_mm_min, d.feed_plunge_mm_min, w_plunge,
         src + ": feed × /cutting/plunge_factor");
    thinning = {};
    if (!w_feed && cs.factors.max_chip_thinning > 1)
      thinning = {d.d_eff_mm, cs.factors.max_chip_thinning, d.feed_max_mm_min};
  } else {  // FinishParams' defaults are the paper's §6.2 figures
    const finish::FinishParams paper;
    take(rec, "spindle_rpm", p.spindle_rpm, paper.spindle_rpm, w_rpm, "fixed: Korosec & Kopac §6.2, 18,000 min^-1");
    take(rec, "feed_mm_min", p.feed_mm_min, paper.feed_mm_min, w_feed, "fixed: Korosec & Kopac §6.2, 1900 mm/min");
    take(rec, "plunge_feed_mm_min", p.plunge_feed_mm_min, paper.plunge_feed_mm_min, w_plunge,
         "fixed: millnet's 600 mm/min");
  }
  for (const auto& [key, fig] : rec.figures) check_machine_limit(cs, key, fig);
}

}  // namespace

void rest_tool_settings(FinishSettings& s, const std::string& text, const Json& config, const FinishToolFlags& flags) {
  const CuttingSettings cs = cutting_settings(config, flags.material);
  const ToolLibrary lib = tool_library(config);
  CuttingRecord rec;
  finish::FinishParams p = s.params;
  if (text.find(':') != std::string::npos) {
    p.tool = parse_tool(text);
    rec.tool = inline_tool(p.tool.type, p.tool.diameter, p.tool.corner_radius, cs, lib);
  } else {
    rec.tool = lib.tool(text, "--rest-tool");
    p.tool = cutter_of(rec.tool);
  }
  FinishSettings::Thinning thinning;
  finish_tool_data(rec, p, thinning, config, cs, lib);
  s.rest_tool = p.tool;
  s.rest_feeds = FinishSettings::Feeds{p.spindle_rpm, p.feed_mm_min, p.plunge_feed_mm_min};
}

namespace {

/// The finishing tool and its cutting data (issue 17), into s.params and s.cutting; with no tool
/// named anywhere (no --tool, no /finish/tool/id, no /finish/tool/diameter, or id "auto"), also
/// every library ball with its cutting data into s.tool_by_part, for the pick per part (for_part).
void finish_cutting_data(FinishSettings& s, const Json& config, const FinishToolFlags& flags) {
  const Json& t = config["finish"]["tool"];
  auto& p = s.params;
  const CuttingSettings cs = cutting_settings(config, flags.material);
  CuttingRecord& rec = s.cutting;
  const ToolLibrary lib = tool_library(config);
  const std::string id = t["id"].get<std::string>();
  const bool by_part =
      !flags.tool &&
      (id == "auto" || (id.empty() && t["diameter"].is_null() && t["type"].get<std::string>() == "ball"));
  if (flags.tool && flags.tool->find(':') == std::string::npos) {
    rec.tool = lib.tool(*flags.tool, "--tool");
    rec.tool_from = "flag --tool";
    p.tool = cutter_of(rec.tool);
  } else if (flags.tool) {
    p.tool = parse_tool(*flags.tool);
    rec.tool = inline_tool(p.tool.type, p.tool.diameter, p.tool.corner_radius, cs, lib);
    rec.tool_from = "flag --tool";
  } else if (!id.empty() && id != "auto") {
    rec.tool = lib.tool(id, "/finish/tool/id");
    rec.tool_from = "config /finish/tool/id";
    p.tool = cutter_of(rec.tool);
  } else {  // inline; not named at all: the paper's Ø2 ball wherever a part does not pick its own
    rec.tool = inline_tool(p.tool.type, p.tool.diameter, p.tool.corner_radius, cs, lib);
    rec.tool_from = "config /finish/tool";
  }
  finish_tool_data(rec, p, s.thinning, config, cs, lib);
  if (!by_part) return;
  for (const tooling::Tool& ball : lib.tools) {  // O(tools)
    if (ball.type != tooling::ToolType::Ball) continue;
    FinishSettings::ToolChoice c;
    c.cutting.tool = ball;
    c.cutting.tool_from = "picked by the part (no /finish/tool, no --tool)";
    finish::FinishParams q = p;
    q.tool = cutter_of(ball);
    finish_tool_data(c.cutting, q, c.thinning, config, cs, lib);
    c.cutter = q.tool;
    c.spindle_rpm = q.spindle_rpm;
    c.feed_mm_min = q.feed_mm_min;
    c.plunge_feed_mm_min = q.plunge_feed_mm_min;
    s.tool_by_part.push_back(std::move(c));
  }
}

}  // namespace

std::vector<finish::FinishParams> FinishSettings::strategy_params(const std::vector<finish::Strategy>& which,
                                                                  const finish::FinishParams& base) const {
  if (!params_from_spec) return std::vector<finish::FinishParams>(which.size(), base);
  std::vector<finish::FinishParams> out = finish::params_for_spec(which, spec, base);
  if (!(thinning.d_eff_mm > 0)) return out;
  const double w = finish::spec_spacing_mm(base.tool, spec.scallop_mm);  // on the surface, at most
  const double k = std::min(thinning.cap, tooling::chip_thinning_factor(thinning.d_eff_mm, w));
  if (!(k > 1)) return out;
  for (std::size_t i = 0; i < which.size(); ++i) {  // O(strategies)
    if (which[i] == finish::Strategy::Raster || which[i] == finish::Strategy::Waterline) continue;
    finish::FinishParams& p = out[i];
    const double thinned = std::min(std::max(1.0, std::round(p.feed_mm_min * k)), thinning.feed_max_mm_min);
    if (!(thinned > p.feed_mm_min)) continue;
    p.comments.push_back("feed " + format_double(p.feed_mm_min) + " -> " + format_double(thinned) +
                         " mm/min: radial chip thinning at a_e " + fixed(w, 3) + " mm on D_eff " +
                         fixed(thinning.d_eff_mm, 3) + " mm, x" + fixed(thinned / p.feed_mm_min, 3));
    p.feed_mm_min = thinned;
  }
  return out;
}

FinishSettings for_part(const FinishSettings& s, const job::Part& part, std::string* why) {
  if (!s.boundary_faces.empty()) {
    FinishSettings out = s;
    out.boundary_faces.clear();
    out.params.boundary.triangles = job::face_selection(part, s.boundary_faces);
    return for_part(out, part, why);
  }
  const ingest::Mesh& mesh = part.mesh;
  if (s.tool_by_part.empty()) return s;
  const job::Frame frame = job::frame_of(mesh, s.stock_top_above_part_mm);
  const job::PartShape shape = job::part_shape(mesh, frame.stock_top);
  std::vector<tooling::Tool> balls;
  for (const FinishSettings::ToolChoice& c : s.tool_by_part) balls.push_back(c.cutting.tool);
  const tooling::Tool* ball = job::finishing_ball(balls, shape);
  const auto& c = s.tool_by_part[static_cast<std::size_t>(ball - balls.data())];  // never null: balls not empty
  FinishSettings out = s;
  out.tool_by_part.clear();
  out.cutting = c.cutting;
  out.thinning = c.thinning;
  out.params.tool = c.cutter;
  out.params.spindle_rpm = c.spindle_rpm;
  out.params.feed_mm_min = c.feed_mm_min;
  out.params.plunge_feed_mm_min = c.plunge_feed_mm_min;
  if (why == nullptr) return out;
  const double size_limit = shape.size_mm / job::kSizePerDiameter;
  *why = "finishing tool " + (ball->id.empty() ? ball->label() : ball->id) + ": the part's " + fixed(shape.size_mm, 1) +
         " mm footprint allows Ø" + fixed(size_limit, 1) + " (its longer side / " + fixed(job::kSizePerDiameter, 0) +
         ")";
  if (std::isfinite(shape.concave_radius_mm))
    *why += ", its smallest concave radius " + fixed(shape.concave_radius_mm, 2) + " mm Ø" +
            fixed(2 * shape.concave_radius_mm, 1) + " (" + fixed(100 * job::kRestShare, 0) +
            " % of its concave curved edges and every sharp corner left to rest machining)";
  else
    *why += ", it has no concave curved surface";
  if (ball->diameter_mm > std::min(size_limit, 2 * shape.concave_radius_mm) * (1 + 1e-12))
    *why += "; the library has no ball that small reaching " + fixed(shape.depth_mm, 1) +
            " mm below the stock top: its smallest that does";
  return out;
}

void set_boundary_file(FinishSettings& s, const std::string& file) {
  const pocket::PocketFile pf = pocket::read_pocket(file);
  constexpr double kChordMm = 0.001;  // arcs of the outline, flattened
  auto& polys = s.params.boundary.polygons;
  polys.clear();
  polys.push_back(pocket::flatten(pf.region.boundary, kChordMm));
  for (const pocket::Loop& island : pf.region.islands) polys.push_back(pocket::flatten(island, kChordMm));
}

finish::Boundary FinishSettings::boundary_in(const job::Frame& frame) const {
  finish::Boundary b = params.boundary;
  if (z_min) b.z_min = *z_min - frame.z_shift();
  if (z_max) b.z_max = *z_max - frame.z_shift();
  return b;
}

void BoundaryFlags::add_to(CLI::App* sub) {
  sub->add_option("--boundary", file,
                  "machining boundary of the finishing: a closed outline (pocket JSON or DXF, program frame X Y; its "
                  "islands left out) the tool axis stays inside (/finish/boundary/file)")
      ->check(CLI::ExistingFile);
  sub->add_option("--faces", faces,
                  "machining boundary of the finishing on a STEP/IGES part: the faces (1-based index in the file's "
                  "face order, or name; comma-separated) the tool axis stays over (/finish/boundary/faces)")
      ->delimiter(',');
  sub->add_option("--z-range", z_range,
                  "lowest and highest tool tip Z of the finishing cuts, mm, program frame (Z 0 = stock top; "
                  "/finish/boundary/z_min, z_max)")
      ->expected(2);
}

void BoundaryFlags::apply(FinishSettings& s) const {
  if (file) set_boundary_file(s, *file);
  if (!faces.empty()) s.boundary_faces = faces;
  if (z_range.empty()) return;
  if (!(z_range[0] < z_range[1]))
    throw Error("--z-range: the lowest Z (" + format_double(z_range[0]) + ") must be below the highest (" +
                format_double(z_range[1]) + ")");
  s.z_min = z_range[0];
  s.z_max = z_range[1];
}

FinishSettings finish_settings(const Json& config, const FinishToolFlags& flags) {
  const Json& f = config["finish"];
  FinishSettings s;
  auto& p = s.params;
  const Json& t = f["tool"];
  const std::string type = t["type"].get<std::string>();
  const double d = t["diameter"].is_null() ? kPaperBallMm : t["diameter"].get<double>();
  p.tool = type == "ball"   ? tooling::Cutter::ball(d)
           : type == "flat" ? tooling::Cutter::flat(d)
                            : tooling::Cutter::bull(d, t["corner_radius"].get<double>());
  p.stepover_mm = f["stepover_mm"].get<double>();
  p.step_down_mm = f["step_down_mm"].get<double>();
  p.chord_tolerance_mm = f["chord_tolerance_mm"].get<double>();
  p.boundary_angle_deg = f["boundary_angle_deg"].get<double>();
  p.scallop_mm = f["scallop_mm"].get<double>();
  p.raster_angle_deg = f["raster_angle_deg"].get<double>();
  p.safe_z_mm = f["safe_z_mm"].get<double>();
  p.limits = work_limits();
  const Json& b = f["boundary"];
  p.boundary.on_part = b["on_part"].get<bool>();
  if (!b["z_min"].is_null()) s.z_min = b["z_min"].get<double>();
  if (!b["z_max"].is_null()) s.z_max = b["z_max"].get<double>();
  if (!b["file"].is_null()) set_boundary_file(s, b["file"].get<std::string>());
  for (const Json& face : b["faces"])
    s.boundary_faces.push_back(face.is_string() ? face.get<std::string>() : face.dump());
  const std::string strat = f["strategy"].get<std::string>();
  s.strategies = strat == "all" ? finish::all_strategies() : std::vector{finish::parse_strategy(strat)};
  s.aim.aim = simulate::parse_aim(f["aim"].get<std::string>());
  s.aim.time_budget_min = f["time_budget_min"].get<double>();
  s.aim.complete_share = f["complete_margin_share"].get<double>();
  s.params_from_spec = f["params_from"].get<std::string>() == "spec";
  s.spec.scallop_mm = f["spec"]["scallop_mm"].get<double>();
  s.spec.form_tolerance_mm = f["spec"]["form_tolerance_mm"].get<double>();
  s.spec.out_of_spec_share = f["spec"]["out_of_spec_share"].get<double>();
  s.spec.check();
  s.aim.out_of_spec_share = s.spec.out_of_spec_share;
  const Json& sim = config["simulate"];
  s.sim.cell_mm = sim["cell_mm"].get<double>();
  s.sim.cells_per_pass = sim["cells_per_pass"].get<double>();
  s.sim.allowance_mm = sim["allowance_mm"].get<double>();
  s.sim.tolerance_mm = sim["tolerance_mm"].get<double>();
  s.sim.sampling_length_mm = sim["sampling_length_mm"].get<double>();
  s.sim.ra_bins_um = sim["ra_bins_um"].get<std::vector<double>>();
  s.sim.ra_spacing_mm = sim["ra_spacing_mm"].get<double>();
  s.sim.ra_target_um = sim["ra_target_um"].get<double>();
  s.aim.gouge_tolerance_mm = s.sim.tolerance_mm;
  s.machine = motion_model(config);
  s.post = post_dialect(config, std::nullopt);
  s.stock_top_above_part_mm = config["rough"]["top_allowance_mm"].get<double>();
  finish_cutting_data(s, config, flags);
  return s;
}

ingest::PrepareOptions prepare_options(const std::string& units, const std::string& up) {
  ingest::PrepareOptions prep;
  prep.units = ingest::parse_units(units);
  prep.up = ingest::parse_up(up);
  return prep;
}

FinishSettings simulated_finish_settings(const Json& config) {
  FinishSettings s = finish_settings(config, {});
  s.strategies = finish::all_strategies();
  s.simulate = true;
  return s;
}

classifier::TrainParams train_params(const Json& config) {
  const Json& t = config["train"];
  classifier::TrainParams tp;
  tp.search.mode = classifier::loo_mode_from_string(t["loo"].get<std::string>());
  // "auto" is settled by the table (learn.cpp: train_model); here it reads as the paper's.
  tp.criterion =
      t["criterion"].get<std::string>() == "regret" ? classifier::Criterion::Regret : classifier::Criterion::Rms;
  tp.limits = work_limits();
  tp.search.steps_per_octave = t["steps_per_octave"].get<int>();
  tp.search.range_low = t["range_low"].get<double>();
  tp.search.range_high = t["range_high"].get<double>();
  if (!t["alpha_min"].is_null() && !t["alpha_max"].is_null()) {
    tp.search.alpha_min = t["alpha_min"].get<double>();
    tp.search.alpha_max = t["alpha_max"].get<double>();
  }
  tp.search.refine_tolerance_octaves = t["refine_tolerance_octaves"].get<double>();
  if (!t["fixed_alpha"].is_null()) tp.fixed_alpha = t["fixed_alpha"].get<double>();
  tp.unfamiliar_factor = t["unfamiliar_factor"].get<double>();
  tp.unfamiliar_percentile = t["unfamiliar_percentile"].get<double>();
  return tp;
}

augment::AugmentParams predict_augment(const Json& config) { return augment_from(config["predict"]["augment"]); }

RunSettings run_settings(const Json& config) {
  const Json& run = config["run"];
  RunSettings s;
  s.rough = run["rough"].get<bool>();
  s.finish = run["finish"].get<bool>();
  s.job = s.finish && run["job"].get<bool>();
  for (const auto& p : run["test_parts"])
    s.test_parts.push_back({p["file"].get<std::string>(), p.value("name", std::string()), p["label"].get<int>()});
  s.generate.seed = run["generate_test_parts"]["seed"].get<std::uint64_t>();
  s.generate.per_family = run["generate_test_parts"]["per_family"].get<int>();
  s.generate.resolution = config["dataset"]["generate"]["resolution"].get<int>();
  s.generate_dir = run["test_parts_dir"].get<std::string>();
  if (s.test_parts.empty() && config["dataset"]["parts"].empty() &&
      s.generate.seed == config["dataset"]["generate"]["seed"].get<std::uint64_t>())
    throw Error("/run/generate_test_parts/seed equals /dataset/generate/seed: the test parts would be training parts");
  return s;
}

}  // namespace millnet::app
