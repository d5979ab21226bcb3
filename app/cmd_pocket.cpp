// millnet pocket --pocket FILE(.json|.dxf) [--config FILE] [--planner som|zigzag|offset] [tool flags] [--no-contour] --out DIR
#include "cli.hpp"
#include "pocket_job.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct PocketOpts {
  Common common;
  PocketFlags flags;
  std::string pocket, out;
};

/// millnet pocket: read → cut parameters → plan → machine → outputs (an empty plan is an error after
/// its metrics are written).
int run_pocket(const PocketOpts& o) {
  const Json config = setup(o.common);
  const pocket::PocketFile file = pocket::read_pocket(o.pocket);
  check_pocket_file(file, o.pocket);
  for (const auto& n : file.notes) info("pocket: " + o.pocket + ": " + n);
  CuttingRecord cutting;
  const pocket::CutParams cut = cut_params(config, explicit_pocket_section(o.common.config), &file, o.flags, &cutting);
  const PlannerChoice choice = planner_choice(config, cut, o.flags);
  const pocket::PlanResult plan = plan_region(file.region, cut, choice);
  pocket::MachiningOptions mo = machining_options(choice, config);
  mo.program_name = fs::path(o.pocket).stem().string();
  mo.comments = {"pocket: " + fs::path(o.pocket).filename().string(), "planner: " + plan.planner};
  const pocket::MachiningResult m = pocket::machine_pocket(file.region, cut, plan, mo);
  const std::string stem = fs::path(o.pocket).stem().string();
  write_pocket_outputs(o.out, stem, file.region, cut, choice, plan, m, file.notes, post_dialect(config, o.flags.post),
                       cutting.to_json());
  if (m.status != pocket::PlanStatus::Ok) {
    throw Error(o.pocket + ": " + pocket::to_string(m.status) + ": " + m.message + " (no G-code written; see " +
                (fs::path(o.out) / (stem + ".metrics.json")).string() + ")");
  }
  if (const std::string w = uncut_warning(plan, m); !w.empty()) warn("pocket: " + o.pocket + ": " + w);
  info("pocket: " + plan.planner + ": " + format_double(m.metrics.tool_points) + " tool points, cut " +
       std::to_string(static_cast<long>(m.metrics.cut_length_mm)) + " mm, rapid " +
       std::to_string(static_cast<long>(m.metrics.rapid_length_mm)) + " mm, " +
       std::to_string(static_cast<long>(m.metrics.retractions)) + " retractions → " +
       (fs::path(o.out) / (stem + ".nc")).string());
  return 0;
}

}  // namespace

Registered register_pocket(CLI::App& app) {
  auto o = std::make_shared<PocketOpts>();
  CLI::App* sub =
      app.add_subcommand("pocket", "rough-cut tool path of a pocket (SOM, zigzag or offset) → G-code, metrics, PNG");
  sub->add_option("--pocket", o->pocket, "pocket file (.json or .dxf)")->required();
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  o->flags.add_to(sub);
  add_common(sub, o->common);
  return {sub, [o]() { return run_pocket(*o); }};
}

}  // namespace millnet::app
