// millnet finish / simulate: job/'s values written to files (finish_job.hpp).
#include "finish_job.hpp"

#include "millnet/job/operations.hpp"

#include "cli.hpp"
#include "preview.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/gcode/bounds.hpp"
#include "millnet/gcode/polylines.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/report/plots.hpp"
#include "millnet/report/tables.hpp"
#include "millnet/simulate/io/zmap_file.hpp"
#include "millnet/simulate/maps.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

/// A picture never needs more than this many cells per side (heat_map_png draws ≥ 1 px per cell).
constexpr int kMaxPictureCells = 500;

/// A map of the part's z-map grid shrunk for a picture (block means, `empty` where a block has no cell).
template <class T>
Eigen::MatrixXd picture_map(const std::vector<T>& v, const simulate::GridSpec& g, double empty) {
  return simulate::block_means(v, g.nx, g.ny, kMaxPictureCells, empty);
}

}  // namespace

simulate::ZMap stock_from_file(const std::string& file, const simulate::GridSpec& g) {
  return saved_stock_from_file(file, g).zmap;
}

simulate::io::SavedStock saved_stock_from_file(const std::string& file, const simulate::GridSpec& g) {
  simulate::io::SavedStock saved = simulate::io::read_saved_stock(file);
  const simulate::GridSpec& s = saved.zmap.spec();
  auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9; };
  if (s.nx != g.nx || s.ny != g.ny || !same(s.cell, g.cell) || !same(s.x0, g.x0) || !same(s.y0, g.y0))
    throw file_error(file, "its grid (" + std::to_string(s.nx) + " × " + std::to_string(s.ny) + " cells of " +
                               fixed(s.cell, 4) + " mm at " + fixed(s.x0, 3) + ", " + fixed(s.y0, 3) +
                               ") is not this part's (" + std::to_string(g.nx) + " × " + std::to_string(g.ny) +
                               " cells of " + fixed(g.cell, 4) + " mm at " + fixed(g.x0, 3) + ", " + fixed(g.y0, 3) +
                               "): save and reuse a stock with the same mesh, --units, --up and /simulate/cell_mm");
  return saved;
}

Json sim_metrics_json(const simulate::SurfaceMetrics& m, const simulate::GridSpec& grid) {
  Json j;
  j["max_gouge_mm"] = m.max_gouge_mm;
  j["gouge_line"] = m.gouged ? Json(m.first_gouge_move.line) : Json(nullptr);
  if (m.gouged && m.gouge_cell < grid.cells()) {  // where the deepest one is, and the move that cut it
    j["gouge_deepest_xy_mm"] = {grid.x(m.gouge_cell % grid.nx), grid.y(m.gouge_cell / grid.nx)};
    j["gouge_deepest_line"] = m.gouge_has_move ? Json(m.gouge_move.line) : Json(nullptr);
  }
  if (m.gouge_checked) {  // the exact check ran (issue 37 §1): what the z-map said, what became of it
    if (m.gouged) j["gouge_xy_mm"] = {m.gouge_x_mm, m.gouge_y_mm};
    j["zmap_max_gouge_mm"] = m.zmap_max_gouge_mm;
    j["zmap_gouge_places"] = m.zmap_gouge_places;
    j["gouge_places_checked"] = m.gouge_places_checked;
    j["zmap_gouge_artefacts"] = m.gouge_places_refuted;
  }
  j["scallop_max_mm"] = m.scallop_max_mm;
  j["ra_mean_um"] = m.ra_mean_um;
  j["ra_median_um"] = m.ra_median_um;
  j["ra_p90_um"] = m.ra_p90_um;
  j["ra_histogram"] = Json{{"bin_edges_um", m.ra_bin_edges_um}, {"shares", m.ra_share}};
  if (m.not_machined_cells > 0) {  // issue 37 §1: surface left at the stock has no Ra
    j["ra_histogram"]["not_machined_share"] = m.ra_not_machined_share;
    j["not_machined_cells"] = m.not_machined_cells;
  }
  j["uncut_area_mm2"] = m.uncut_area_mm2;
  j["remaining_area_mm2"] = m.remaining_area_mm2;
  j["scallop_area_mm2"] = m.scallop_area_mm2;
  j["rest_area_mm2"] = m.rest_area_mm2;
  j["surface_cells"] = m.surface_cells;
  if (!std::isnan(m.ra_target_share)) j["ra_target_share"] = m.ra_target_share;
  if (m.spec_measured) {  // issue 37 §2: the surface specification, and where and how much it is missed
    const double a = grid.cell * grid.cell;
    Json sp{{"share_in_spec", m.spec_share},
            {"judged_area_mm2", static_cast<double>(m.spec_cells) * a},
            {"over_spec_area_mm2", static_cast<double>(m.over_spec_cells) * a},
            {"not_machined_area_mm2", static_cast<double>(m.spec_not_machined_cells) * a},
            {"over_spec_max_mm", m.over_spec_max_mm}};
    if (m.over_spec_cell < grid.cells())
      sp["over_spec_max_xy_mm"] = {grid.x(m.over_spec_cell % grid.nx), grid.y(m.over_spec_cell / grid.nx)};
    j["spec"] = sp;
  }
  return j;
}

