#include "finish_job.hpp"

#include "cli.hpp"
#include "preview.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "millnet/gcode/polylines.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/report/plots.hpp"
#include "millnet/simulate/maps.hpp"
#include "millnet/simulate/io/zmap_file.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <variant>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

/// A picture never needs more than this many cells per side (heat_map_png draws ≥ 1 px per cell).
constexpr int kMaxPictureCells = 500;

/// The part in the program frame and (for simulation) its design surface on the z-map grid.
struct PartFrame {
  double stock_top = 0;  ///< part frame
  double z_shift = 0;    ///< program Z = part z + z_shift
  double width = 0, depth = 0;
  simulate::GridSpec grid;
  std::vector<double> design;  ///< program frame, NaN off the part
};

/// The z-map's own backstop at the run's memory limit (--max-memory-mb), not its 2 GiB default.
std::size_t zmap_max_bytes() { return static_cast<std::size_t>(std::min(work_limits().max_memory_bytes, 1e18)); }

PartFrame part_frame(const ingest::Mesh& mesh, const FinishSettings& s, bool with_design) {
  PartFrame f;
  f.stock_top = mesh.V.col(2).maxCoeff() + s.stock_top_above_part_mm;
  f.z_shift = -f.stock_top;
  f.width = mesh.V.col(0).maxCoeff();
  f.depth = mesh.V.col(1).maxCoeff();
  if (!with_design) return f;
  f.grid.cell = s.sim.cell_mm;
  f.grid.nx = static_cast<std::size_t>(std::max(1.0, std::ceil(f.width / s.sim.cell_mm)));
  f.grid.ny = static_cast<std::size_t>(std::max(1.0, std::ceil(f.depth / s.sim.cell_mm)));
  f.grid.check();
  // + design and raster (17 B per cell), + the metrics' per-cell excess (8 B), before any is allocated
  check_work(simulate::zmap_work(f.grid, 25), work_limits());
  const ingest::HeightField hf = ingest::rasterize_top(mesh, 0.5 * f.grid.cell, 0.5 * f.grid.cell, f.grid.cell,
                                                       static_cast<int>(f.grid.nx), static_cast<int>(f.grid.ny));
  f.design = simulate::design_heights(hf, f.z_shift);
  return f;
}

/// A map of the part's z-map grid shrunk for a picture (block means, `empty` where a block has no cell).
Eigen::MatrixXd picture_map(const std::vector<double>& v, const simulate::GridSpec& g, double empty) {
  return simulate::block_means(v, g.nx, g.ny, kMaxPictureCells, empty);
}

/// A stock saved by an earlier `simulate --save-stock`: its grid must be the part's.
simulate::ZMap stock_from_file(const std::string& file, const simulate::GridSpec& g) {
  simulate::ZMap z = simulate::io::read_zmap(file);
  const simulate::GridSpec& s = z.spec();
  auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9; };
  if (s.nx != g.nx || s.ny != g.ny || !same(s.cell, g.cell) || !same(s.x0, g.x0) || !same(s.y0, g.y0))
    throw file_error(file, "its grid (" + std::to_string(s.nx) + " × " + std::to_string(s.ny) + " cells of " +
                               fixed(s.cell, 4) + " mm at " + fixed(s.x0, 3) + ", " + fixed(s.y0, 3) +
                               ") is not this part's (" + std::to_string(g.nx) + " × " + std::to_string(g.ny) +
                               " cells of " + fixed(g.cell, 4) + " mm at " + fixed(g.x0, 3) + ", " + fixed(g.y0, 3) +
                               "): save and reuse a stock with the same mesh, --units, --up and /simulate/cell_mm");
  return z;
}

/// Scoring a finished surface: nothing should be left above the design (allowance 0).
simulate::MetricsOptions metrics_options(const SimSettings& sim) {
  simulate::MetricsOptions mo;
  mo.allowance_mm = 0;
  mo.tolerance_mm = sim.tolerance_mm;
  mo.sampling_length_mm = sim.sampling_length_mm;
  mo.ra_bins_um = sim.ra_bins_um;
  mo.ra_every = static_cast<std::size_t>(std::max(1.0, std::round(sim.ra_spacing_mm / sim.cell_mm)));
  return mo;
}

