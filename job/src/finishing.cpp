// The design surface, a program machined and scored, and a part's strategies labelled (finishing.hpp).
#include "millnet/job/finishing.hpp"

#include "millnet/ingest/heightfield.hpp"
#include "millnet/simulate/maps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

namespace millnet::job {

namespace {
constexpr double kRestBlockMm = 0.125;  ///< the rest test's block side at the default cell (5 × 0.025 mm)
}  // namespace

simulate::MetricsOptions SimParams::metrics_options(const tooling::Cutter& cutter) const {
  simulate::MetricsOptions mo;
  mo.allowance_mm = 0;
  mo.tolerance_mm = tolerance_mm;
  mo.sampling_length_mm = sampling_length_mm;
  mo.ra_bins_um = ra_bins_um;
  mo.ra_every = static_cast<std::size_t>(std::max(1.0, std::round(ra_spacing_mm / cell_mm)));
  // A cell from the passes' spacing keeps the rest test's block and stride near their millimetres at
  // the default cell (5 × 0.025 mm): the rest found must not grow with the cell.
  if (pass_spacing_mm > 0) mo.reach_every = static_cast<std::size_t>(std::max(1.0, std::round(kRestBlockMm / cell_mm)));
  mo.cutter = cutter;
  mo.spec_limit_mm = spec_limit_mm;
  mo.ra_target_um = ra_target_um;
  return mo;
}

simulate::ExactGougeOptions SimParams::gouge_options() const {
  simulate::ExactGougeOptions o;
  o.tolerance_mm = tolerance_mm;
  return o;
}

std::size_t SimParams::max_bytes() const { return static_cast<std::size_t>(std::min(limits.max_memory_bytes, 1e18)); }

namespace {
/// Bytes per z-map cell the simulating run holds at its peak, all stages together (measured, below).
constexpr double kRunBytesPerCell = 44;

/// The z-map grid over the part's footprint at `cell` mm.
simulate::GridSpec footprint_grid(const Frame& frame, double cell) {
  simulate::GridSpec g;
  g.cell = cell;
  g.nx = static_cast<std::size_t>(std::max(1.0, std::ceil(frame.width / cell)));
  g.ny = static_cast<std::size_t>(std::max(1.0, std::ceil(frame.depth / cell)));
  return g;
}

/// Refuses a z-map the limits cannot hold before any of it is allocated, naming the coarsest
/// thousandth of a millimetre that would fit so that the user can choose (issue 37 §3: a 300 mm
/// part at the default cell is refused with its estimate rather than run past 4 GB).
void check_design_work(const Frame& frame, const SimParams& sim) {
  const auto work = [&](double cell) {
    return simulate::zmap_work(footprint_grid(frame, cell), kRunBytesPerCell - 12);
  };
  const auto fits = [&](const WorkEstimate& e) {
    return e.bytes <= sim.limits.max_memory_bytes && (e.memory_only || e.count <= sim.limits.max_work);
  };
  const WorkEstimate e = work(sim.cell_mm);
  if (fits(e)) return;
  // The cell that fits: cells fall with its square, so start from the ratio and step up by 1 µm
  // (a handful of steps; the ceil of the grid's sides can keep the first one just over).
  double cell = std::ceil(sim.cell_mm * std::sqrt(e.bytes / std::max(1.0, sim.limits.max_memory_bytes)) * 1000) / 1000;
  for (int k = 0; k < 1000 && !fits(work(cell)); ++k) cell += 0.001;
  try {
    check_work(e, sim.limits);
  } catch (const Error& err) {
    char buf[128];
    if (sim.pass_spacing_mm > 0)  // the cell from the passes' spacing: the key that sets it
      std::snprintf(buf, sizeof buf, "; /simulate/cells_per_pass %.2f (a cell of %.3f mm) fits",
                    std::floor(sim.pass_spacing_mm / cell * 100) / 100, cell);
    else
      std::snprintf(buf, sizeof buf, "; /simulate/cell_mm %.3f fits", cell);
    throw Error(err.what() + std::string(buf));
  }
}
}  // namespace

Design design_surface(const ingest::Mesh& mesh, const Frame& frame, const SimParams& sim) {
  Design d;
  d.grid = footprint_grid(frame, sim.cell_mm);
  d.grid.check();
  // Before any is allocated. At the peak (the metrics' rest split) the design (8 B per cell), the
  // machined z-map (12), the material over the design (8) and two byte masks are alive: 30 B per cell,
  // 38 with a boundary's judged copy of the design; the drop-cutter's index and the plans are freed
  // or shrinking by then. `finish --strategy all --simulate` on a 300 × 200 mm plate (9.6e7 cells)
  // peaked at 3.88 GB by getrusage, 40.4 B per cell with everything fixed in it (was 72 B per cell
  // budgeted and 60 used before 2026-12-05: the index and the plans stayed alive through the scoring).
  check_design_work(frame, sim);
  const ingest::HeightField hf = ingest::rasterize_top(mesh, 0.5 * d.grid.cell, 0.5 * d.grid.cell, d.grid.cell,
                                                       static_cast<int>(d.grid.nx), static_cast<int>(d.grid.ny));
  d.heights = simulate::design_heights(hf, frame.z_shift());
  d.solid = std::make_shared<const simulate::PartSolid>(mesh, frame.z_shift());
  return d;
}

simulate::ZMap finishing_stock(const Design& design, const Frame& frame, const SimParams& sim, simulate::ZMap reuse) {
  return simulate::ZMap::from_heights(design.grid, design.heights, sim.allowance_mm, frame.z_shift() + sim.allowance_mm,
                                      sim.max_bytes(), std::move(reuse));
}

Scored score_program(const Design& design, const Frame& frame, const gcode::Program& program,
                     const tooling::Cutter& cutter, const SimParams& sim, simulate::ZMap reuse) {
  Scored s;
  s.machined = finishing_stock(design, frame, sim, std::move(reuse));
  const simulate::SweepResult sw = simulate::machine(s.machined, program, cutter);
  s.cutting_rapids = sw.cutting_rapids.size();
  s.max_depth_of_cut_mm = sw.item_max_engage_mm.empty()
                              ? 0.0
                              : *std::max_element(sw.item_max_engage_mm.begin(), sw.item_max_engage_mm.end());
  // Uncut = reachable material the program left; the scallops between passes are scored by
  // scallop and Ra, and the rest material no program with this cutter can clear is apart.
  simulate::MetricsOptions mo = sim.metrics_options(cutter);
  mo.judged = design.judged;
  mo.reach_memo = design.reach_memo;
  s.metrics = simulate::surface_metrics(s.machined, design.heights, mo);
  if (design.solid)  // a z-map gouge is a gouge only when the exact check confirms it (issue 37 §1)
    simulate::confirm_gouges(s.metrics, s.machined, design.heights, *design.solid, {{&program, cutter}},
                             sim.gouge_options());
  return s;
}

void judge_within(Design& design, const finish::Boundary& b) {
  if (b.polygons.empty() && !b.limits_z()) return;
  const simulate::GridSpec& g = design.grid;
  design.judged.assign(design.heights.size(), 1);
  design.reach_memo = std::make_shared<simulate::ReachMemo>();  // its answers were for the whole surface
  for (std::size_t iy = 0; iy < g.ny; ++iy)                     // O(cells · polygon points)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const std::size_t i = iy * g.nx + ix;
      const double z = design.heights[i];
      const bool in = b.encloses(g.x(ix), g.y(iy)) && (std::isnan(z) || (z >= b.z_min && z <= b.z_max));
      design.judged[i] = in ? 1 : 0;
    }
}