namespace {

/// A map over the z-map grid as a heat-map PNG with the footprint's extent.
template <class T>
void grid_png(const fs::path& path, const std::vector<T>& values, const simulate::GridSpec& g, const std::string& title,
              const std::string& units) {
  const Eigen::MatrixXd m = picture_map(values, g, 0.0);
  report::HeatMapOptions o;
  o.extent_mm = std::array<double, 4>{0, static_cast<double>(g.nx) * g.cell, 0, static_cast<double>(g.ny) * g.cell};
  // The scale a few extreme cells (an uncut corner's Ra, a step left by the roughing) do not flatten.
  const report::ColourRange r = report::robust_range(m);
  if (r.hi > r.lo) {
    o.value_range = std::pair{r.lo, r.hi};
    o.below_share = r.below_share;
    o.above_share = r.above_share;
  } else {
    o.value_range = std::pair{m.minCoeff(), m.minCoeff() + 1};
  }
  (void)report::heat_map_png(path, m, title, units, o);
}

void ra_png(const fs::path& path, const simulate::GridSpec& g, const simulate::SurfaceMetrics& m,
            const std::string& title) {
  grid_png(path, m.ra_um, g, title, "Ra (um)");  // the float map itself: no 8 B-per-cell copy
}

/// The 3D page's part and stock in the frame.
void frame_page(report::PreviewInput& page, const job::Part& part, const job::Frame& frame) {
  set_preview_part(page, part.mesh, frame.z_shift());
  page.stock = std::array<double, 6>{0, 0, frame.program_bottom(), frame.width, frame.depth, 0};
}

/// The holder check on what the plans machine: each one's lowest move (a finishing program's rapids
/// stop above its cuts), below the stock top.
void check_plans_reach(const FinishSettings& settings, const std::vector<finish::FinishPlan>& plans) {
  for (const finish::FinishPlan& plan : plans)  // O(strategies)
    job::check_reach(settings.cutting.tool.cutter(), settings.cutting.tool.label(), -job::deepest_z(plan.program),
                     "the finishing's lowest cut (" + finish::strategy_name(plan.strategy) + ")");
}

PartJob part_job(const job::Part& part, const FinishSettings& settings, const fs::path& out) {
  PartJob job = finishing_job(part, settings);
  // The picture under the paths: the part's heights (program frame), downsampled.
  const double pic_step = std::max(job.frame.width, job.frame.depth) / kMaxPictureCells;
  job.hf = ingest::rasterize_top(part.mesh, std::max(pic_step, 1e-3));
  job.heights = ingest::height_matrix(job.hf, job.frame.z_shift());
  fs::create_directories(out);
  return job;
}

/// The path over the part's heights.
void path_png(const fs::path& path, const PartJob& job, const gcode::Program& program, const std::string& title) {
  gcode::XyPaths paths = gcode::xy_paths(program);
  const ingest::HeightField& hf = job.hf;
  report::HeatMapOptions ho;
  ho.extent_mm = std::array<double, 4>{hf.x0 - 0.5 * hf.step_x, hf.x0 + (hf.nx - 0.5) * hf.step_x,
                                       hf.y0 - 0.5 * hf.step_y, hf.y0 + (hf.ny - 0.5) * hf.step_y};
  ho.overlay_cuts = std::move(paths.cuts);
  ho.overlay_rapids = std::move(paths.rapids);
  const Eigen::MatrixXd& h = job.heights;
  if (!(h.maxCoeff() > h.minCoeff())) ho.value_range = std::pair{h.minCoeff(), h.minCoeff() + 1};
  (void)report::heat_map_png(path, h, title, "Z (mm)", ho);
}

/// One planned strategy written (program, metrics, pictures, page) and, with settings.simulate,
/// machined on the z-map and scored (job::score_program).
job::StrategyOutcome strategy_outcome(const job::Part& part, const FinishSettings& settings, PartJob& job,
                                      const finish::FinishPlan& plan, const fs::path& out,
                                      const finish::FinishParams& params) {
  const std::string& stem = part.name;
  const std::string title = stem + ": " + finish::strategy_name(plan.strategy);
  const std::string base = stem + ".s" + std::to_string(static_cast<int>(plan.strategy));
  // Written in memory first: a program that gouges is kept under a name that says so.
  gcode::Written written = gcode::written(plan.program, job.frame.post(settings.post), (out / (base + ".nc")).string());
  job::StrategyOutcome o = job::planned_outcome(plan, gcode::stats(plan.program, settings.machine));
  o.stepover_mm = params.stepover_mm;
  o.step_down_mm = params.step_down_mm;
  o.scallop_mm = params.scallop_mm;
  o.feed_mm_min = params.feed_mm_min;
  path_png(out / (base + ".png"), job, plan.program, title);
  std::optional<report::PreviewSurface> surface;
  if (job.design) {  // the program as the machine gets it: the text written, read back
    job::Scored s = job::score_program(*job.design, job.frame, written.program, job.params.tool, sim_params(settings),
                                       std::move(job.spare));
    if (preview_settings().enabled) surface = preview_surface(s.machined, job.design->heights);
    if (s.metrics.gouge_places_refuted > 0)
      info(base + ".nc: " + std::to_string(s.metrics.gouge_places_refuted) +
           " z-map gouge place(s) refuted by the exact check (cell artefacts; the z-map said " +
           fixed(s.metrics.zmap_max_gouge_mm, 4) + " mm)");
    ra_png(out / (base + ".ra.png"), job.design->grid, s.metrics, title + ", roughness Ra");
    std::vector<float>().swap(s.metrics.ra_um);  // drawn; not copied into the outcome (4 B per cell)
    job::add_simulation(o, s, job.design->grid);
    job.spare = std::move(s.machined);
  }
  write_file_atomic(out / program_file_name(base, o), written.text);
  report::PreviewInput page;  // the 3D page of the program (issue 16), with its machined surface when simulated
  page.title = base + " — " + finish::strategy_name(plan.strategy);
  page.programs.push_back({finish::strategy_name(plan.strategy), std::move(written)});
  const tooling::Cutter& tool = job.params.tool;
  page.tool = {tool.diameter, tool.profile_corner_radius(), tool.describe()};
  frame_page(page, part, job.frame);
  page.surface = std::move(surface);
  (void)write_program_preview(out / (base + ".html"), std::move(page));
  write_file_atomic(out / (base + ".metrics.json"), strategy_metrics(o, settings, part).dump(2) + "\n");
  return o;
}

}  // namespace

