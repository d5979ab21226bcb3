#pragma once
// Finishing a part and proving it by virtual machining: the design surface on a z-map grid, each
// strategy's program machined on a stock of the design + allowance and its surface scored, and the
// figures the aims rank by. Values in, values out: nothing here writes a file (app/ writes the
// programs, metrics and pictures; dataset labelling writes none of them).
//
//   const job::Design d = job::design_surface(part.mesh, frame, sim);
//   for (const finish::FinishPlan& plan : finish::plan_finish(mesh, dropper, strategies, params)) {
//     const gcode::Written w = gcode::written(plan.program, post, name);      // as the machine gets it
//     const job::Scored s = job::score_program(d, frame, w.program, params.tool, sim);
//     scores.push_back(job::strategy_score(slot, stats.kinematic_time_min, s, d.grid.cell));
//   }
#include "millnet/core/budget.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/gcode/program.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/simulate/aim.hpp"
#include "millnet/simulate/exact_gouge.hpp"
#include "millnet/simulate/zmap.hpp"
#include "millnet/tooling/cutter.hpp"

#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace millnet::job {

/// How a finished surface is simulated and measured (/simulate).
struct SimParams {
  double cell_mm = 0.02;  ///< z-map cell edge
  /// > 0: cell_mm is this spacing of the passes / /simulate/cells_per_pass (a refusal names that key).
  double pass_spacing_mm = 0;
  double allowance_mm = 0.1;        ///< finishing stock over the design surface
  double tolerance_mm = 0.002;      ///< gouge / remaining-material tolerance
  double sampling_length_mm = 0.8;  ///< Ra sampling length (ISO 4288)
  double ra_spacing_mm = 0.1;       ///< Ra centres this far apart (whole cells)
  std::vector<double> ra_bins_um{0, 0.4, 0.8, 1.6, 3.2, 6.3, 12.5, 25};
  /// The surface specification's limit (finish::SurfaceSpec::limit_mm: scallop + form tolerance);
  /// NaN: no specification, its figures not measured.
  double spec_limit_mm = std::numeric_limits<double>::quiet_NaN();
  double ra_target_um = std::numeric_limits<double>::quiet_NaN();  ///< the quality aim's Ra target; NaN: none
  WorkLimits limits;  ///< the z-map, design and metrics are checked against them first
  /// Material over the design thicker than this (along the normal) is rest, for a rest step's
  /// figures (ChainResult::rest_area_*; /finish/rest/threshold_mm, finish --rest-threshold).
  double rest_threshold_mm = 0.02;

  /// The surface metrics' options for a finished surface (nothing should be left: allowance 0),
  /// with `cutter` the last tool (scallop, rest material and uncut told apart).
  [[nodiscard]] simulate::MetricsOptions metrics_options(const tooling::Cutter& cutter) const;
  /// The z-map's own memory backstop: the run's memory limit.
  [[nodiscard]] std::size_t max_bytes() const;
  /// The exact gouge check's options (its tolerance is the gouge tolerance).
  [[nodiscard]] simulate::ExactGougeOptions gouge_options() const;
};

/// The part's design surface on the z-map grid over its footprint: cells of sim.cell_mm from
/// (0, 0), heights in the program frame (NaN off the part); and the part's triangles in the program
/// frame, for the exact check of the z-map's gouges (simulate/exact_gouge.hpp; null: unchecked).
struct Design {
  simulate::GridSpec grid;
  std::vector<double> heights;
  std::shared_ptr<const simulate::PartSolid> solid;
  /// The surface a finishing program is judged on (simulate::MetricsOptions::judged); empty = all.
  std::vector<std::uint8_t> judged;
  /// The rest-material test's answers, shared by every program scored on this design (its
  /// strategies): computed once per part instead of once per program (simulate::ReachMemo).
  std::shared_ptr<simulate::ReachMemo> reach_memo = std::make_shared<simulate::ReachMemo>();
};

/// Judges finishing only inside a machining boundary (issue 38): the cells whose centre the
/// boundary's polygons enclose and whose design height (program frame) lies in [z_min, z_max] of
/// `boundary` given in the program frame. Nothing changes when the boundary has neither. O(cells ·
/// polygon points).
void judge_within(Design& design, const finish::Boundary& boundary_program_frame);

/// Rasterizes the design once per part. Checked first against sim.limits: the z-map (12 bytes a
/// cell) + design and raster (17) + the metrics' per-cell excess (8). Throws millnet::Error.
[[nodiscard]] Design design_surface(const ingest::Mesh& mesh, const Frame& frame, const SimParams& sim);

/// The stock a finishing program starts from: the design + allowance (off the part: the allowance
/// above the part's lowest point, where the table would be).
/// `reuse`: a z-map no longer needed whose memory it takes (simulate::ZMap::from_heights).
[[nodiscard]] simulate::ZMap finishing_stock(const Design& design, const Frame& frame, const SimParams& sim,
                                             simulate::ZMap reuse = {});

/// One program machined and its surface measured.
struct Scored {
  simulate::SurfaceMetrics metrics;
  std::size_t cutting_rapids = 0;  ///< rapids that removed material
  double max_depth_of_cut_mm = 0;  ///< deepest cut of any move (axial engagement)
  simulate::ZMap machined;         ///< the machined stock (pictures and previews)
};

