#pragma once
// millnet job's rest operation (issue 41; docs/job.md step 4b): the program of a smaller tool where
// the finishing leaves rest, checked on the stock it meets before it joins the job.
#include "finish_job.hpp"

#include "millnet/job/operations.hpp"
#include "millnet/tooling/cutting.hpp"

#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

/// The rest operation of `rest` (smaller than the finishing tool; `cut` its cutting data) from
/// `left`, the stock the finishing leaves (program frame; `before` the programs that cut it, which
/// measure its rest exactly): job_rest_program's program, its reach
/// checked at its lowest cut, machined on a copy of `left` — links raised over the pooled stock
/// (job::clear_rapids) only where that finds a rapid that cuts, and left out (said, with where)
/// when it would cut beyond the tool's flutes unless `keep_deep_cuts`. Empty when there is no
/// rest to take or it is left out. What it says goes to `notes` (and stderr, prefixed "job:
/// <stem>: "). Throws millnet::Error when the tool's reach falls short of its lowest cut.
[[nodiscard]] std::optional<job::Operation> rest_operation(const job::Part& part, const FinishSettings& settings,
                                                           const simulate::ZMap& left, const job::Design& design,
                                                           const std::vector<job::ChainStep>& before,
                                                           const tooling::Tool& rest, const RestCut& cut,
                                                           double min_area_mm2, bool keep_deep_cuts,
                                                           const std::string& stem, std::vector<std::string>& notes);

}  // namespace millnet::app