PartJob finishing_job(const job::Part& part, const FinishSettings& settings, bool with_dropper) {
  PartJob job;
  settings.params.check();
  job.frame = job::frame_of(part.mesh, settings.stock_top_above_part_mm);
  finish::Boundary in_program = settings.params.boundary;  // the Z range as given (program frame)
  in_program.z_min = settings.z_min.value_or(in_program.z_min);
  in_program.z_max = settings.z_max.value_or(in_program.z_max);
  if (settings.simulate) {
    job.design = job::design_surface(part.mesh, job.frame, sim_params(settings));
    job::judge_within(*job.design, in_program);
  }
  // The holder check on the depth the finishing machines: over the whole footprint box (on_part
  // false, no outline), down to the part's lowest point (or the Z range's floor) before planning;
  // inside a boundary, each plan's lowest cut after planning (check_plans_reach).
  const finish::Boundary& b = settings.params.boundary;
  if (b.polygons.empty() && !b.on_part)
    job::check_reach(settings.cutting.tool.cutter(), settings.cutting.tool.label(),
                     job.frame.depth_below_top(std::max(job.frame.part_bottom, in_program.z_min + job.frame.stock_top)),
                     "the part");
  std::vector<std::string> tool_lines = settings.cutting.header();
  if (tool_lines.empty()) tool_lines.push_back("tool: " + settings.params.tool.describe());
  job.params = job::part_params(settings.params, job.frame, part.name, std::move(tool_lines));
  job.params.boundary = settings.boundary_in(job.frame);
  if (with_dropper) job.dropper.emplace(part.mesh, job.params.tool);
  return job;
}

std::string program_file_name(const std::string& base, const job::StrategyOutcome& o) {
  return base + (o.simulated && o.surface.gouged ? ".GOUGES.nc" : ".nc");
}

std::string gouge_failure(const std::string& program, const simulate::SurfaceMetrics& m) {
  return program + " gouges the part: " + fixed(m.max_gouge_mm, 4) + " mm deep at G-code line " +
         std::to_string(m.gouge_move.line) + ", X " + fixed(m.gouge_x_mm, 3) + " Y " + fixed(m.gouge_y_mm, 3) +
         " (confirmed by the exact check; first gouging line " + std::to_string(m.first_gouge_move.line) + ")";
}

Json strategy_metrics(const job::StrategyOutcome& o, const FinishSettings& settings, const job::Part& part) {
  Json j;
  j["strategy"] = static_cast<int>(o.strategy);
  j["strategy_name"] = finish::strategy_name(o.strategy);
  j["tool"] = settings.params.tool.describe();
  j["cutting_data"] = settings.cutting.to_json();
  if (const Json cad = cad_metrics(part); !cad.is_null()) j["cad"] = cad;
  j["stock_top_above_part_mm"] = settings.stock_top_above_part_mm;
  j["path_length_mm"] = o.path_length_mm;
  j["time_feed_min"] = o.time_feed_min;
  j["time_kinematic_min"] = o.time_kinematic_min;
  j["lifts"] = o.lifts;
  j["passes"] = o.passes;
  j["cl_points"] = o.cl_points;
  j["drops"] = o.drops;  // a property of the strategy: the same planned alone (MPI) or with others
  j["planning_s"] = o.planning_s;
  j["params"] = Json{{"from", settings.params_from_spec ? "spec" : "fixed"},
                     {"stepover_mm", o.stepover_mm},
                     {"step_down_mm", o.step_down_mm},
                     {"scallop_mm", o.scallop_mm},
                     {"feed_mm_min", o.feed_mm_min}};
  if (o.simulated) {
    j.update(sim_metrics_json(o.surface, o.grid));
    j["cutting_rapids"] = o.cutting_rapids;
    j["max_depth_of_cut_mm"] = o.max_depth_of_cut_mm;
  }
  return j;
}

