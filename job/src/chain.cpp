// A part's programs machined in order on one stock (chain.hpp).
#include "millnet/job/chain.hpp"

#include <algorithm>

namespace millnet::job {

simulate::ZMap block_stock(const Design& design, const SimParams& sim) {
  return simulate::ZMap::flat(design.grid, 0.0, sim.max_bytes());
}

ChainResult machine_chain(simulate::ZMap& stock, const Design& design, const std::vector<ChainStep>& steps,
                          const gcode::MotionModel& machine, const SimParams& sim) {
  ChainResult r;
  // The exact gouge check's programs per z-map pass: none for the passes of a stock read back.
  std::vector<simulate::PassTool> passes(stock.passes());
  for (const ChainStep& s : steps) {  // O(steps)
    passes.push_back({s.program, s.cutter});
    const simulate::SweepResult sw = simulate::machine(stock, *s.program, s.cutter);
    StepResult st;
    st.stats = gcode::stats(*s.program, machine);
    st.max_depth_of_cut_mm = *std::max_element(sw.max_cut_mm.begin(), sw.max_cut_mm.end());
    st.cutting_rapids = sw.cutting_rapids.size();
    r.steps.push_back(st);
  }
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