simulate::StrategyScore strategy_score(int slot, double time_min, const Scored& scored, double cell_mm) {
  simulate::StrategyScore c;
  c.slot = slot;
  c.time_min = time_min;
  c.ra_median_um = scored.metrics.ra_median_um;
  c.ra_p90_um = scored.metrics.ra_p90_um;
  c.uncut_area_mm2 = scored.metrics.uncut_area_mm2;
  c.max_gouge_mm = scored.metrics.max_gouge_mm;
  c.surface_area_mm2 = static_cast<double>(scored.metrics.surface_cells) * cell_mm * cell_mm;
  if (scored.metrics.spec_measured) c.spec_share = scored.metrics.spec_share;
  c.ra_target_share = scored.metrics.ra_target_share;
  return c;
}

StrategyOutcome planned_outcome(const finish::FinishPlan& plan, const gcode::ProgramStats& stats) {
  StrategyOutcome o;
  o.strategy = plan.strategy;
  o.path_length_mm = plan.path_length_mm;
  o.lifts = plan.lifts;
  o.passes = plan.passes.size();
  o.cl_points = plan.cl_points;
  o.drops = plan.drops_needed;
  o.planning_s = plan.planning_s;
  o.time_feed_min = stats.feed_time_min;
  o.time_kinematic_min = stats.kinematic_time_min;
  o.score.slot = static_cast<int>(plan.strategy);
  o.score.time_min = stats.kinematic_time_min;
  return o;
}

void add_simulation(StrategyOutcome& o, const Scored& scored, const simulate::GridSpec& grid) {
  o.simulated = true;
  o.surface = scored.metrics;
  o.surface.ra_um.clear();
  o.surface.ra_um.shrink_to_fit();
  o.grid = grid;
  o.cutting_rapids = scored.cutting_rapids;
  o.max_depth_of_cut_mm = scored.max_depth_of_cut_mm;
  o.score = strategy_score(o.score.slot, o.time_kinematic_min, scored, grid.cell);
}

namespace {
/// Ranks `scores` by the aim: each one's 1-based rank and regret, and the order best first.
struct Ranked {
  std::vector<std::size_t> order;
  std::vector<int> rank;
  std::vector<double> regret;
};
Ranked rank_scores(const std::vector<simulate::StrategyScore>& scores, const simulate::AimParams& aim) {
  Ranked r;
  r.order = simulate::rank_strategies(scores, aim);
  r.rank = simulate::ranks_from_order(r.order);
  r.regret = simulate::regrets(scores, r.order, aim);
  return r;
}
}  // namespace

