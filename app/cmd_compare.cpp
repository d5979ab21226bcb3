// millnet compare --pocket FILE [tool flags as pocket] --out DIR → DIR/compare.csv, DIR/compare.md, one PNG
// per planner: every planner on the same pocket and tool.
#include "cli.hpp"
#include "text.hpp"
#include "pocket_job.hpp"

#include "millnet/core/atomic_file.hpp"

#include <algorithm>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct CompareOpts {
  Common common;
  PocketFlags flags;
  std::string pocket, out;
};

struct Row {
  std::string planner;
  pocket::PlanResult plan;
  pocket::MachiningResult m;
  /// Passes and partition faces are the zigzag's figures: 0 for the SOM, and for a zigzag that found
  /// no room for the tool (no figures). The SOM's regions: tool-down chains per level.
  [[nodiscard]] double passes() const {
    const auto* zz = std::get_if<pocket::ZigzagStats>(&plan.stats);
    return zz ? static_cast<double>(zz->passes) : 0.0;
  }
  [[nodiscard]] double regions() const {
    if (planner == "som") return 1.0 + m.metrics.retractions / std::max(1.0, m.metrics.levels);
    const auto* zz = std::get_if<pocket::ZigzagStats>(&plan.stats);
    return zz ? zz->regions : 0.0;
  }
};

/// Plans and machines the pocket with every run of every planner of the registry (SOM, zigzag T,
/// zigzag I, offset, adaptive), writing each one's pocket outputs (<stem>.<run>.*) as it goes.
std::vector<Row> plan_every_planner(const CompareOpts& o, const Json& config, const pocket::PocketFile& file,
                                    const pocket::CutParams& cut, const Json& cutting_data) {
  const std::string stem = fs::path(o.pocket).stem().string();
  std::vector<Row> rows;
  for (const pocket::PlannerEntry& planner : pocket::planners())
    for (const pocket::CompareRun& run : planner.compare) {
      PocketFlags f = o.flags;
      f.planner = std::string(planner.name);
      const PlannerChoice ch = planner_choice(config, cut, f, &run);
      const std::string n(run.label);
      Row r{n, plan_region(file.region, cut, ch), {}};
      pocket::MachiningOptions mo = machining_options(ch, config);
      mo.program_name = stem + "-" + n;
      r.m = pocket::machine_pocket(file.region, cut, r.plan, mo);
      write_pocket_outputs(o.out, stem + "." + n, file.region, cut, ch, r.plan, r.m, {},
                           post_dialect(config, o.flags.post), cutting_data);
      info("compare: " + n + " done");
      rows.push_back(std::move(r));
    }
  return rows;
}

/// Rank of each row (1 = best): pocket::rank_by_time_to_clear.
std::vector<std::size_t> ranks(const std::vector<Row>& rows) {
  std::vector<const pocket::MachiningResult*> results;
  for (const Row& r : rows) results.push_back(&r.m);
  return pocket::rank_by_time_to_clear(results);
}

std::string compare_csv(const std::vector<Row>& rows) {
  std::ostringstream csv;
  csv << "planner,status,tool_points,passes,regions,cut_length_mm,rapid_length_mm,retractions,plunges,"
         "predrill_points,time_adjusted_min,time_constant_min,uncut_area_mm2,planning_time_s,"
         "time_kinematic_min,max_engagement_deg,rank\n";
  const std::vector<std::size_t> rank = ranks(rows);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const auto& mt = r.m.metrics;
    csv << r.planner << "," << pocket::to_string(r.m.status) << "," << format_double(mt.tool_points) << ","
        << format_double(r.passes()) << "," << format_double(r.regions()) << "," << format_double(mt.cut_length_mm)
        << "," << format_double(mt.rapid_length_mm) << "," << format_double(mt.retractions) << ","
        << format_double(mt.plunges) << "," << format_double(mt.predrill_points) << ","
        << format_double(mt.time_adjusted_min) << "," << format_double(mt.time_constant_min) << ","
        << format_double(mt.uncut_area_mm2) << "," << format_double(mt.planning_time_s) << ","
        << format_double(mt.time_kinematic_min) << "," << format_double(mt.max_engagement_deg) << "," << rank[i]
        << "\n";
  }
  return csv.str();
}