Json histogram_json(const simulate::SurfaceMetrics& m) {
  return Json{{"bin_edges_um", m.ra_bin_edges_um}, {"shares", m.ra_share}};
}

Json sim_metrics_json(const simulate::SurfaceMetrics& m, const simulate::SweepResult& sweep,
                      const simulate::GridSpec& grid) {
  Json j;
  j["max_gouge_mm"] = m.max_gouge_mm;
  j["gouge_line"] = m.gouged ? Json(m.first_gouge_move.line) : Json(nullptr);
  if (m.gouged && m.gouge_cell < grid.cells()) {  // where the deepest one is, and the move that cut it
    j["gouge_deepest_xy_mm"] = {grid.x(m.gouge_cell % grid.nx), grid.y(m.gouge_cell / grid.nx)};
    j["gouge_deepest_line"] = m.gouge_has_move ? Json(m.gouge_move.line) : Json(nullptr);
  }
  j["scallop_max_mm"] = m.scallop_max_mm;
  j["ra_mean_um"] = m.ra_mean_um;
  j["ra_median_um"] = m.ra_median_um;
  j["ra_p90_um"] = m.ra_p90_um;
  j["ra_histogram"] = histogram_json(m);
  j["uncut_area_mm2"] = m.uncut_area_mm2;
  j["remaining_area_mm2"] = m.remaining_area_mm2;
  j["scallop_area_mm2"] = m.scallop_area_mm2;
  j["rest_area_mm2"] = m.rest_area_mm2;
  j["surface_cells"] = m.surface_cells;
  j["cutting_rapids"] = sweep.cutting_rapids.size();
  j["max_depth_of_cut_mm"] = *std::max_element(sweep.max_cut_mm.begin(), sweep.max_cut_mm.end());
  return j;
}

void ra_png(const fs::path& path, const PartFrame& f, const simulate::SurfaceMetrics& m, const std::string& title) {
  const std::vector<double> ra(m.ra_um.begin(), m.ra_um.end());
  const Eigen::MatrixXd g = picture_map(ra, f.grid, 0.0);
  report::HeatMapOptions o;
  o.extent_mm = std::array<double, 4>{0, static_cast<double>(f.grid.nx) * f.grid.cell, 0,
                                      static_cast<double>(f.grid.ny) * f.grid.cell};
  if (!(g.maxCoeff() > g.minCoeff())) o.value_range = std::pair{g.minCoeff(), g.minCoeff() + 1};
  (void)report::heat_map_png(path, g, title, "Ra (um)", o);
}

}  // namespace