std::vector<std::size_t> rank_outcomes(std::vector<StrategyOutcome>& outcomes, simulate::AimParams aim) {
  std::vector<simulate::StrategyScore> scores;
  bool simulated = !outcomes.empty();
  for (const StrategyOutcome& o : outcomes) {  // O(n)
    scores.push_back(o.score);
    simulated = simulated && o.simulated;
  }
  if (!simulated) aim.aim = simulate::Aim::Time;
  const Ranked r = rank_scores(scores, aim);
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    outcomes[i].rank = r.rank[i];
    outcomes[i].regret = r.regret[i];
    outcomes[i].meets_spec = simulate::meets_spec(outcomes[i].score, aim);
  }
  return r.order;
}

std::vector<std::string> spec_misses(const std::vector<StrategyOutcome>& outcomes) {
  auto fixed = [](double v, int decimals) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return std::string(b);
  };
  std::vector<std::string> lines;
  for (const StrategyOutcome& o : outcomes) {
    const simulate::SurfaceMetrics& m = o.surface;
    if (!o.simulated || !m.spec_measured || o.meets_spec) continue;
    const double a = o.grid.cell * o.grid.cell;
    std::string where;
    if (m.over_spec_cell < o.grid.cells())
      where = " by up to " + fixed(m.over_spec_max_mm, 3) + " mm at X " +
              fixed(o.grid.x(m.over_spec_cell % o.grid.nx), 2) + " Y " +
              fixed(o.grid.y(m.over_spec_cell / o.grid.nx), 2);
    lines.push_back("strategy " + std::to_string(static_cast<int>(o.strategy)) +
                    " misses the specification: " + fixed(100 * m.spec_share, 1) + " % of the surface in spec (" +
                    fixed(static_cast<double>(m.over_spec_cells) * a, 1) + " mm² over it" + where + ", " +
                    fixed(static_cast<double>(m.spec_not_machined_cells) * a, 1) + " mm² not machined)");
  }
  return lines;
}

OutcomeColumns outcome_columns(const std::vector<StrategyOutcome>& outcomes) {
  OutcomeColumns c;
  for (const StrategyOutcome& o : outcomes) {  // O(n)
    c.slots.push_back(static_cast<int>(o.strategy));
    c.ranks.push_back(o.rank);
    c.ra_median_um.push_back(o.score.ra_median_um);
    c.time_min.push_back(o.time_kinematic_min);
    c.regret.push_back(o.regret);
    c.spec_share.push_back(o.score.spec_share);
    c.meets_spec.push_back(o.meets_spec ? 1 : 0);
  }
  return c;
}

finish::FinishParams part_params(finish::FinishParams base, const Frame& frame, const std::string& name,
                                 std::vector<std::string> tool_lines) {
  base.check();
  base.z_shift = frame.z_shift();
  base.program_name = name;
  base.comments = std::move(tool_lines);
  base.comments.push_back(frame.header());
  return base;
}

std::vector<StrategyFigures> score_strategies(const ingest::Mesh& mesh, const Frame& frame,
                                              std::vector<finish::FinishPlan> plans, const tooling::Cutter& cutter,
                                              const gcode::Dialect& post, const gcode::MotionModel& machine,
                                              const simulate::AimParams& aim, const SimParams& sim) {
  const Design design = design_surface(mesh, frame, sim);
  std::vector<StrategyFigures> out;
  std::vector<simulate::StrategyScore> scores;
  simulate::ZMap spare;                     // the z-map of the strategy before: its memory reused
  for (finish::FinishPlan& plan : plans) {  // O(strategies × (program + z-map))
    const int slot = static_cast<int>(plan.strategy);
    const gcode::Written w =
        gcode::written(plan.program, post, plan.program.header.empty() ? "" : plan.program.header[0]);
    const double time = gcode::stats(plan.program, machine).kinematic_time_min;
    Scored s = score_program(design, frame, w.program, cutter, sim, std::move(spare));
    scores.push_back(strategy_score(slot, time, s, design.grid.cell));
    out.push_back({slot, scores.back(), 0});
    plan = {};  // its program and passes freed before the next is machined
    spare = std::move(s.machined);
  }
  const Ranked r = rank_scores(scores, aim);
  const std::vector<double> score = simulate::aim_scores(scores, r.order, aim);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].rank = r.rank[i];
    out[i].regret = r.regret[i];
    out[i].aim_score = score[i];
  }
  return out;
}

std::vector<StrategyOutcome> ranked_clean(const std::vector<StrategyOutcome>& outcomes, const StrategyOutcome& first) {
  std::vector<StrategyOutcome> out{first};
  for (const StrategyOutcome& k : outcomes)  // O(strategies)
    if (k.strategy != first.strategy && k.rank > 0 && !(k.simulated && k.surface.gouged)) out.push_back(k);
  std::sort(out.begin() + 1, out.end(), [](const auto& a, const auto& b) { return a.rank < b.rank; });
  return out;
}

}  // namespace millnet::job
