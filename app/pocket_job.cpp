#include "pocket_job.hpp"
#include "preview.hpp"
#include "cli.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/io/tables.hpp"
#include "millnet/pocket/work.hpp"
#include "millnet/report/plots.hpp"

namespace millnet::app {
namespace fs = std::filesystem;

pocket::PlanResult plan_region(const pocket::Region& region, const pocket::CutParams& cut, const PlannerChoice& ch) {
  const pocket::PlannerSpec& spec = ch.spec;
  pocket::check_work(region, cut, spec, work_limits());  // before anything is allocated (issue 12)
  return pocket::plan(region, cut, spec);
}

Json cut_json(const pocket::CutParams& c) {
  Json j = Json::object();
  j["tool_diameter"] = c.tool.diameter;
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
  j["predrill"] = pocket::xy_pairs(plan.predrill);
  j["parameters"] = cut_json(cut);
  // Only when it says something: the metrics of a cleared pocket stay as they were.
  if (const std::string w = uncut_warning(plan, m); !w.empty()) {
    j["cleared"] = false;
    j["warning"] = w;
  }
  return j;
}

std::string uncut_warning(const pocket::PlanResult& plan, const pocket::MachiningResult& m) {
  const double uncut = m.metrics.uncut_area_mm2;
  if (m.status != pocket::PlanStatus::Ok || !(uncut > pocket::kClearedUncutMm2)) return {};
  const double reachable = m.metrics.reachable_area_mm2;
  const std::string share = reachable > 0 ? " (" + fixed(100.0 * uncut / reachable, 1) + " % of the reachable " +
                                                fixed(reachable, 0) + " mm²)"
                                          : std::string();
  return "the " + plan.planner + " plan leaves " + fixed(uncut, 1) + " mm² uncut" + share + ", more than the " +
         fixed(pocket::kClearedUncutMm2, 0) + " mm² a cleared pocket may leave (uncut_area_mm2 in the metrics)";
}

void write_pocket_outputs(const fs::path& dir, const std::string& stem, const pocket::Region& region,
                          const pocket::CutParams& cut, const PlannerChoice& ch, const pocket::PlanResult& plan,
                          const pocket::MachiningResult& m, const std::vector<std::string>& notes,
                          const gcode::Dialect& post, const Json& cutting_data) {
  Json metrics = metrics_json(plan, m, cut, ch);
  if (!cutting_data.is_null()) metrics["cutting_data"] = cutting_data;
  if (!notes.empty()) metrics["notes"] = notes;
  // Tool points (x,y) in the planner's order of discovery.
  write_file_atomic(dir / (stem + ".points.csv"), pocket::tool_points_csv(plan.tool_points.pts));
  // Feed profile along the path (seed Fig. 14).
  write_file_atomic(dir / (stem + ".feed.csv"), pocket::feed_profile_csv(m.feed_profile));
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
                                    fixed(cut.tool.diameter, 1) + ", stepover " + fixed(cut.stepover, 1),
                                block);
  (void)report::feed_profile_png(dir / (stem + ".feed.png"), m.feed_profile,
                                 stem + ": engagement, feed and MRR along the path (first level)");
  if (m.status == pocket::PlanStatus::Ok) {
    report::PreviewInput page;  // the 3D page of the program just written (issue 16)
    page.title = stem + " — " + metrics["planner"].get<std::string>();
    page.programs.push_back(
        {metrics["planner"].get<std::string>(), gcode::write_program(dir / (stem + ".nc"), m.program, post)});
    page.tool = {cut.tool.diameter, cut.tool.profile_corner_radius(), cut.tool.describe()};
    (void)write_program_preview(dir / (stem + ".html"), std::move(page));
  }
  write_file_atomic(dir / (stem + ".metrics.json"), metrics.dump(2) + "\n");
}

}  // namespace millnet::app
