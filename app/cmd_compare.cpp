// millnet compare --pocket FILE [tool flags as pocket] --out DIR → DIR/compare.csv, DIR/compare.md, one PNG
// per planner: every planner on the same pocket and tool.
#include "cli.hpp"
#include "text.hpp"
#include "pocket_job.hpp"

#include "millnet/core/atomic_file.hpp"

#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
struct Row {
  std::string planner;
  pocket::PlanResult plan;
  pocket::MachiningResult m;
};

}  // namespace

Registered register_compare(CLI::App& app) {
  struct Opts {
    Common common;
    PocketFlags flags;
    std::string pocket, out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand("compare", "run every planner (SOM, zigzag T, zigzag I) on one pocket and tool");
  sub->add_option("--pocket", o->pocket, "pocket file (.json or .dxf)")->required();
  sub->add_option("--out", o->out, "output folder")->required();
  o->flags.add_to(sub, false);
  sub->add_option("--angle", o->flags.angle, "zigzag reference angle in degrees, or auto (default auto)");
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            const pocket::PocketFile file = pocket::read_pocket(o->pocket);
            const pocket::CutParams cut = cut_params(config, explicit_pocket_section(o->common.config), &file, o->flags);
            const std::string stem = fs::path(o->pocket).stem().string();
            std::vector<Row> rows;
            for (const char* name : {"som", "zigzag-t", "zigzag-i"}) {
              PocketFlags f = o->flags;
              const std::string n = name;
              f.planner = n == "som" ? "som" : "zigzag";
              if (n != "som") f.partition = n == "zigzag-t" ? "t" : "i";
              if (!f.angle) f.angle = "auto";
              const PlannerChoice ch = planner_choice(config, cut, f);
              Row r{n, plan_region(file.region, cut, ch), {}};
              pocket::MachiningOptions mo;
              mo.entry = ch.entry;
              mo.contour = ch.contour;
              mo.program_name = stem + "-" + n;
              r.m = pocket::machine_pocket(file.region, cut, r.plan, mo);
              write_pocket_outputs(o->out, stem + "." + n, file.region, cut, ch, r.plan, r.m, {});
              info("compare: " + n + " done");
              rows.push_back(std::move(r));
            }
            std::ostringstream csv, md;
            csv << "planner,status,tool_points,passes,regions,cut_length_mm,rapid_length_mm,retractions,plunges,"
                   "predrill_points,time_adjusted_min,time_constant_min,uncut_area_mm2,planning_time_s\n";
            md << "# Planner comparison: " << fs::path(o->pocket).filename().string() << "\n\n"
               << "Tool Ø" << fixed(cut.tool_diameter, 2) << " mm, stepover " << fixed(cut.stepover, 2)
               << " mm, depth " << fixed(cut.depth, 2) << " mm (step-down " << fixed(cut.step_down, 2)
               << " mm), stock to leave " << fixed(cut.stock_to_leave, 2) << " mm.\n\n"
               << "| planner | tool points | passes | regions | cut (mm) | rapid (mm) | retractions | plunges | "
                  "time adjusted (min) | time constant (min) | uncut (mm²) | planning (s) |\n"
               << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
            for (const auto& r : rows) {
              const auto& mt = r.m.metrics;
              // Passes and partition faces are the zigzag's figures: 0 for the SOM, and for a zigzag
              // that found no room for the tool (no figures).
              const auto* zz = std::get_if<pocket::ZigzagStats>(&r.plan.stats);
              const double passes = zz ? static_cast<double>(zz->passes) : 0.0;
              const double regions = r.planner == "som" ? 1.0 + mt.retractions / std::max(1.0, mt.levels)
                                                        : (zz ? zz->regions : 0.0);
              csv << r.planner << "," << pocket::to_string(r.m.status) << "," << format_double(mt.tool_points) << ","
                  << format_double(passes) << "," << format_double(regions) << ","
                  << format_double(mt.cut_length_mm) << "," << format_double(mt.rapid_length_mm) << ","
                  << format_double(mt.retractions) << "," << format_double(mt.plunges) << ","
                  << format_double(mt.predrill_points) << "," << format_double(mt.time_adjusted_min) << ","
                  << format_double(mt.time_constant_min) << "," << format_double(mt.uncut_area_mm2) << ","
                  << format_double(mt.planning_time_s) << "\n";
              md << "| " << r.planner << " | " << fixed(mt.tool_points, 0) << " | " << fixed(passes, 0) << " | "
                 << fixed(regions, 0) << " | " << fixed(mt.cut_length_mm, 0) << " | " << fixed(mt.rapid_length_mm, 0)
                 << " | " << fixed(mt.retractions, 0) << " | " << fixed(mt.plunges, 0) << " | "
                 << fixed(mt.time_adjusted_min, 1) << " | " << fixed(mt.time_constant_min, 1) << " | "
                 << fixed(mt.uncut_area_mm2, 1) << " | " << fixed(mt.planning_time_s, 3) << " |\n";
            }
            md << "\nPictures: ";
            for (const auto& r : rows) md << "![" << r.planner << "](" << stem << "." << r.planner << ".png) ";
            md << "\n\nRetractions are counted over all step-down levels; \"regions\" is the number of tool-down"
                  " chains per level (zigzag: partition faces cut; SOM: chains after linking).\n";
            write_file_atomic(fs::path(o->out) / "compare.csv", csv.str());
            write_file_atomic(fs::path(o->out) / "compare.md", md.str());
            if (!o->common.quiet) std::fputs(md.str().c_str(), stdout);
            return 0;
          }};
}

}  // namespace millnet::app