job::StrategyOutcome outcome_from_metrics(const Json& j, double cell_mm) {
  job::StrategyOutcome o;
  o.strategy = static_cast<finish::Strategy>(j.at("strategy").get<int>());
  o.path_length_mm = j.at("path_length_mm").get<double>();
  o.lifts = j.at("lifts").get<std::size_t>();
  o.passes = j.at("passes").get<std::size_t>();
  o.cl_points = j.at("cl_points").get<std::size_t>();
  o.drops = j.at("drops").get<std::size_t>();
  o.planning_s = j.at("planning_s").get<double>();
  o.time_feed_min = j.at("time_feed_min").get<double>();
  o.time_kinematic_min = j.at("time_kinematic_min").get<double>();
  o.score.slot = static_cast<int>(o.strategy);
  o.score.time_min = o.time_kinematic_min;
  o.simulated = j.contains("max_gouge_mm");
  if (j.contains("params")) {
    o.stepover_mm = j["params"].at("stepover_mm").get<double>();
    o.step_down_mm = j["params"].at("step_down_mm").get<double>();
    o.scallop_mm = j["params"].at("scallop_mm").get<double>();
    o.feed_mm_min = j["params"].value("feed_mm_min", 0.0);
  }
  if (!o.simulated) return o;
  simulate::SurfaceMetrics& m = o.surface;
  o.grid.cell = cell_mm;  // (its size and origin are the part's, not in the file)
  m.max_gouge_mm = j.at("max_gouge_mm").get<double>();
  m.gouged = !j.at("gouge_line").is_null();
  if (m.gouged && j.contains("gouge_deepest_line") && !j["gouge_deepest_line"].is_null())
    m.gouge_move.line = j["gouge_deepest_line"].get<std::size_t>();
  if (m.gouged) m.first_gouge_move.line = j.at("gouge_line").get<std::size_t>();
  if (j.contains("zmap_max_gouge_mm")) {  // the exact check ran
    m.gouge_checked = true;
    m.zmap_max_gouge_mm = j["zmap_max_gouge_mm"].get<double>();
    m.zmap_gouge_places = j.at("zmap_gouge_places").get<std::size_t>();
    m.gouge_places_checked = j.at("gouge_places_checked").get<std::size_t>();
    m.gouge_places_refuted = j.at("zmap_gouge_artefacts").get<std::size_t>();
    if (j.contains("gouge_xy_mm")) {
      m.gouge_x_mm = j["gouge_xy_mm"].at(0).get<double>();
      m.gouge_y_mm = j["gouge_xy_mm"].at(1).get<double>();
    }
  }
  m.scallop_max_mm = j.at("scallop_max_mm").get<double>();
  m.ra_mean_um = j.at("ra_mean_um").get<double>();
  m.ra_median_um = j.at("ra_median_um").get<double>();
  m.ra_p90_um = j.at("ra_p90_um").get<double>();
  m.ra_bin_edges_um = j.at("ra_histogram").at("bin_edges_um").get<std::vector<double>>();
  m.ra_share = j.at("ra_histogram").at("shares").get<std::vector<double>>();
  m.ra_not_machined_share = j.at("ra_histogram").value("not_machined_share", 0.0);
  m.not_machined_cells = j.value("not_machined_cells", std::size_t{0});
  m.uncut_area_mm2 = j.at("uncut_area_mm2").get<double>();
  m.remaining_area_mm2 = j.at("remaining_area_mm2").get<double>();
  m.scallop_area_mm2 = j.at("scallop_area_mm2").get<double>();
  m.rest_area_mm2 = j.at("rest_area_mm2").get<double>();
  m.surface_cells = j.at("surface_cells").get<std::size_t>();
  if (j.contains("ra_target_share")) m.ra_target_share = j["ra_target_share"].get<double>();
  if (j.contains("spec")) {
    const Json& sp = j["spec"];
    const double a = cell_mm * cell_mm;
    auto cells = [&](const char* key) { return static_cast<std::size_t>(std::llround(sp.at(key).get<double>() / a)); };
    m.spec_measured = true;
    m.spec_share = sp.at("share_in_spec").get<double>();
    m.spec_cells = cells("judged_area_mm2");
    m.over_spec_cells = cells("over_spec_area_mm2");
    m.spec_not_machined_cells = cells("not_machined_area_mm2");
    m.in_spec_cells = m.spec_cells - m.over_spec_cells - m.spec_not_machined_cells;
    m.over_spec_max_mm = sp.at("over_spec_max_mm").get<double>();
  }
  o.cutting_rapids = j.at("cutting_rapids").get<std::size_t>();
  o.max_depth_of_cut_mm = j.at("max_depth_of_cut_mm").get<double>();
  o.score.ra_median_um = m.ra_median_um;
  o.score.ra_p90_um = m.ra_p90_um;
  o.score.uncut_area_mm2 = m.uncut_area_mm2;
  o.score.max_gouge_mm = m.max_gouge_mm;
  o.score.surface_area_mm2 = static_cast<double>(m.surface_cells) * cell_mm * cell_mm;
  if (m.spec_measured) o.score.spec_share = m.spec_share;
  o.score.ra_target_share = m.ra_target_share;
  return o;
}