namespace {

/// What every strategy of a part shares: its frame, the finishing parameters with the part's Z
/// shift and the program header, the drop cutter and the height picture under the paths.
struct PartJob {
  PartFrame frame;
  finish::FinishParams params;
  std::optional<finish::DropCutter> dropper;
  ingest::HeightField hf;
  Eigen::MatrixXd heights;
};

PartJob part_job(const ingest::Mesh& mesh, const std::string& stem, const FinishSettings& settings,
                 const fs::path& out) {
  PartJob job;
  settings.params.check();
  job.frame = part_frame(mesh, settings, settings.simulate);
  const PartFrame& frame = job.frame;
  if (const tooling::Tool& tool = settings.cutting.tool; tool.stickout_mm > 0) {
    // The tool reaches down from the stock top at most to the part's lowest point.
    const double reach = frame.stock_top - mesh.V.col(2).minCoeff();
    if (reach > tool.stickout_mm)
      throw Error(tool.label() + ": the part reaches " + fixed(reach, 2) +
                  " mm below the stock top, beyond the tool's stick-out " + format_double(tool.stickout_mm) +
                  " mm by " + fixed(reach - tool.stickout_mm, 2) + " mm: the holder would hit the part");
  }
  finish::FinishParams& params = job.params;
  params = settings.params;
  params.z_shift = frame.z_shift;
  params.program_name = stem;
  job.dropper.emplace(mesh, params.tool);
  // The picture under the paths: the part's heights (program frame), downsampled.
  const double pic_step = std::max(frame.width, frame.depth) / kMaxPictureCells;
  job.hf = ingest::rasterize_top(mesh, std::max(pic_step, 1e-3));
  job.heights = ingest::height_matrix(job.hf, frame.z_shift);
  fs::create_directories(out);
  std::vector<std::string> tool_lines = settings.cutting.header();
  if (tool_lines.empty()) tool_lines.push_back("tool: " + params.tool.describe());
  params.comments = tool_lines;
  params.comments.push_back("frame: Z 0 = stock top = part top + " + fixed(settings.stock_top_above_part_mm, 3) +
                            " mm");
  return job;
}

/// One planned strategy written (program, metrics, pictures, page) and, with settings.simulate,
/// machined on the z-map and scored.
StrategyOutcome strategy_outcome(const ingest::Mesh& mesh, const std::string& stem, const FinishSettings& settings,
                                 const PartJob& job, const finish::FinishPlan& plan, const fs::path& out,
                                 const Json& cad) {
  const PartFrame& frame = job.frame;
  const finish::FinishParams& params = job.params;
  const ingest::HeightField& hf = job.hf;
  const Eigen::MatrixXd& heights = job.heights;
  const finish::Strategy strategy = plan.strategy;
  const int k = static_cast<int>(strategy);
  const std::string base = stem + ".s" + std::to_string(k);
  const double plan_s = plan.planning_s;
  const gcode::Written written = gcode::write_program(out / (base + ".nc"), plan.program, settings.post);
  const gcode::ProgramStats st = gcode::stats(plan.program, settings.machine);
  StrategyOutcome o;
  o.strategy = strategy;
  Json& j = o.metrics;
  j["strategy"] = k;
  j["strategy_name"] = finish::strategy_name(strategy);
  j["tool"] = params.tool.describe();
  j["cutting_data"] = settings.cutting.to_json();
  if (!cad.is_null()) j["cad"] = cad;
  j["stock_top_above_part_mm"] = settings.stock_top_above_part_mm;
  j["path_length_mm"] = plan.path_length_mm;
  j["time_feed_min"] = st.feed_time_min;
  j["time_kinematic_min"] = st.kinematic_time_min;
  j["lifts"] = plan.lifts;
  j["passes"] = plan.passes.size();
  j["cl_points"] = plan.cl_points;
  j["drops"] = plan.drops_needed;  // a property of the strategy: the same planned alone (MPI) or with others
  j["planning_s"] = plan_s;
  o.score.slot = k;
  o.score.time_min = st.kinematic_time_min;
  {  // path over the height map
    gcode::XyPaths paths = gcode::xy_paths(plan.program);
    report::HeatMapOptions ho;
    ho.extent_mm = std::array<double, 4>{hf.x0 - 0.5 * hf.step_x, hf.x0 + (hf.nx - 0.5) * hf.step_x,
                                         hf.y0 - 0.5 * hf.step_y, hf.y0 + (hf.ny - 0.5) * hf.step_y};
    ho.overlay_cuts = std::move(paths.cuts);
    ho.overlay_rapids = std::move(paths.rapids);
    if (!(heights.maxCoeff() > heights.minCoeff()))
      ho.value_range = std::pair{heights.minCoeff(), heights.minCoeff() + 1};
    (void)report::heat_map_png(out / (base + ".png"), heights, stem + ": " + finish::strategy_name(strategy), "Z (mm)",
                               ho);
  }
  std::optional<report::PreviewSurface> surface;
  if (settings.simulate) {
    simulate::ZMap z = simulate::ZMap::from_heights(frame.grid, frame.design, settings.sim.allowance_mm,
                                                    frame.z_shift + settings.sim.allowance_mm, zmap_max_bytes());
    // The program as the machine gets it: the text written, read back (its coordinates rounded as
    // written, gouges reported at their line).
    const simulate::SweepResult sw = simulate::machine(z, written.program, params.tool);
    // Uncut = reachable material the program left; the scallops between passes are scored by
    // scallop and Ra, and the rest material no program with this cutter can clear is apart.
    simulate::MetricsOptions mo = metrics_options(settings.sim);
    mo.cutter = params.tool;
    const simulate::SurfaceMetrics m = simulate::surface_metrics(z, frame.design, mo);
    j.update(sim_metrics_json(m, sw, frame.grid));
    if (preview_settings().enabled) surface = preview_surface(z, simulate::deviation(z, frame.design));
    if (m.gouged) {  // a gouge from the program itself is a planner bug: say where
      warn(base + ".nc: gouge " + fixed(m.max_gouge_mm, 4) + " mm first at line " +
           std::to_string(m.first_gouge_move.line));
    }
    o.score.ra_median_um = m.ra_median_um;
    o.score.ra_p90_um = m.ra_p90_um;
    o.score.uncut_area_mm2 = m.uncut_area_mm2;
    o.score.max_gouge_mm = m.max_gouge_mm;
    o.score.surface_area_mm2 = static_cast<double>(m.surface_cells) * frame.grid.cell * frame.grid.cell;
    o.ra_share = m.ra_share;
    ra_png(out / (base + ".ra.png"), frame, m, stem + ": " + finish::strategy_name(strategy) + ", roughness Ra");
  }
  {
    report::PreviewInput page;  // the 3D page of the program (issue 16), with its machined surface when simulated
    page.title = base + " — " + finish::strategy_name(strategy);
    page.programs.push_back({finish::strategy_name(strategy), std::move(written)});
    page.tool = {params.tool.diameter, params.tool.corner_radius, params.tool.describe()};
    set_preview_part(page, mesh, frame.z_shift);
    page.stock = std::array<double, 6>{0, 0, frame.z_shift + mesh.V.col(2).minCoeff(), frame.width, frame.depth, 0};
    page.surface = std::move(surface);
    (void)write_program_preview(out / (base + ".html"), std::move(page));
  }
  write_file_atomic(out / (base + ".metrics.json"), j.dump(2) + "\n");
  return o;
}

}  // namespace

