#include "rough.hpp"
#include "preview.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/report/plots.hpp"

namespace millnet::app {
namespace fs = std::filesystem;

Json write_rough_outputs(const fs::path& dir, const std::string& stem, const rough::Result& r, const rough::Params& p,
                         const gcode::Dialect& post, const Json& cutting_data, const ingest::Mesh* part,
                         const Json& cad) {
  const std::vector<rough::LevelSummary> summaries = rough::level_summaries(r);
  Json levels = Json::array();
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const rough::Level& lv = r.levels[k];
    const rough::LevelSummary& s = summaries[k];
    levels.push_back({{"level", k + 1},
                      {"z", lv.z},
                      {"z_part_mm", lv.z_part},
                      {"regions", lv.regions.size()},
                      {"islands", lv.islands},
                      {"tool_points", static_cast<double>(s.tool_points)},
                      {"chains", s.chains},
                      {"retractions", s.chains > 0 ? s.chains - 1 : 0},
                      {"cut_length_mm", s.cut_length_mm},
                      {"uncut_area_mm2", s.uncut_area_mm2},
                      {"status", lv.status},
                      {"flat_z_part_mm", std::isnan(lv.flat_z_part) ? Json(nullptr) : Json(lv.flat_z_part)}});
    (void)report::level_png(dir / (stem + ".level_" + std::to_string(k + 1) + ".png"), lv.regions, s.path, lv.z, stem,
                            {{"islands", std::to_string(lv.islands)},
                             {"cut", fixed(s.cut_length_mm, 0) + " mm"},
                             {"chains", std::to_string(s.chains)}});
  }
  Json j = Json::object();
  j["status"] = pocket::to_string(r.machining.status);
  if (!r.machining.message.empty()) j["message"] = r.machining.message;
  j["planner"] = std::string(pocket::planner_name(p.planner));
  j["stock_top_above_part_mm"] = p.top_allowance_mm;
  j["stock_to_leave_mm"] = p.cut.stock_to_leave;
  j["stock"] = {
      {"x0", r.stock_x0}, {"y0", r.stock_y0}, {"x1", r.stock_x1}, {"y1", r.stock_y1}, {"height_mm", r.stock_top_part}};
  j["raster_mm"] = p.raster_mm;
  j["contour_tolerance_mm"] = p.contour_tolerance_mm;
  j["tool_points"] = r.tool_points;
  j["planning_time_s"] = r.planning_time_s;
  for (const auto& [k, v] : r.machining.metrics.to_key_values())
    if (!j.contains(k)) j[k] = v;
  j["levels"] = r.levels.size();
  j["per_level"] = levels;
  j["parameters"] = cut_json(p.cut);
  if (!cutting_data.is_null()) j["cutting_data"] = cutting_data;
  if (!cad.is_null()) j["cad"] = cad;  // the part came from STEP/IGES: its unit and tessellation
  if (r.machining.status == pocket::PlanStatus::Ok) {
    report::PreviewInput page;  // the 3D page of the program just written (issue 16)
    page.title = stem + " — roughing, " + std::string(pocket::planner_name(p.planner));
    // The work origin on the stock (around the part's footprint, as the roughing took it).
    const gcode::Dialect placed = gcode::placed(post, r.part_x0, r.part_y0, r.part_x1, r.part_y1);
    page.programs.push_back({"roughing", gcode::write_program(dir / (stem + ".nc"), r.machining.program, placed)});
    const tooling::Cutter& cutter = p.cut.tool;
    page.tool = {cutter.diameter, cutter.profile_corner_radius(), cutter.describe()};
    // Program Z = part z − stock top (rough.hpp); the part's base is its lowest point.
    const double base = part != nullptr ? part->V.col(2).minCoeff() : 0.0;
    page.stock = std::array<double, 6>{r.stock_x0, r.stock_y0, base - r.stock_top_part, r.stock_x1, r.stock_y1, 0};
    if (part != nullptr) set_preview_part(page, *part, -r.stock_top_part);
    page.notes.push_back(std::to_string(r.levels.size()) + " Z levels");
    (void)write_program_preview(dir / (stem + ".html"), std::move(page));
  }
  write_file_atomic(dir / (stem + ".metrics.json"), j.dump(2) + "\n");
  return j;
}

}  // namespace millnet::app