finish::RestStock stock_of(simulate::ZMap z, const job::Frame& frame) {
  const simulate::GridSpec g = z.spec();
  finish::RestStock s;
  s.x0 = g.x(0), s.y0 = g.y(0), s.cell = g.cell;  // its nodes at the cells' centres, not their corner
  s.nx = static_cast<int>(g.nx), s.ny = static_cast<int>(g.ny);
  s.z = std::move(z.heights());
  s.z_offset = -frame.z_shift();  // program frame → part frame
  return s;
}

job::SimParams sim_params(const FinishSettings& settings) {
  job::SimParams p;
  p.cell_mm = settings.sim.cell_mm;
  if (settings.sim.cells_per_pass > 0) {  // the cell the passes need: their spacing / cells a pass
    const finish::FinishParams& f = settings.params;
    const double w =
        settings.params_from_spec ? finish::spec_spacing_mm(f.tool, settings.spec.scallop_mm) : f.stepover_mm;
    p.cell_mm = std::min(w / settings.sim.cells_per_pass, 0.25 * f.tool.radius());
    p.pass_spacing_mm = w;
  }
  p.allowance_mm = settings.sim.allowance_mm;
  p.tolerance_mm = settings.sim.tolerance_mm;
  p.sampling_length_mm = settings.sim.sampling_length_mm;
  p.ra_spacing_mm = settings.sim.ra_spacing_mm;
  p.ra_bins_um = settings.sim.ra_bins_um;
  p.spec_limit_mm = settings.spec.limit_mm();
  p.ra_target_um = settings.sim.ra_target_um;
  p.limits = work_limits();
  p.rest_threshold_mm = settings.rest_threshold_mm;
  return p;
}

finish::FinishParams rest_finish_params(const FinishSettings& settings, finish::FinishParams base,
                                        const tooling::Cutter& rest_tool) {
  base.tool = rest_tool;
  base.motion = settings.machine;  // its links over the stock timed as the machine moves
  if (!settings.params_from_spec) return base;
  return finish::params_for_spec(finish::Strategy::SlopeMode, settings.spec, std::move(base));
}