std::vector<StrategyOutcome> finish_part(const ingest::Mesh& mesh, const std::string& stem,
                                         const FinishSettings& settings, const fs::path& out, const Json& cad) {
  const PartJob job = part_job(mesh, stem, settings, out);
  const std::vector<finish::FinishPlan> plans =
      finish::plan_finish(mesh, *job.dropper, settings.strategies, job.params);
  std::vector<StrategyOutcome> outcomes;
  Progress progress("finish " + stem, settings.strategies.size());
  for (const finish::FinishPlan& plan : plans) {
    outcomes.push_back(strategy_outcome(mesh, stem, settings, job, plan, out, cad));
    progress.tick();
  }
  write_strategy_ranking(stem, settings, outcomes, out);
  return outcomes;
}

StrategyOutcome finish_strategy(const ingest::Mesh& mesh, const std::string& stem, const FinishSettings& settings,
                                finish::Strategy strategy, const fs::path& out, const Json& cad) {
  const PartJob job = part_job(mesh, stem, settings, out);
  const finish::FinishPlan plan = finish::plan_finish(mesh, *job.dropper, strategy, job.params);
  return strategy_outcome(mesh, stem, settings, job, plan, out, cad);
}

void write_strategy_ranking(const std::string& stem, const FinishSettings& settings,
                            std::vector<StrategyOutcome>& outcomes, const fs::path& out) {
  if (outcomes.size() > 1) {
    std::vector<simulate::StrategyScore> scores;
    for (const auto& o : outcomes) scores.push_back(o.score);
    simulate::AimParams aim = settings.aim;
    if (!settings.simulate) aim.aim = simulate::Aim::Time;  // without a surface only time can rank
    const std::vector<std::size_t> order = simulate::rank_strategies(scores, aim);
    const std::vector<int> rank = simulate::ranks_from_order(order);
    for (std::size_t i = 0; i < outcomes.size(); ++i) outcomes[i].rank = rank[i];
    std::ostringstream csv, md;
    csv << "rank,strategy,name,path_length_mm,time_feed_min,time_kinematic_min,lifts";
    md << "# " << stem << ": finishing strategies ranked by " << simulate::to_string(aim.aim) << "\n\n"
       << "| rank | strategy | path (m) | time feed (min) | time kinematic (min) | lifts |";
    if (settings.simulate) {
      csv << ",ra_median_um,ra_p90_um,scallop_max_mm,max_gouge_mm,uncut_area_mm2";
      md << " Ra median (µm) | Ra p90 (µm) | scallop (mm) | gouge (mm) | uncut (mm²) |";
    }
    csv << "\n";
    md << "\n|---|---|---|---|---|---|" << (settings.simulate ? "---|---|---|---|---|" : "") << "\n";
    for (std::size_t r = 0; r < order.size(); ++r) {
      const Json& j = outcomes[order[r]].metrics;
      csv << r + 1 << "," << j["strategy"].get<int>() << ",\"" << j["strategy_name"].get<std::string>() << "\","
          << fixed(j["path_length_mm"].get<double>(), 3) << "," << fixed(j["time_feed_min"].get<double>(), 4) << ","
          << fixed(j["time_kinematic_min"].get<double>(), 4) << "," << j["lifts"].get<std::size_t>();
      md << "| " << r + 1 << " | " << j["strategy_name"].get<std::string>() << " | "
         << fixed(j["path_length_mm"].get<double>() / 1000, 2) << " | " << fixed(j["time_feed_min"].get<double>(), 1)
         << " | " << fixed(j["time_kinematic_min"].get<double>(), 1) << " | " << j["lifts"].get<std::size_t>() << " |";
      if (settings.simulate) {
        csv << "," << fixed(j["ra_median_um"].get<double>(), 3) << "," << fixed(j["ra_p90_um"].get<double>(), 3) << ","
            << fixed(j["scallop_max_mm"].get<double>(), 4) << "," << fixed(j["max_gouge_mm"].get<double>(), 4) << ","
            << fixed(j["uncut_area_mm2"].get<double>(), 2);
        md << " " << fixed(j["ra_median_um"].get<double>(), 2) << " | " << fixed(j["ra_p90_um"].get<double>(), 2)
           << " | " << fixed(j["scallop_max_mm"].get<double>(), 4) << " | " << fixed(j["max_gouge_mm"].get<double>(), 4)
           << " | " << fixed(j["uncut_area_mm2"].get<double>(), 1) << " |";
      }
      csv << "\n";
      md << "\n";
    }
    write_file_atomic(out / (stem + ".strategies.csv"), csv.str());
    write_file_atomic(out / (stem + ".strategies.md"), md.str());
    if (settings.simulate) {  // the paper's Figure 9: share of the surface per Ra bin, per strategy
      const auto& edges = settings.sim.ra_bins_um;
      std::vector<std::string> cats;
      for (std::size_t b = 0; b < edges.size(); ++b)
        cats.push_back(b + 1 < edges.size() ? fixed(edges[b], 2) + "-" + fixed(edges[b + 1], 2)
                                            : ">= " + fixed(edges[b], 2));
      std::vector<report::NamedValues> series;
      for (const auto& o : outcomes) {
        report::NamedValues nv{finish::strategy_name(o.strategy), {}};
        for (const double s : o.ra_share) nv.values.push_back(100 * s);
        series.push_back(std::move(nv));
      }
      report::BarOptions bo;
      bo.show_values = false;
      (void)report::grouped_bar_png(out / (stem + ".strategies.png"), cats, series,
                                    stem + ": share of the surface per Ra bin (um)", "surface (%)", bo);
    }
  }
}

