// The job's semi-finishing (job_semi.hpp).
#include "job_semi.hpp"

#include "text.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>

namespace millnet::app {

SemiFinish semi_finishing(const SemiFinishInput& in, const tooling::Tool& semi, const Json& config,
                          const std::optional<std::string>& material, const ToolLibrary& lib) {
  const double a = in.settings.sim.allowance_mm;
  const double left =
      semi.flute_length_mm > 0 ? std::min(in.roughed.max_left_mm, semi.flute_length_mm) : in.roughed.max_left_mm;
  const CuttingSettings cs = cutting_settings(config, material);
  const tooling::CuttingData d =
      tooling::cutting_data(semi, lib.material(cs.material_id, cs.material_from), left, cs.machine, cs.factors);
  finish::FinishParams p = job::part_params(in.settings.params, in.finishing.frame, in.part.name + " semi-finishing",
                                            {"tool: " + semi.label()});
  p.boundary = in.settings.boundary_in(in.finishing.frame);
  const tooling::Cutter grown = tooling::Cutter::ball(semi.diameter_mm + 2 * a);
  p.tool = grown;
  p.tool_label = "semi-finishing, " + semi.label() + ", leaving " + format_double(a) + " mm";
  p.z_shift += a;
  p.stepover_mm = p.step_down_mm = job::scallop_step(semi.diameter_mm / 2, a);
  p.spindle_rpm = d.rpm, p.feed_mm_min = d.feed_mm_min, p.plunge_feed_mm_min = d.feed_plunge_mm_min;
  const finish::DropCutter dropper(in.part.mesh, grown);
  finish::FinishPlan plan = finish::plan_finish(in.part.mesh, dropper, finish::Strategy::SlopeMode, p);
  return {{"semi-finishing (s1 slope mode, leaving " + format_double(a) + " mm)", semi, std::move(plan.program)}, p};
}

/// The semi-finishing whose flutes take what it meets: the candidates (job::semi_finishing_tools)
/// planned in turn, each program's links lifted over the roughed stock and machined on a copy of
/// it, the first whose axial engagement its flutes take. Refused in one line naming the least
/// engaged candidate when none will do.
SemiFinish semi_finishing_that_fits(const SemiFinishInput& in, const simulate::ZMap& roughed, const job::Design& design,
                                    const FinishSettings& fs, const Json& config,
                                    const std::optional<std::string>& material, const ToolLibrary& lib,
                                    const std::string& file, double finish_cut) {
  const std::vector<const tooling::Tool*> candidates =
      job::semi_finishing_tools(lib.tools, in.finisher, in.mill, in.depth_mm);
  std::string tried;
  for (const tooling::Tool* t : candidates) {  // O(candidates × (plan + simulation))
    SemiFinish sf = semi_finishing(in, *t, config, material, lib);
    sf.op.program =
        job::clear_rapids(sf.op.program, roughed, t->cutter(), fs.params.clearance_mm, sf.params.plunge_feed_mm_min);
    simulate::ZMap trial = roughed;
    const job::StepResult st = job::machine_steps(trial, design, {{&sf.op.program, t->cutter()}}, fs.machine).front();
    if (t->flute_length_mm <= 0 || st.max_depth_of_cut_mm <= t->flute_length_mm) return sf;
    tried += (tried.empty() ? "" : "; ") + t->id + " would cut " + fixed(st.max_depth_of_cut_mm, 2) + " mm (flutes " +
             fixed(t->flute_length_mm, 1) + " mm) at X" + fixed(st.max_cut_at[0], 1) + " Y" +
             fixed(st.max_cut_at[1], 1);
  }
  throw Error(file + ": the finishing would cut " + fixed(finish_cut, 2) + " mm deep, more than the " +
              fixed(in.finisher.flute_length_mm, 1) + " mm flutes of " + in.finisher.label() +
              " take, and no ball of the library between Ø" + fixed(in.finisher.diameter_mm, 1) + " and Ø" +
              fixed(in.mill.diameter_mm, 1) + " mm that reaches " + fixed(in.depth_mm, 1) +
              " mm semi-finishes within its flutes" + (tried.empty() ? std::string() : " (" + tried + ")") +
              ": add one, or rough with a smaller step-down (/pocket/step_down)");
}

}  // namespace millnet::app
