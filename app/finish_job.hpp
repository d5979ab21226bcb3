#pragma once
// millnet finish / millnet simulate: the files a finished (and simulated) part is written to. The
// work is job/'s (the frame, the design surface, programs machined and scored) and finish/'s (the
// tool paths); this file wires them to the settings and writes programs, metrics and pictures.
//
// Frame (job/frame.hpp): program Z = part z − stock_top, stock_top = part top +
// /rough/top_allowance_mm, so a rough and a finish program of the same part run in the same work
// offset. Z in the programs is the tool tip.
#include "settings.hpp"

#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/job/chain.hpp"
#include "millnet/job/finishing.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/job/part.hpp"
#include "millnet/simulate/aim.hpp"
#include "millnet/simulate/io/zmap_file.hpp"
#include "millnet/simulate/zmap.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

/// A part's finishing: its frame, its design surface (when simulated) and every strategy's outcome.
struct PartFinish {
  job::Frame frame;
  std::optional<job::Design> design;
  std::vector<job::StrategyOutcome> outcomes;
};

/// What every strategy of a part shares: its frame, the finishing parameters in it, the drop
/// cutter, the height picture under the paths and (simulated) the design surface.
struct PartJob {
  job::Frame frame;
  finish::FinishParams params;
  std::optional<finish::DropCutter> dropper;
  ingest::HeightField hf;
  Eigen::MatrixXd heights;
  std::optional<job::Design> design;
  simulate::ZMap spare;  ///< the machined z-map of the strategy scored last: its memory reused
};

/// The frame, the holder check, the parameters in the frame and (unless `with_dropper` is false:
/// the frame and parameters only, for another tool) the drop-cutter, and, simulated, the design
/// surface: what planning and scoring a part's strategies needs.
[[nodiscard]] PartJob finishing_job(const job::Part& part, const FinishSettings& settings, bool with_dropper = true);

/// A simulated stock (a z-map in the program frame) as rest finishing reads it, in the part's frame.
[[nodiscard]] finish::RestStock stock_of(simulate::ZMap z, const job::Frame& frame);

/// The rest program's parameters: `base` (the finishing's) with the rest tool, and — when the
/// strategies take theirs from the specification (/finish/params_from "spec") — the stepover and
/// step-down that strategy 1, the rest's pattern, derives from the spec for that tool: the rest is
/// finished to the surface specification the strategies were compared at, with its own ball's
/// spacing (a Ø1 ball at the default 0.005 mm scallop: 0.141 mm on the surface; the finishing
/// Ø2's 0.2 mm would leave 0.010 mm scallops, its 0.04 mm step-down cut 3.5× the Z-levels). Its
/// links over the stock are timed by the machine's motion (/machine).
[[nodiscard]] finish::FinishParams rest_finish_params(const FinishSettings& settings, finish::FinishParams base,
                                                      const tooling::Cutter& rest_tool);

/// Rest finishing as a job's operation (issue 41): the program of `rest_tool` behind the stock `z`
/// the operations before it left (a z-map in the program frame), planned as `finish --rest-tool
/// --rest-from` plans it, in the part's finishing frame. Empty, with `why` saying so, when the rest
/// tool's axis positions over rest cover less than `min_area_mm2` (or none). `cut`: the rest
/// tool's spindle speed, feed and plunge feed. With `before` (the programs that cut `z`) and the
/// design on z's grid, the rest is measured as the job judges it (job::measure_rest_exactly).
struct RestCut {
  double rpm = 0, feed_mm_min = 0, plunge_feed_mm_min = 0;
  double stepover_mm = 0, step_down_mm = 0;  ///< rest_finish_params' (the setup sheet's)
};
[[nodiscard]] std::optional<gcode::Program> job_rest_program(const job::Part& part, const FinishSettings& settings,
                                                             const simulate::ZMap& z, const tooling::Cutter& rest_tool,
                                                             double min_area_mm2, const RestCut& cut, std::string& why,
                                                             const job::Design* design = nullptr,
                                                             const std::vector<job::ChainStep>& before = {});

/// Plans, writes and (optionally) simulates every strategy of `settings` on the part:
/// DIR/<stem>.s<k>.nc, .metrics.json, .png, .ra.png (with simulate); with several strategies also
/// <stem>.strategies.csv/.md and <stem>.strategies.png (the paper's Figure 9), ranked by the aim.
/// The part's CAD report goes into each metrics file as "cad".
PartFinish finish_part(const job::Part& part, const FinishSettings& settings, const std::filesystem::path& out);

