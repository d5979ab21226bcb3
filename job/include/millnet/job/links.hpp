#pragma once
// Links over the stock that is left (issue 38): a program planned against the design (finishing
// lifts to the highest CL point under a link + a clearance) meets, in a job, the stock the
// operations before it left — roughing steps up to a step-down above the design. Its rapids are
// made to clear that stock: a rapid across is raised to the highest stock under the tool's
// swept disk + the clearance, and a rapid down stops at the clearance above the stock under the
// tool, the rest of the way at the plunge feed. The stock is read max-pooled onto coarse cells
// (kLinkCellMm), so the heights used are never below the z-map's.
#include "millnet/gcode/program.hpp"
#include "millnet/simulate/zmap.hpp"
#include "millnet/tooling/cutter.hpp"

#include <cstddef>

namespace millnet::job {

/// Edge of the coarse cells the stock is pooled onto for the link checks, mm.
inline constexpr double kLinkCellMm = 0.5;

struct LinkChanges {
  std::size_t raised = 0;  ///< rapids across lifted over the stock
  std::size_t fed = 0;     ///< rapids down whose last part became a feed move
};

/// `program` with its rapids clear of `stock` (same frame) by `clearance_mm` for `cutter`; moves
/// whose start is not yet known (before the first stated X Y) are kept. Feed moves are kept: their
/// depth of cut is the simulation's to measure. O(cells + Σ over rapids of the coarse cells under
/// their swept disk).
[[nodiscard]] gcode::Program clear_rapids(const gcode::Program& program, const simulate::ZMap& stock,
                                          const tooling::Cutter& cutter, double clearance_mm, double plunge_feed_mm_min,
                                          LinkChanges* changes = nullptr);

}  // namespace millnet::job
