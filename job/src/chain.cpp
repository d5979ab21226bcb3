// A part's programs machined in order on one stock (chain.hpp).
#include "millnet/job/chain.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace millnet::job {

simulate::ZMap block_stock(const Design& design, const SimParams& sim) {
  return simulate::ZMap::flat(design.grid, 0.0, sim.max_bytes());
}

namespace {

/// The most stock above the design and where. O(cells).
void left_above(const simulate::ZMap& stock, const Design& design, StepResult& st) {
  const simulate::GridSpec& g = stock.spec();
  st.max_left_mm = 0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double d = design.heights[iy * g.nx + ix];
      if (std::isnan(d)) continue;
      const double left = stock.at(ix, iy) - d;
      if (left > st.max_left_mm) {
        st.max_left_mm = left;
        st.max_left_at = {g.x(ix), g.y(iy)};
      }
    }
}

}  // namespace

std::vector<ChainStep> chain_steps(const std::vector<Operation>& ops) {
  std::vector<ChainStep> out;
  out.reserve(ops.size());
  for (const Operation& op : ops) out.push_back({&op.program, op.tool.cutter()});
  return out;
}

std::vector<StepResult> machine_steps(simulate::ZMap& stock, const Design& design, const std::vector<ChainStep>& steps,
                                      const gcode::MotionModel& machine) {
  std::vector<StepResult> out;
  for (const ChainStep& s : steps) {  // O(steps)
    const simulate::SweepResult sw = simulate::machine(stock, *s.program, s.cutter);
    StepResult st;
    st.stats = gcode::stats(*s.program, machine);
    const auto deepest = std::max_element(sw.max_cut_mm.begin(), sw.max_cut_mm.end());
    st.max_depth_of_cut_mm = *deepest;
    const std::size_t item = sw.max_cut_item[static_cast<std::size_t>(deepest - sw.max_cut_mm.begin())];
    if (item < s.program->items.size()) {
      if (const auto* m = std::get_if<gcode::Move>(&s.program->items[item])) st.max_cut_at = m->to;
      if (item < s.program->source_line.size()) st.max_cut_line = s.program->source_line[item];
    }
    st.cutting_rapids = sw.cutting_rapids.size();
    left_above(stock, design, st);
    out.push_back(st);
  }
  return out;
}

ChainResult machine_chain(simulate::ZMap& stock, const Design& design, const std::vector<ChainStep>& steps,
                          const gcode::MotionModel& machine, const SimParams& sim) {
  ChainResult r;
  // The exact gouge check's programs per z-map pass: none for the passes of a stock read back.
  std::vector<simulate::PassTool> passes(stock.passes());
  for (const ChainStep& s : steps) passes.push_back({s.program, s.cutter});
  r.steps = machine_steps(stock, design, steps, machine);
  simulate::MetricsOptions mo;
  if (!steps.empty()) {
    mo = sim.metrics_options(steps.back().cutter);  // scallop and rest of the last tool
  } else {
    mo = sim.metrics_options(tooling::Cutter::ball(2));
    mo.cutter.reset();
  }
  r.metrics = simulate::surface_metrics(stock, design.heights, mo);
  if (design.solid)
    simulate::confirm_gouges(r.metrics, stock, design.heights, *design.solid, passes, sim.gouge_options());
  return r;
}

}  // namespace millnet::job