/// Some strategies of finish_part (a unit of a batch: a part, or under MPI a part × strategy): the
/// same files and figures finish_part writes for them, without the ranking files.
std::vector<job::StrategyOutcome> finish_strategies(const job::Part& part, const FinishSettings& settings,
                                                    const std::vector<finish::Strategy>& strategies,
                                                    const std::filesystem::path& out);

/// With several outcomes (in settings.strategies order): ranks them by the aim (sets their rank) and
/// writes <stem>.strategies.csv/.md and, simulated, <stem>.strategies.png. Nothing for one.
void write_strategy_ranking(const std::string& stem, const FinishSettings& settings,
                            std::vector<job::StrategyOutcome>& outcomes, const std::filesystem::path& out);

/// The file a strategy's program is written to: <base>.nc, or <base>.GOUGES.nc when its simulation
/// confirmed a gouge (kept for inspection; such a program never ranks).
[[nodiscard]] std::string program_file_name(const std::string& base, const job::StrategyOutcome& o);
/// The one line a confirmed gouge fails a command with: the program, the depth, the G-code line
/// and the XY of the deepest gouge.
[[nodiscard]] std::string gouge_failure(const std::string& program, const simulate::SurfaceMetrics& m);

/// The keys of <stem>.s<k>.metrics.json for an outcome of the part (its CAD report under "cad").
[[nodiscard]] Json strategy_metrics(const job::StrategyOutcome& o, const FinishSettings& settings,
                                    const job::Part& part);
/// An outcome back from its metrics (how a rank's result travels to rank 0 under MPI); `cell_mm`
/// gives the scored surface's area.
[[nodiscard]] job::StrategyOutcome outcome_from_metrics(const Json& metrics, double cell_mm);

/// A part labelled by simulation: every strategy of `settings` planned, written in memory, machined
/// and scored, ranked by the aim (job::score_strategies). Writes nothing.
[[nodiscard]] std::vector<job::StrategyFigures> label_part(const job::Part& part, const FinishSettings& settings);

/// The simulated surface's keys of a metrics or .sim.json file (gouge, scallop, Ra, uncut, rest,
/// the specification's share) over the z-map grid.
[[nodiscard]] Json sim_metrics_json(const simulate::SurfaceMetrics& m, const simulate::GridSpec& grid);

/// The job::SimParams of the settings (with the run's work limits).
[[nodiscard]] job::SimParams sim_params(const FinishSettings& settings);

/// A program of `millnet simulate` or of a chain: read from its file or written in memory.
struct ChainProgram {
  std::string file;  ///< its path as given ("gcode" in the metrics; its file name in the preview)
  gcode::Written written;
  tooling::Cutter cutter;
};

/// millnet simulate: machines `programs` one after the other on one z-map over the part, stock flat
/// at Z = 0 ("flat"), the design + allowance ("design") or a z-map file saved by an earlier
/// simulation of the same part (any other value: its path; the grid must match); writes
/// DIR/<stem>.sim.json, <stem>.ra.png and <stem>.deviation.png, and with save_stock the machined
/// z-map as DIR/<stem>.zmap. `design` (the part's, when its finishing already made it) saves a
/// second rasterization. `score_rest` (millnet simulate): a last program with a smaller tool than a
/// finishing one before it is scored as rest machining (job::machine_chain). `record_moves`
/// (simulate --moves): every move of every program as machined, one row each, in DIR/<stem>.moves.csv
/// (job::moves_csv).
Json simulate_programs(const job::Part& part, const std::string& stem, std::vector<ChainProgram> programs,
                       const std::string& stock, const FinishSettings& settings, const std::filesystem::path& out,
                       bool save_stock = false, const job::Design* design = nullptr, bool score_rest = false,
                       bool record_moves = false);

/// A stock saved by `simulate --save-stock` (FILE.zmap), checked to lie on the part's grid `g`
/// (millnet::Error naming the file and both grids otherwise).
[[nodiscard]] simulate::ZMap stock_from_file(const std::string& file, const simulate::GridSpec& g);
/// stock_from_file with the block's surround the file may carry (simulate/io/zmap_file.hpp).
[[nodiscard]] simulate::io::SavedStock saved_stock_from_file(const std::string& file, const simulate::GridSpec& g);

/// A program file read for simulate_programs (the file's text and that text read back), shifted from
/// the work frame `post` placed it in (its origin) back into millnet's.
[[nodiscard]] ChainProgram read_chain_program(const std::filesystem::path& file, const tooling::Cutter& cutter,
                                              const gcode::Dialect& post = {});

}  // namespace millnet::app
