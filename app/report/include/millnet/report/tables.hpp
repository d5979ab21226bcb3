#pragma once
// The tables and charts that rank a part's finishing strategies: <stem>.strategies.csv and .md (one
// row per strategy, best first) and the paper's Figure 9 (share of the surface per Ra bin, per
// strategy) as <stem>.strategies.png.
#include "millnet/job/finishing.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace millnet::report {

struct StrategyTable {
  std::string csv, md;
};

/// The ranking of `outcomes` in `order` (best first; job::rank_outcomes): CSV and Markdown, with the
/// simulated columns when `simulated`. `aim` names the rule in the Markdown title.
[[nodiscard]] StrategyTable strategy_table(const std::string& stem, const std::string& aim,
                                           const std::vector<job::StrategyOutcome>& outcomes,
                                           const std::vector<std::size_t>& order, bool simulated);

/// Figure 9: grouped bars of each simulated outcome's share of the surface per Ra bin (bin edges
/// `edges_um`, the last bin open). O(outcomes × bins).
void ra_bins_png(const std::filesystem::path& path, const std::string& stem, const std::vector<double>& edges_um,
                 const std::vector<job::StrategyOutcome>& outcomes);

}  // namespace millnet::report