Json simulate_files(const ingest::Mesh& mesh, const std::string& stem,
                    const std::vector<std::pair<fs::path, tooling::Cutter>>& programs, const std::string& stock,
                    const FinishSettings& settings, const fs::path& out, bool save_stock) {
  const PartFrame frame = part_frame(mesh, settings, true);
  simulate::ZMap z = stock == "flat" ? simulate::ZMap::flat(frame.grid, 0.0, zmap_max_bytes())
                     : stock == "design"
                         ? simulate::ZMap::from_heights(frame.grid, frame.design, settings.sim.allowance_mm,
                                                        frame.z_shift + settings.sim.allowance_mm, zmap_max_bytes())
                         : stock_from_file(stock, frame.grid);
  Json runs = Json::array();
  std::vector<report::PreviewProgram> shown;
  for (const auto& [file, cutter] : programs) {
    // read_file: a program this command wrote is read from its OutputSet's temporary (core/output_set.hpp).
    gcode::Written w;
    w.text = read_file(file);
    w.program = gcode::read(w.text, file.string());
    const gcode::Program& prog = w.program;
    const simulate::SweepResult sw = simulate::machine(z, prog, cutter);
    const gcode::ProgramStats st = gcode::stats(prog, settings.machine);
    runs.push_back(Json{{"gcode", file.string()},
                        {"tool", cutter.describe()},
                        {"path_length_mm", st.cut_length_mm},
                        {"time_feed_min", st.feed_time_min},
                        {"time_kinematic_min", st.kinematic_time_min},
                        {"max_depth_of_cut_mm", *std::max_element(sw.max_cut_mm.begin(), sw.max_cut_mm.end())},
                        {"cutting_rapids", sw.cutting_rapids.size()}});
    shown.push_back({file.filename().string(), std::move(w)});
  }
  simulate::MetricsOptions mo = metrics_options(settings.sim);
  if (!programs.empty()) mo.cutter = programs.back().second;  // scallop and rest of the last tool
  const simulate::SurfaceMetrics m = simulate::surface_metrics(z, frame.design, mo);
  simulate::SweepResult none;
  Json j = sim_metrics_json(m, none, frame.grid);
  j.erase("cutting_rapids");
  j.erase("max_depth_of_cut_mm");
  if (m.gouged) j["gouge_gcode"] = runs.at(m.first_gouge_move.pass)["gcode"];
  j["programs"] = runs;
  j["stock"] = stock;
  j["stock_top_above_part_mm"] = settings.stock_top_above_part_mm;
  j["cell_mm"] = frame.grid.cell;
  fs::create_directories(out);
  ra_png(out / (stem + ".ra.png"), frame, m, stem + ": roughness Ra");
  const std::vector<double> e = simulate::deviation(z, frame.design);
  const Eigen::MatrixXd g = picture_map(e, frame.grid, 0.0);
  report::HeatMapOptions o;
  o.extent_mm = std::array<double, 4>{0, static_cast<double>(frame.grid.nx) * frame.grid.cell, 0,
                                      static_cast<double>(frame.grid.ny) * frame.grid.cell};
  if (!(g.maxCoeff() > g.minCoeff())) o.value_range = std::pair{g.minCoeff(), g.minCoeff() + 1};
  (void)report::heat_map_png(out / (stem + ".deviation.png"), g, stem + ": machined - design", "mm", o);
  if (save_stock) {
    simulate::io::write_zmap(out / (stem + ".zmap"), z);
    j["saved_stock"] = (out / (stem + ".zmap")).string();
  }
  if (preview_settings().enabled && !programs.empty()) {
    report::PreviewInput page;  // the 3D page of the programs on the machined surface (issue 16)
    page.title = stem + " — simulation";
    page.programs = std::move(shown);
    page.tool = {programs.back().second.diameter, programs.back().second.corner_radius,
                 programs.back().second.describe()};
    set_preview_part(page, mesh, frame.z_shift);
    page.stock = std::array<double, 6>{0, 0, frame.z_shift + mesh.V.col(2).minCoeff(), frame.width, frame.depth, 0};
    page.surface = preview_surface(z, e);
    (void)write_program_preview(out / (stem + ".html"), std::move(page));
  }
  write_file_atomic(out / (stem + ".sim.json"), j.dump(2) + "\n");
  return j;
}

}  // namespace millnet::app