namespace {
/// A program beside the strategies' (rest finishing, pencil tracing): <stem>.<kind>.nc, its path
/// picture and <stem>.<kind>.json with `figures` and the program's own.
void write_extra_program(const job::Part& part, const FinishSettings& settings, const PartJob& job,
                         const finish::FinishPlan& plan, const std::string& kind, Json figures, const fs::path& out) {
  const std::string base = part.name + "." + kind;
  const gcode::Written written =
      gcode::written(plan.program, job.frame.post(settings.post), (out / (base + ".nc")).string());
  const gcode::ProgramStats st = gcode::stats(plan.program, settings.machine);
  figures["path_length_mm"] = plan.path_length_mm;
  figures["lifts"] = plan.lifts;
  figures["hops"] = plan.hops;
  figures["passes"] = plan.passes.size();
  figures["time_min"] = st.feed_time_min;
  figures["time_kinematic_min"] = st.kinematic_time_min;
  path_png(out / (base + ".png"), job, plan.program, part.name + ": " + kind);
  write_file_atomic(out / (base + ".nc"), written.text);
  write_file_atomic(out / (base + ".json"), figures.dump(2) + "\n");
}

/// The stock a simulation saved (`simulate --save-stock`), in the mesh frame, for rest from the
/// stock: it must cover the part's footprint. Errors name the file.
finish::RestStock rest_stock(const fs::path& file, const job::Part& part, const job::Frame& frame) {
  if (!fs::is_regular_file(file))
    throw file_error(file.string(),
                     "no such z-map (--rest-from: a FILE.zmap saved by simulate --save-stock, or a "
                     "folder holding " +
                         part.name + ".zmap)");
  simulate::ZMap z = simulate::io::read_zmap(file);
  const simulate::GridSpec& g = z.spec();
  const double x1 = g.x(g.nx - 1) + 0.5 * g.cell, y1 = g.y(g.ny - 1) + 0.5 * g.cell;
  const double px0 = part.mesh.V.col(0).minCoeff(), py0 = part.mesh.V.col(1).minCoeff();
  const double px1 = part.mesh.V.col(0).maxCoeff(), py1 = part.mesh.V.col(1).maxCoeff();
  const double slack = g.cell;
  if (g.x0 - 0.5 * g.cell > px0 + slack || g.y0 - 0.5 * g.cell > py0 + slack || x1 < px1 - slack || y1 < py1 - slack)
    throw file_error(file.string(), "its grid (X " + fixed(g.x0, 3) + " … " + fixed(x1, 3) + ", Y " + fixed(g.y0, 3) +
                                        " … " + fixed(y1, 3) + ") does not cover the part " + part.name + " (X " +
                                        fixed(px0, 3) + " … " + fixed(px1, 3) + ", Y " + fixed(py0, 3) + " … " +
                                        fixed(py1, 3) + "): save the stock from a simulation of this part");
  return stock_of(std::move(z), frame);
}

/// finish --rest-tool and --pencil (issue 41): rest finishing behind the reference tool, and pencil
/// tracing with the finishing tool, each a program of its own. No rest: said, and no program.
void write_rest_and_pencil(const job::Part& part, const FinishSettings& settings, const PartJob& job,
                           const fs::path& out) {
  if (settings.rest_tool) {
    finish::FinishParams p = rest_finish_params(settings, job.params, *settings.rest_tool);
    if (settings.rest_feeds) {  // the rest tool's own cutting data, not the finishing ball's
      p.spindle_rpm = settings.rest_feeds->spindle_rpm;
      p.feed_mm_min = settings.rest_feeds->feed_mm_min;
      p.plunge_feed_mm_min = settings.rest_feeds->plunge_feed_mm_min;
    }
    p.tool_label.clear();
    p.comments = {"tool: " + p.tool.describe()};
    const finish::DropCutter dropper(part.mesh, p.tool);
    finish::RestParams rp;
    rp.reference = settings.rest_reference.value_or(job.params.tool);
    rp.threshold_mm = settings.rest_threshold_mm;
    rp.margin_mm = settings.rest_margin_mm;
    std::optional<finish::RestStock> stock;
    std::string behind = rp.reference.describe();
    if (!settings.rest_from.empty()) {
      const fs::path file = fs::is_directory(settings.rest_from) ? fs::path(settings.rest_from) / (part.name + ".zmap")
                                                                 : fs::path(settings.rest_from);
      rp.stock = &stock.emplace(rest_stock(file, part, job.frame));
      behind = "the stock " + file.filename().string();
    }
    const finish::RestRegions r = finish::rest_regions(part.mesh, dropper, rp, p.x0, p.y0, p.x1, p.y1);
    Json figures{{"rest_tool", p.tool.describe()},
                 {"stepover_mm", p.stepover_mm},
                 {"step_down_mm", p.step_down_mm},
                 {rp.stock ? "rest_from" : "reference_tool", rp.stock ? behind : rp.reference.describe()},
                 {"threshold_mm", rp.threshold_mm},
                 {"cell_mm", r.cell},
                 {"regions", r.regions},
                 {"slivers_dropped", r.slivers},
                 {"rest_axis_area_mm2", r.rest_axis_area_mm2},
                 {"max_rest_mm", r.max_thickness_mm},
                 {"along_deg", r.axis_deg}};
    if (r.empty()) {
      info("finish: " + part.name + ": no rest material behind " + behind + " for " + p.tool.describe() +
           "; no rest program");
      write_file_atomic(out / (part.name + ".rest.json"), figures.dump(2) + "\n");
    } else {
      figures["rest_top_z"] = r.rest_top_z + job.frame.z_shift();  // program frame
      write_extra_program(part, settings, job, finish::plan_rest(part.mesh, dropper, r, behind, p), "rest",
                          std::move(figures), out);
    }
  }
  if (settings.pencil) {
    std::optional<finish::DropCutter> own;  // the strategies' was freed after planning
    const finish::DropCutter& dropper = job.dropper ? *job.dropper : own.emplace(part.mesh, job.params.tool);
    const finish::FinishPlan plan = finish::plan_pencil(part.mesh, dropper, job.params, settings.pencil_offsets);
    write_extra_program(part, settings, job, plan, "pencil",
                        Json{{"tool", job.params.tool.describe()},
                             {"offsets_each_side", settings.pencil_offsets},
                             {"offset_spacing_mm", job.params.stepover_mm}},
                        out);
  }
}

/// The part's strategies planned, written and (simulated) scored; the job kept for the caller.
std::vector<job::StrategyOutcome> plan_and_write(const job::Part& part, const FinishSettings& settings,
                                                 const std::vector<finish::Strategy>& strategies, PartJob& job,
                                                 const fs::path& out) {
  const std::vector<finish::FinishParams> params = settings.strategy_params(strategies, job.params);
  std::vector<finish::FinishPlan> plans = finish::plan_finish(part.mesh, *job.dropper, strategies, params);
  check_plans_reach(settings, plans);
  // What scoring does not need is freed before the first z-map is made (issue 37 §3: a 200 mm
  // plate's peak was the drop-cutter's index, 0.8 GB, and five plans, 0.4 GB, beside it).
  job.dropper.reset();
  std::vector<job::StrategyOutcome> outcomes;
  Progress progress("finish " + part.name, strategies.size());
  for (std::size_t i = 0; i < plans.size(); ++i) {  // O(strategies)
    outcomes.push_back(strategy_outcome(part, settings, job, plans[i], out, params[i]));
    plans[i] = {};
    progress.tick();
  }
  job.spare = {};  // not kept past the strategies (rest and pencil planning come next)
  return outcomes;
}
}  // namespace

PartFinish finish_part(const job::Part& part, const FinishSettings& settings, const fs::path& out) {
  PartJob job = part_job(part, settings, out);
  PartFinish pf;
  pf.outcomes = plan_and_write(part, settings, settings.strategies, job, out);
  write_rest_and_pencil(part, settings, job, out);
  write_strategy_ranking(part.name, settings, pf.outcomes, out);
  pf.frame = job.frame;
  pf.design = std::move(job.design);
  return pf;
}

