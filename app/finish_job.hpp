#pragma once
// millnet finish / millnet simulate: wiring of finish:: (tool paths), gcode:: (text, times) and
// simulate:: (virtual machining) for one part, and the files they write. No algorithm lives here.
//
// Frame (the roughing contract): the mesh is prepared (units, up → +Z, footprint lower-left at
// x = y = 0, lowest point z = 0); program Z = part z − stock_top with stock_top = part top +
// stock_top_above_part_mm (/rough/top_allowance_mm), so a rough and a finish program of the same
// part run in the same work offset. Z in the programs is the tool tip.
#include "settings.hpp"

#include "millnet/finish/strategy.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/simulate/aim.hpp"
#include "millnet/simulate/zmap.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

/// One strategy's figures (the keys of <stem>.s<k>.metrics.json).
struct StrategyOutcome {
  finish::Strategy strategy = finish::Strategy::Raster;
  Json metrics;
  simulate::StrategyScore score;
  std::vector<double> ra_share;  ///< per Ra bin (with --simulate)
  int rank = 0;                  ///< 1-based rank by the aim when several strategies ran, else 0
};

/// Plans, writes and (optionally) simulates every strategy of `settings` on the prepared mesh:
/// DIR/<stem>.s<k>.nc, .metrics.json, .png, .ra.png (with simulate); with several strategies also
/// <stem>.strategies.csv/.md and <stem>.strategies.png (the paper's Figure 9), ranked by the aim.
/// `cad` (cad_metrics of the part's file, null for meshes) goes into each metrics file as "cad".
std::vector<StrategyOutcome> finish_part(const ingest::Mesh& mesh, const std::string& stem,
                                         const FinishSettings& settings, const std::filesystem::path& out,
                                         const Json& cad = Json());

/// One strategy of finish_part on its own (MPI's work unit is part × strategy): the same files and
/// figures finish_part writes for that strategy (rank 0), without the ranking files.
StrategyOutcome finish_strategy(const ingest::Mesh& mesh, const std::string& stem, const FinishSettings& settings,
                                finish::Strategy strategy, const std::filesystem::path& out, const Json& cad = Json());

/// With several outcomes (in settings.strategies order): ranks them by the aim (sets their rank) and
/// writes <stem>.strategies.csv/.md and, simulated, <stem>.strategies.png. Nothing for one.
void write_strategy_ranking(const std::string& stem, const FinishSettings& settings,
                            std::vector<StrategyOutcome>& outcomes, const std::filesystem::path& out);

/// millnet simulate: machines `programs` (read from disk, each with its cutter) one after the
/// other on one z-map over the part, stock flat at Z = 0 ("flat"), the design + allowance
/// ("design") or a z-map file saved by an earlier simulation of the same part (any other value: its
/// path; the grid must match); writes DIR/<stem>.sim.json, <stem>.ra.png and <stem>.deviation.png,
/// and with save_stock the machined z-map as DIR/<stem>.zmap.
Json simulate_files(const ingest::Mesh& mesh, const std::string& stem,
                    const std::vector<std::pair<std::filesystem::path, tooling::Cutter>>& programs,
                    const std::string& stock, const FinishSettings& settings, const std::filesystem::path& out,
                    bool save_stock = false);

}  // namespace millnet::app
