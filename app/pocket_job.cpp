#include "pocket_job.hpp"
#include "cli.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/io/tables.hpp"
#include "millnet/report/plots.hpp"

#include <cmath>


namespace millnet::app {
namespace fs = std::filesystem;

void PocketFlags::add_to(CLI::App* sub, bool with_planner_flags, bool with_depth) {
  sub->add_option("--tool-diameter", tool_diameter, "flat end mill diameter, mm")->check(schema_range("/pocket/tool_diameter"));
  sub->add_option("--stepover", stepover, "grid spacing / pass distance, mm")->check(schema_range("/pocket/stepover"));
  if (with_depth) sub->add_option("--depth", depth, "pocket depth, mm (floor Z = -depth)")->check(schema_range("/pocket/depth"));
  sub->add_option("--step-down", step_down, "maximum depth of cut per level, mm")->check(schema_range("/pocket/step_down"));
  sub->add_option("--safe-z", safe_z, "retract height, mm")->check(schema_range("/pocket/safe_z"));
  sub->add_option("--stock-to-leave", stock_to_leave, "radial allowance on walls and islands, mm")
      ->check(schema_range("/pocket/stock_to_leave"));
  sub->add_option("--entry", entry, "entry into uncut material")->check(CLI::IsMember({"predrill", "helix", "ramp"}));
  sub->add_flag("--contour", contour, "finish with a contour pass along the walls");
  if (with_planner_flags) {
    sub->add_option("--planner", planner, "planner")->check(CLI::IsMember({"som", "zigzag"}));
    sub->add_option("--partition", partition, "zigzag partition (T: Tang, I: Suh & Kim)")
        ->check(CLI::IsMember({"t", "i", "T", "I"}));
    sub->add_option("--angle", angle, "zigzag reference angle in degrees, or auto");
  }
}

Json explicit_pocket_section(const std::string& config_path) {
  if (config_path.empty()) return Json::object();
  const Json raw = read_json(config_path);
  if (raw.is_object() && raw.contains("pocket") && raw["pocket"].is_object()) return raw["pocket"];
  return Json::object();
}

pocket::CutParams cut_params(const Json& config, const Json& explicit_pocket, const pocket::PocketFile* file,
                             const PocketFlags& flags) {
  const Json& pc = config["pocket"];
  pocket::CutParams c;
  auto pick = [&](double& dst, const char* key, const std::optional<double>& from_file, const std::optional<double>& flag) {
    dst = pc[key].get<double>();                                     // config (explicit or default)
    if (from_file && !explicit_pocket.contains(key)) dst = *from_file;  // the pocket file's own key
    if (flag) dst = *flag;                                           // the command line
  };
  const std::optional<double> none;
  pick(c.tool_diameter, "tool_diameter", file ? file->tool_diameter : none, flags.tool_diameter);
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
  c.rapid_rate = pc["rapid_rate"].get<double>();
  if (c.stepover > c.tool_diameter)
    throw Error("stepover " + format_double(c.stepover) + " mm exceeds the tool diameter " +
                format_double(c.tool_diameter) + " mm: ridges of material would be left between passes");
  if (c.feed_min > c.feed_max) throw Error("/pocket/feed_min exceeds /pocket/feed_max");
  return c;
}

PlannerChoice planner_choice(const Json& config, const pocket::CutParams& cut, const PocketFlags& flags) {
  const Json& pc = config["pocket"];
  PlannerChoice ch;
  ch.name = flags.planner.value_or(pc["planner"].get<std::string>());
  ch.entry = pocket::parse_entry(flags.entry.value_or(pc["entry"].get<std::string>()));
  ch.contour = flags.contour || pc["contour"].get<bool>();
  ch.frame.origin = {pc["grid"]["origin_x"].get<double>(), pc["grid"]["origin_y"].get<double>()};
  ch.frame.angle_deg = pc["grid"]["angle_deg"].get<double>();
  ch.frame.spacing = cut.stepover;
  const Json& s = pc["som"];
  ch.som.node_factor = s["node_factor"].get<double>();
  ch.som.g0 = s["g0"].get<double>();
  ch.som.alpha = s["alpha"].get<double>();
  ch.som.adaptive_alpha = s["adaptive_alpha"].get<bool>();
  ch.som.c = s["c"].get<double>();
  ch.som.k_scale_mm = s["k_scale_mm"].get<double>();
  ch.som.alpha_min = s["alpha_min"].get<double>();
  ch.som.w = s["w"].get<double>();
  ch.som.max_passes = s["max_passes"].get<int>();
  ch.som.tolerance_mm = s["tolerance_mm"].get<double>();
  ch.som.seed = config["seed"].get<std::uint64_t>();
  const Json& m = pc["smoothing"];
  ch.smooth.linking = m["linking"].get<bool>();
  ch.smooth.link_max_ratio = m["link_max_ratio"].get<double>();
  ch.smooth.link_max_mm = m["link_max_mm"].get<double>();
  ch.smooth.weak = m["weak"].get<bool>();
  ch.smooth.extra_passes = m["extra_passes"].get<bool>();
  ch.smooth.opt_neighbours = m["opt_neighbours"].get<int>();
  ch.smooth.retract_penalty_mm = m["retract_penalty_mm"].get<double>();
  ch.smooth.max_opt_moves = m["max_opt_moves"].get<long>();
  const Json& z = pc["zigzag"];
  std::string part = flags.partition.value_or(z["partition"].get<std::string>());
  ch.zigzag.partition = (part == "t" || part == "T") ? pocket::PartitionKind::T : pocket::PartitionKind::I;
  std::string angle = flags.angle ? *flags.angle : (z["angle"].is_string() ? z["angle"].get<std::string>() : "");
  if (!flags.angle && z["angle"].is_number()) {
    ch.zigzag.angle_deg = z["angle"].get<double>();
  } else if (angle == "auto") {
    ch.zigzag.angle_deg = std::nullopt;
  } else {
    try {
      std::size_t used = 0;
      ch.zigzag.angle_deg = std::stod(angle, &used);
      if (used != angle.size() || !(std::abs(*ch.zigzag.angle_deg) <= 360)) throw std::invalid_argument(angle);
    } catch (const std::exception&) {
      throw Error((flags.angle ? std::string("--angle") : std::string("/pocket/zigzag/angle")) +
                  ": expected a number of degrees in [-360, 360] or \"auto\", got \"" + angle.substr(0, 40) + "\"");
    }
  }
  return ch;
}

pocket::PlannerSpec planner_spec(const PlannerChoice& ch) {
  if (ch.name == "som") return pocket::SomSpec{ch.frame, ch.som, ch.smooth};
  if (ch.name == "zigzag") return pocket::ZigzagSpec{ch.zigzag};
  throw Error("unknown planner '" + ch.name + "' (expected som or zigzag)");
}

pocket::PlanResult plan_region(const pocket::Region& region, const pocket::CutParams& cut, const PlannerChoice& ch) {
  return pocket::plan(region, cut, planner_spec(ch));
}

Json cut_json(const pocket::CutParams& c) {
  Json j = Json::object();
  j["tool_diameter"] = c.tool_diameter;
  j["stepover"] = c.stepover;
  j["stock_to_leave"] = c.stock_to_leave;
  j["depth"] = c.depth;
  j["step_down"] = c.step_down;
  j["safe_z"] = c.safe_z;
  j["feed_slot"] = c.feed_slot;
  j["feed_half"] = c.feed_half;
  j["feed_plunge"] = c.feed_plunge;
  j["feed_min"] = c.feed_min;
  j["feed_max"] = c.feed_max;
  j["spindle_rpm"] = c.spindle_rpm;
  j["feed_grid"] = c.feed_grid;
  j["feed_adjust"] = c.feed_adjust;
  return j;
}

Json metrics_json(const pocket::PlanResult& plan, const pocket::MachiningResult& m, const pocket::CutParams& cut,
                  const PlannerChoice& ch) {
  Json j = Json::object();
  j["status"] = pocket::to_string(m.status);
  if (!m.message.empty()) j["message"] = m.message;
  j["planner"] = plan.planner.empty() ? ch.name : plan.planner;
  for (const auto& [k, v] : m.metrics.to_key_values()) j[k] = v;
  j["entry"] = std::string(pocket::to_string(ch.entry));
  j["contour"] = ch.contour;
  // The entry points that need a pre-drilled hole (drilled first in the program with entry "predrill").
  Json holes = Json::array();
  for (const auto& p : plan.predrill) holes.push_back({p.x(), p.y()});
  j["predrill"] = holes;
  j["parameters"] = cut_json(cut);
  return j;
}

void write_pocket_outputs(const fs::path& dir, const std::string& stem, const pocket::Region& region,
                          const pocket::CutParams& cut, const PlannerChoice& ch, const pocket::PlanResult& plan,
                          const pocket::MachiningResult& m, const std::vector<std::string>& notes) {
  Json metrics = metrics_json(plan, m, cut, ch);
  if (!notes.empty()) metrics["notes"] = notes;
  // Tool points (x,y) in the planner's order of discovery.
  write_file_atomic(dir / (stem + ".points.csv"), pocket::tool_points_csv(plan.tool_points.pts));
  // Feed profile along the path (seed Fig. 14).
  write_file_atomic(dir / (stem + ".feed.csv"), pocket::feed_profile_csv(m.feed_profile));
  std::vector<double> s, n3, f, mrr;
  for (const auto& p : m.feed_profile.pieces) {  // the plot's series
    s.push_back(p.s_mm);
    n3.push_back(p.engagement);
    f.push_back(p.feed);
    mrr.push_back(p.mrr_mm3_min);
  }
  std::vector<std::pair<std::string, std::string>> block;
  block.emplace_back("planner", metrics["planner"].get<std::string>());
  block.emplace_back("tool points", fixed(m.metrics.tool_points, 0));
  block.emplace_back("cut length", fixed(m.metrics.cut_length_mm, 0) + " mm");
  block.emplace_back("rapid length", fixed(m.metrics.rapid_length_mm, 0) + " mm");
  block.emplace_back("retractions", fixed(m.metrics.retractions, 0));
  block.emplace_back("time (adjusted feed)", fixed(m.metrics.time_adjusted_min, 1) + " min");
  block.emplace_back("time (constant feed)", fixed(m.metrics.time_constant_min, 1) + " min");
  (void)report::pocket_path_png(dir / (stem + ".png"), region, plan.tool_points.pts, m.path,
                                stem + " - " + metrics["planner"].get<std::string>() + ", tool D" +
                                    fixed(cut.tool_diameter, 1) + ", stepover " + fixed(cut.stepover, 1),
                                block);
  if (s.size() >= 2) {
    (void)report::profile_png(dir / (stem + ".feed.png"), s,
                              {{"engagement n3 (cells)", {{"n3", n3}}},
                               {"feed (mm/min)", {{"feed", f}}},
                               {"MRR (mm^3/min)", {{"MRR", mrr}}}},
                              stem + ": engagement, feed and MRR along the path (first level)", {.steps = true});
  }
  if (m.status == pocket::PlanStatus::Ok) write_file_atomic(dir / (stem + ".nc"), m.gcode);
  write_file_atomic(dir / (stem + ".metrics.json"), metrics.dump(2) + "\n");
}

}  // namespace millnet::app