std::vector<job::StrategyOutcome> finish_strategies(const job::Part& part, const FinishSettings& settings,
                                                    const std::vector<finish::Strategy>& strategies,
                                                    const fs::path& out) {
  PartJob job = part_job(part, settings, out);
  std::vector<job::StrategyOutcome> outcomes = plan_and_write(part, settings, strategies, job, out);
  if (!strategies.empty() && strategies.front() == settings.strategies.front())  // once per part (MPI units)
    write_rest_and_pencil(part, settings, job, out);
  return outcomes;
}

void write_strategy_ranking(const std::string& stem, const FinishSettings& settings,
                            std::vector<job::StrategyOutcome>& outcomes, const fs::path& out) {
  if (outcomes.size() < 2) return;
  const std::vector<std::size_t> order = job::rank_outcomes(outcomes, settings.aim);
  const simulate::Aim used = settings.simulate ? settings.aim.aim : simulate::Aim::Time;
  for (const std::string& line : job::spec_misses(outcomes)) info(stem + ": " + line);  // where and how much
  const report::StrategyTable t =
      report::strategy_table(stem, simulate::to_string(used), outcomes, order, settings.simulate);
  write_file_atomic(out / (stem + ".strategies.csv"), t.csv);
  write_file_atomic(out / (stem + ".strategies.md"), t.md);
  if (settings.simulate)  // the paper's Figure 9: share of the surface per Ra bin, per strategy
    report::ra_bins_png(out / (stem + ".strategies.png"), stem, settings.sim.ra_bins_um, outcomes);
}

std::vector<job::StrategyFigures> label_part(const job::Part& part, const FinishSettings& settings) {
  FinishSettings s = settings;
  s.simulate = false;  // score_strategies rasterizes the design itself
  PartJob job = finishing_job(part, s);
  std::vector<finish::FinishPlan> plans = finish::plan_finish(
      part.mesh, *job.dropper, settings.strategies, settings.strategy_params(settings.strategies, job.params));
  check_plans_reach(settings, plans);
  job.dropper.reset();  // its index (0.8 GB on a 200 mm plate) freed before the z-map is made
  return job::score_strategies(part.mesh, job.frame, std::move(plans), job.params.tool, job.frame.post(settings.post),
                               settings.machine, settings.aim, sim_params(settings));
}

ChainProgram read_chain_program(const fs::path& file, const tooling::Cutter& cutter, const gcode::Dialect& post) {
  ChainProgram p;
  p.file = file.string();
  // read_file: a program this command wrote is read from its OutputSet's temporary (core/output_set.hpp).
  p.written.text = read_file(file);
  // Bounds, a move, and the chords its arcs become, before the part is read (issue 42).
  p.written.program = gcode::read_checked(p.written.text, file.string(), work_limits());
  gcode::shift(p.written.program, post.origin[0], post.origin[1]);  // from the work frame into millnet's
  p.cutter = cutter;
  return p;
}

namespace {
/// A rest step's figures (issue 41; job::split_rest) into the program's entry, its missed rest drawn.
void rest_figures(const job::Part& part, const job::Design& design, const simulate::ZMap& z, const job::ChainResult& r,
                  const std::vector<job::ChainStep>& steps, const tooling::Cutter& tool, double threshold_mm,
                  double z_shift, Json& figures, const fs::path& picture) {
  // As the job splits it: where the design lies deeper below the stock top than the tool's stated
  // stick-out reaches, the rest is beyond its reach, not missed.
  const job::RestSplit split = job::split_rest(part.mesh, design, z, r, steps, tool, threshold_mm,
                                               tool.reach_mm > 0 ? -tool.reach_mm : -HUGE_VAL, z_shift);
  figures["over_threshold_before_mm2"] = r.rest_area_before_mm2;
  figures["over_threshold_after_mm2"] = r.rest_area_after_mm2;
  figures["rest_area_before_mm2"] = split.before_mm2;
  figures["rest_area_after_mm2"] = split.after_mm2;
  figures["rest_area_unreachable_mm2"] = split.unreachable_mm2;
  figures["rest_area_reference_unreachable_mm2"] = split.reference_unreachable_mm2;
  figures["rest_area_missed_mm2"] = split.missed_mm2;
  figures["rest_area_missed_zmap_mm2"] = split.missed_zmap_mm2;
  figures["rest_area_beyond_reach_mm2"] = split.beyond_reach_mm2;
  fs::create_directories(picture.parent_path());
  grid_png(picture, split.missed, design.grid,
           part.name + ": rest left where the " + tool.describe() + " reaches (vertical, mm)", "mm");
}
}  // namespace

