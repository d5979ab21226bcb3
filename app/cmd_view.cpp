// millnet view FILE.nc [FILE.nc …] [--mesh PART] [--tool T] --out DIR   (the 3D preview page of any G-code)
#include "cli.hpp"
#include "preview.hpp"
#include "settings.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/gcode/bounds.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct ViewOpts {
  Common common;
  MeshFlags mesh_flags;
  std::vector<std::string> gcode;
  std::string mesh, tool = "flat:6", out;
};

int run_view(const ViewOpts& o) {
  const Json config = setup(o.common);
  const tooling::Cutter cutter = tool_arg(o.tool, config);
  report::PreviewInput in;
  const std::string stem = fs::path(o.gcode.front()).stem().string();
  in.title = stem;
  for (const std::string& f : o.gcode) {
    // read_file refuses a folder (`view .` wrote "..html") and a device (`view /dev/zero` grew to
    // 3 GB); read_checked what `simulate` checks: the bounds, a move, the preview's points (issue 42).
    report::PreviewProgram p;
    p.name = fs::path(f).stem().string();
    p.written.text = read_file(f);
    gcode::ProgramUse use;
    use.simulate = false;
    use.preview_step_deg = preview_settings().limits.arc_step_deg;
    p.written.program = gcode::read_checked(p.written.text, f, work_limits(), use);  // before any output
    in.programs.push_back(std::move(p));
  }
  in.tool = {cutter.diameter, cutter.profile_corner_radius(), cutter.describe()};
  if (!o.mesh.empty()) {
    const ingest::Mesh mesh = ingest::load_prepared(o.mesh, o.mesh_flags.prepare(&config["rough"], &config));
    // The roughing / finishing frame (finish_job.hpp): Z 0 = stock top = part top + /rough/top_allowance_mm.
    const double top = mesh.V.col(2).maxCoeff(), allowance = finish_settings(config).stock_top_above_part_mm;
    set_preview_part(in, mesh, -(top + allowance));
    in.stock = std::array<double, 6>{0, 0, -(top + allowance), mesh.V.col(0).maxCoeff(), mesh.V.col(1).maxCoeff(), 0};
    in.notes.push_back("part " + fs::path(o.mesh).filename().string() + ": Z 0 = part top + " +
                       std::to_string(allowance).substr(0, 5) + " mm");
  }
  fs::create_directories(o.out);
  const fs::path html = fs::path(o.out) / (stem + ".html");
  PreviewSettings ps = preview_settings();
  ps.enabled = true;  // the page is this command's only output
  set_preview_settings(ps);
  (void)write_program_preview(html, std::move(in));
  info("view: " + std::to_string(o.gcode.size()) + " program(s) → " + html.string());
  return 0;
}

}  // namespace

Registered register_view(CLI::App& app) {
  auto o = std::make_shared<ViewOpts>();
  CLI::App* sub = app.add_subcommand("view", "3D preview page (HTML, opens offline in any browser) of G-code programs");
  sub->add_option("gcode", o->gcode, "G-code files (several: one page, coloured by program)")->required();
  sub->add_option("--mesh", o->mesh,
                  "the part's mesh, shown shaded in the programs' frame (Z 0 = part top + /rough/top_allowance_mm)");
  sub->add_option("--tool", o->tool,
                  "cutter drawn at the tool position: a tool library id, or ball:D, flat:D, bull:D:r (default flat:6)");
  o->mesh_flags.add_to(sub);
  sub->add_option("--out", o->out, "output folder (the page is DIR/<first file's stem>.html)")
      ->check(output_path())
      ->required();
  add_common(sub, o->common);
  return {sub, [o]() { return run_view(*o); }};
}

}  // namespace millnet::app