std::string compare_md(const std::vector<Row>& rows, const pocket::CutParams& cut, const fs::path& pocket_file) {
  const std::string stem = pocket_file.stem().string();
  std::ostringstream md;
  md << "# Planner comparison: " << pocket_file.filename().string() << "\n\n"
     << "Tool Ø" << fixed(cut.tool.diameter, 2) << " mm, stepover " << fixed(cut.stepover, 2) << " mm, depth "
     << fixed(cut.depth, 2) << " mm (step-down " << fixed(cut.step_down, 2) << " mm), stock to leave "
     << fixed(cut.stock_to_leave, 2) << " mm.\n\n"
     << "## Ranked by time to a cleared pocket\n\n"
     << "Time on the machine (motion model: /machine acceleration, junction deviation, rapids), planners that "
        "leave at most "
     << fixed(pocket::kClearedUncutMm2, 0) << " mm² of the reachable area uncut first.\n\n"
     << "| rank | planner | time on the machine (min) | uncut (mm²) | retractions | largest engagement (°) |\n"
     << "|---:|---|---:|---:|---:|---:|\n";
  const std::vector<std::size_t> rank = ranks(rows);
  for (std::size_t k = 1; k <= rows.size(); ++k)
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rank[i] == k) {
        const auto& mt = rows[i].m.metrics;
        md << "| " << k << " | " << rows[i].planner << " | " << fixed(mt.time_kinematic_min, 2) << " | "
           << fixed(mt.uncut_area_mm2, 1) << " | " << fixed(mt.retractions, 0) << " | "
           << fixed(mt.max_engagement_deg, 0) << " |\n";
      }
  md << "\n## All figures\n\n"
     << "| planner | tool points | passes | regions | cut (mm) | rapid (mm) | retractions | plunges | "
        "time adjusted (min) | time constant (min) | uncut (mm²) | planning (s) |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const auto& mt = r.m.metrics;
    md << "| " << r.planner << " | " << fixed(mt.tool_points, 0) << " | " << fixed(r.passes(), 0) << " | "
       << fixed(r.regions(), 0) << " | " << fixed(mt.cut_length_mm, 0) << " | " << fixed(mt.rapid_length_mm, 0) << " | "
       << fixed(mt.retractions, 0) << " | " << fixed(mt.plunges, 0) << " | " << fixed(mt.time_adjusted_min, 1) << " | "
       << fixed(mt.time_constant_min, 1) << " | " << fixed(mt.uncut_area_mm2, 1) << " | "
       << fixed(mt.planning_time_s, 3) << " |\n";
  }
  md << "\nPictures: ";
  for (const auto& r : rows) md << "![" << r.planner << "](" << stem << "." << r.planner << ".png) ";
  md << "\n\nRetractions are counted over all step-down levels; \"regions\" is the number of tool-down"
        " chains per level (zigzag: partition faces cut; SOM: chains after linking).\n";
  return md.str();
}

/// millnet compare: every planner on one pocket → their pocket outputs, compare.csv, compare.md.
int run_compare(const CompareOpts& o) {
  const Json config = setup(o.common);
  const pocket::PocketFile file = pocket::read_pocket(o.pocket);
  check_pocket_file(file, o.pocket);
  CuttingRecord cutting;
  const pocket::CutParams cut = cut_params(config, explicit_pocket_section(o.common.config), &file, o.flags, &cutting);
  const std::vector<Row> rows = plan_every_planner(o, config, file, cut, cutting.to_json());
  const std::string md = compare_md(rows, cut, o.pocket);
  write_file_atomic(fs::path(o.out) / "compare.csv", compare_csv(rows));
  write_file_atomic(fs::path(o.out) / "compare.md", md);
  if (!o.common.quiet) std::fputs(md.c_str(), stdout);
  return 0;
}

}  // namespace

Registered register_compare(CLI::App& app) {
  auto o = std::make_shared<CompareOpts>();
  CLI::App* sub = app.add_subcommand(
      "compare",
      "run every planner (SOM, zigzag T, zigzag I, offset) on one pocket and tool, ranked by time to a cleared pocket");
  sub->add_option("--pocket", o->pocket, "pocket file (.json or .dxf)")->required();
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  o->flags.add_to(sub, false);
  sub->add_option("--angle", o->flags.angle, "zigzag reference angle in degrees, or auto (default auto)");
  add_common(sub, o->common);
  return {sub, [o]() { return run_compare(*o); }};
}

}  // namespace millnet::app
