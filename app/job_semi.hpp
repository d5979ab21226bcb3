#pragma once
// The job's semi-finishing (issue 38): a larger ball over the design + the finishing allowance when
// the roughing leaves more than the finishing tool's flutes take (app/cmd_job.cpp's step 4).
#include "cutting.hpp"
#include "finish_job.hpp"
#include "settings.hpp"

#include "millnet/job/chain.hpp"
#include "millnet/job/operations.hpp"
#include "millnet/job/part.hpp"

#include <optional>
#include <string>

namespace millnet::app {

/// What the semi-finishing needs to know of the job so far.
struct SemiFinishInput {
  const job::Part& part;
  const PartFinish& finishing;
  const FinishSettings& settings;
  const tooling::Tool& finisher;
  const tooling::Tool& mill;
  const job::StepResult& roughed;  ///< what the roughing left (its largest and where)
  double depth_mm = 0;             ///< the part's depth below the stock top (the reach)
};

/// A semi-finishing operation (issue 38) for when the roughing leaves more above the design than
/// the finishing tool's flutes take: strategy 1 (Z-level on the steep, raster on the shallow, as a
/// CAM engineer semi-finishes) with the library's smallest larger ball whose flutes take that
/// stock, over the design + the finishing allowance (a ball of radius R over the surface offset by
/// a is a ball of radius R + a over the surface, raised by a), its passes the step that leaves
/// cusps no higher than the allowance, at the ball's own cutting data. Refused in one line when no
/// ball of the library will do.
struct SemiFinish {
  job::Operation op;
  finish::FinishParams params;  ///< its cutting data and steps
};
/// semi_finishing with `semi`, the ball chosen. Throws millnet::Error naming it when it cannot plan.
[[nodiscard]] SemiFinish semi_finishing(const SemiFinishInput& in, const tooling::Tool& semi, const Json& config,
                                        const std::optional<std::string>& material, const ToolLibrary& lib);

/// The semi-finishing whose flutes take what it meets: the candidates (job::semi_finishing_tools)
/// planned in turn, each program's links lifted over the roughed stock and machined on a copy of
/// it, the first whose axial engagement its flutes take. Refused in one line naming the least
/// engaged candidate when none will do.
[[nodiscard]] SemiFinish semi_finishing_that_fits(const SemiFinishInput& in, const simulate::ZMap& roughed,
                                                  const job::Design& design, const FinishSettings& fs,
                                                  const Json& config, const std::optional<std::string>& material,
                                                  const ToolLibrary& lib, const std::string& file, double finish_cut);

}  // namespace millnet::app