/// Machines `program` (as written: gcode::Written::program, so that gouges name their lines) with
/// `cutter` on the finishing stock and scores the surface against the design; the z-map's gouges
/// are confirmed or refuted by the exact check (design.solid), so metrics.gouged is a real gouge.
/// Writes nothing. `reuse`: the machined z-map of a program scored before, no longer needed (its
/// memory is taken over: finishing_stock).
[[nodiscard]] Scored score_program(const Design& design, const Frame& frame, const gcode::Program& program,
                                   const tooling::Cutter& cutter, const SimParams& sim, simulate::ZMap reuse = {});

/// The figures an aim ranks a strategy by (simulate::rank_strategies).
[[nodiscard]] simulate::StrategyScore strategy_score(int slot, double time_min, const Scored& scored, double cell_mm);

/// The part's finishing parameters: `base` in its frame (z_shift), named after it, its header the
/// tool's lines then the frame's.
[[nodiscard]] finish::FinishParams part_params(finish::FinishParams base, const Frame& frame, const std::string& name,
                                               std::vector<std::string> tool_lines);

/// One strategy of a part, planned and (simulated) machined: the figures of its metrics file, of
/// its row in the ranking table and of the paper's Figure 9.
struct StrategyOutcome {
  finish::Strategy strategy = finish::Strategy::Raster;
  double path_length_mm = 0;  ///< the plan's cutting path
  std::size_t lifts = 0, passes = 0, cl_points = 0, drops = 0;
  double planning_s = 0;
  double time_feed_min = 0, time_kinematic_min = 0;  ///< gcode::stats with the /machine motion model
  bool simulated = false;
  simulate::SurfaceMetrics surface;  ///< simulated: the scores (its per-cell Ra map is left empty)
  simulate::GridSpec grid;           ///< simulated: the z-map grid (where the gouge is)
  std::size_t cutting_rapids = 0;
  double max_depth_of_cut_mm = 0;
  simulate::StrategyScore score;  ///< what the aim ranks (time only when not simulated)
  int rank = 0;                   ///< 1-based by the aim, once ranked; 0 before
  /// Its time / the best's time − 1, once ranked (simulate::regrets; NaN when no strategy is good
  /// enough to measure against).
  double regret = std::numeric_limits<double>::quiet_NaN();
  bool meets_spec = false;  ///< once ranked: simulate::meets_spec
  /// The parameters it was planned with (the spec's derived ones, or the fixed ones).
  double stepover_mm = 0, step_down_mm = 0, scallop_mm = 0;
  double feed_mm_min = 0;  ///< its cutting feed (chip thinning may raise it above the tool's)
};

/// The outcome of a planned strategy, from its plan and program figures (not simulated yet).
[[nodiscard]] StrategyOutcome planned_outcome(const finish::FinishPlan& plan, const gcode::ProgramStats& stats);
/// Adds a simulation's figures (score_program) to an outcome; the per-cell Ra map is not kept.
void add_simulation(StrategyOutcome& outcome, const Scored& scored, const simulate::GridSpec& grid);

/// Ranks outcomes by the aim (time only when they were not simulated: without a surface only time
/// can rank): sets each one's rank and returns their indices best first. O(n log n).
std::vector<std::size_t> rank_outcomes(std::vector<StrategyOutcome>& outcomes, simulate::AimParams aim);

/// One line per ranked, simulated outcome that misses the surface specification: its share in spec,
/// the area over it (and where the most material is left) and the area not machined. O(outcomes).
[[nodiscard]] std::vector<std::string> spec_misses(const std::vector<StrategyOutcome>& outcomes);

/// The outcomes' slots, ranks and Ra medians as columns, in the outcomes' order (a run's summary
/// sets the network's ranking beside them).
struct OutcomeColumns {
  std::vector<int> slots, ranks;
  std::vector<double> ra_median_um;
  std::vector<double> time_min;    ///< kinematic
  std::vector<double> regret;      ///< NaN where unmeasured
  std::vector<double> spec_share;  ///< NaN without a specification
  std::vector<int> meets_spec;     ///< 1 / 0
};
[[nodiscard]] OutcomeColumns outcome_columns(const std::vector<StrategyOutcome>& outcomes);

/// `first`, then the other ranked strategies in the simulated ranking's order, those that gouge left
/// out: the order a job tries them in when the first would cut beyond its tool's flutes.
/// O(strategies log strategies).
[[nodiscard]] std::vector<StrategyOutcome> ranked_clean(const std::vector<StrategyOutcome>& outcomes,
                                                        const StrategyOutcome& first);

/// What labelling a part needs of one strategy (datasets' labels, the agreement table).
struct StrategyFigures {
  int slot = 0;
  simulate::StrategyScore score;
  int rank = 0;                                              ///< 1-based, by the aim
  double regret = std::numeric_limits<double>::quiet_NaN();  ///< simulate::regrets
  double aim_score = 0;                                      ///< simulate::aim_scores (the network's output)
};

/// Every strategy of `plans` written in memory (`post`), machined and scored (each plan freed once
/// scored), then ranked by
/// `aim`: the labelling of a part by simulation. Writes nothing; O(strategies × z-map).
[[nodiscard]] std::vector<StrategyFigures> score_strategies(const ingest::Mesh& mesh, const Frame& frame,
                                                            std::vector<finish::FinishPlan> plans,
                                                            const tooling::Cutter& cutter, const gcode::Dialect& post,
                                                            const gcode::MotionModel& machine,
                                                            const simulate::AimParams& aim, const SimParams& sim);

}  // namespace millnet::job