Json simulate_programs(const job::Part& part, const std::string& stem, std::vector<ChainProgram> programs,
                       const std::string& stock, const FinishSettings& settings, const fs::path& out, bool save_stock,
                       const job::Design* design, bool score_rest, bool record_moves) {
  const job::SimParams sim = sim_params(settings);
  const job::Frame frame = job::frame_of(part.mesh, settings.stock_top_above_part_mm);
  std::optional<job::Design> own;
  if (design == nullptr) design = &own.emplace(job::design_surface(part.mesh, frame, sim));
  // With --save-stock, the block's surround too (the stock beyond the footprint, for a job that
  // starts from the saved stock: job::block_surround): from the block, or the one a saved stock brings.
  std::optional<simulate::ZMap> surround;
  simulate::ZMap z = [&] {
    if (stock == "flat") return job::block_stock(*design, sim);
    if (stock == "design") return job::finishing_stock(*design, frame, sim);
    simulate::io::SavedStock saved = saved_stock_from_file(stock, design->grid);
    surround = std::move(saved.surround);
    return std::move(saved.zmap);
  }();
  if (save_stock && stock == "flat")
    surround = job::block_surround(frame, settings.post.stock.sides(frame.width, frame.depth), 0.0, sim);
  std::vector<job::ChainStep> steps;
  for (const ChainProgram& p : programs) steps.push_back({&p.written.program, p.cutter});
  if (save_stock && surround) job::machine_surround(*surround, steps);
  const job::ChainResult r = job::machine_chain(z, *design, steps, settings.machine, sim, score_rest, record_moves);
  Json runs = Json::array();
  for (std::size_t i = 0; i < programs.size(); ++i) {
    const job::StepResult& s = r.steps[i];
    runs.push_back(Json{{"gcode", programs[i].file},
                        {"tool", programs[i].cutter.describe()},
                        {"path_length_mm", s.stats.cut_length_mm},
                        {"time_feed_min", s.stats.feed_time_min},
                        {"time_kinematic_min", s.stats.kinematic_time_min},
                        {"max_depth_of_cut_mm", s.max_depth_of_cut_mm},
                        {"cutting_rapids", s.cutting_rapids},
                        {"air_cut_share", s.air_cut_share()},
                        {"feed_outside_zmap_mm", s.outside_feed_mm},
                        {"air_run_share", s.air_run_share()},
                        {"feed_mm", s.feed_mm},
                        {"air_feed_mm", s.air_feed_mm}});
    if (const auto& g = r.metrics.pass_max_gouge_mm; g.size() >= programs.size())  // its own passes are the last
      runs.back()["max_gouge_mm"] = g[g.size() - programs.size() + i];
  }
  if (r.rest_step) {  // issue 41: the last program as rest machining behind the one before it
    Json& last = runs.back();
    last["rest_reference_tool"] = r.rest_reference.describe();
    last["rest_threshold_mm"] = sim.rest_threshold_mm;
    rest_figures(part, *design, z, r, steps, programs.back().cutter, sim.rest_threshold_mm, frame.z_shift(), last,
                 out / (stem + ".rest_missed.png"));
  }
  const simulate::SurfaceMetrics& m = r.metrics;
  Json j = sim_metrics_json(m, design->grid);
  if (m.gouged) j["gouge_gcode"] = runs.at(m.first_gouge_move.pass)["gcode"];
  fs::create_directories(out);
  const std::size_t first_pass = z.passes() - programs.size();  // a stock read back brings its own passes
  if (m.gouged && m.gouge_move.pass >= first_pass) {            // kept for inspection under a name that says it gouges
    const ChainProgram& g = programs[m.gouge_move.pass - first_pass];
    const fs::path kept = out / (fs::path(g.file).stem().string() + ".GOUGES.nc");
    write_file_atomic(kept, g.written.text);
    j["gouge_program_kept"] = kept.string();
    j["gouge_failure"] = gouge_failure(g.file, m);
  }
  j["programs"] = runs;
  j["stock"] = stock;
  j["stock_top_above_part_mm"] = settings.stock_top_above_part_mm;
  j["cell_mm"] = design->grid.cell;
  fs::create_directories(out);
  ra_png(out / (stem + ".ra.png"), design->grid, m, stem + ": roughness Ra");
  const std::vector<double> e = simulate::deviation(z, design->heights);
  grid_png(out / (stem + ".deviation.png"), e, design->grid, stem + ": machined - design", "mm");
  if (record_moves) {  // where the air lies, move by move, in each program's own work frame
    const gcode::Dialect post = frame.post(settings.post);
    std::vector<std::string> files;
    for (const ChainProgram& p : programs) files.push_back(fs::path(p.file).filename().string());
    write_file_atomic(out / (stem + ".moves.csv"), job::moves_csv(r.steps, files, post.origin));
    j["moves_csv"] = (out / (stem + ".moves.csv")).string();
  }
  if (save_stock) {
    simulate::io::write_zmap(out / (stem + ".zmap"), z, surround ? &*surround : nullptr);
    j["saved_stock"] = (out / (stem + ".zmap")).string();
  }
  if (preview_settings().enabled && !programs.empty()) {
    report::PreviewInput page;  // the 3D page of the programs on the machined surface (issue 16)
    page.title = stem + " — simulation";
    const tooling::Cutter last = programs.back().cutter;
    for (ChainProgram& p : programs)
      page.programs.push_back({fs::path(p.file).filename().string(), std::move(p.written)});
    page.tool = {last.diameter, last.profile_corner_radius(), last.describe()};
    frame_page(page, part, frame);
    page.surface = preview_surface(z, design->heights);
    (void)write_program_preview(out / (stem + ".html"), std::move(page));
  }
  write_file_atomic(out / (stem + ".sim.json"), j.dump(2) + "\n");
  return j;
}

}  // namespace millnet::app
