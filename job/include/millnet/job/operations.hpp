#pragma once
// A part's job as the machine runs it: its operations in order (drilling, roughing, finishing), each
// with the tool that runs it, assembled into one program with a tool change per operation, or into
// one program per operation for shops that run them one by one; the job program split back at its
// tool changes for the simulator; the tool that reaches; and each tool's holder clearance over the
// part. Values in, values out (app/ writes the files).
//
//   std::vector<job::Operation> ops = job::roughing_operations(rough.program, mill, &drill, drill_cut);
//   ops.push_back({"finishing s3", ball, finish_program});
//   const gcode::Program one = job::job_program(ops, header);        // T M6 (G43 H) per operation
//   for (const job::ToolRun& run : job::split_at_tool_changes(read_back)) …   // machined tool by tool
#include "millnet/gcode/program.hpp"
#include "millnet/simulate/zmap.hpp"
#include "millnet/tooling/cutting.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace millnet::job {

/// One operation: what it is, the tool that runs it (its number is the T word, its length-offset
/// register the H word), and its program (spindle on … off; its header lines become comments).
struct Operation {
  std::string name;  ///< "drilling", "roughing", "finishing s3 equidistant"
  tooling::Tool tool;
  gcode::Program program;
};

/// The spindle speed and feed of a drilling operation (tooling::cutting_data of the drill).
struct DrillCut {
  double rpm = 0;
  double feed_mm_min = 0;  ///< the drill's f_z·z·n, every feed move of the drilling
};

/// Whether a roughing program pre-drills its entries (moves with op 1).
[[nodiscard]] bool predrills(const gcode::Program& rough);

/// A roughing program as operations: without pre-drilled entries, the roughing alone; with them, a
/// drilling operation by `drill` first (the same holes as drilling cycles, gcode/cycles.hpp: from
/// the plane each plunge starts at, back to the height it rose to, at the drill's feed and speed;
/// G83 pecks of one diameter for holes deeper than three diameters), then
/// the roughing without its "load a drill" comment, its drill spindle and its pause for the end
/// mill. The drill's tip goes to the hole's level (its point leaves a cone the end mill's plunge
/// cuts: drilling deeper could reach the part below). Throws millnet::Error when the program
/// pre-drills and `drill` is null. O(items).
[[nodiscard]] std::vector<Operation> roughing_operations(const gcode::Program& rough, const tooling::Tool& mill,
                                                         const tooling::Tool* drill, const DrillCut& cut);

/// A sawn blank's top faced down to the stock top (issue 38: a stock block "pre-squared or not").
/// Program frame: XY as the part's programs, Z 0 the squared stock top every other operation starts
/// from, the blank's top above it.
struct FacingSpec {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< the stock rectangle (program XY), mm
  double blank_top = 0;                   ///< the sawn top, program Z (> 0): faced to Z 0
  double max_depth_mm = 0;                ///< per level (evenly split levels); ≤ 0: one level
  double stepover_mm = 0;                 ///< the most between passes, (0, D]
  double safe_z = 5;                      ///< rapid height, above blank_top
  double rpm = 0, feed_mm_min = 0, plunge_feed_mm_min = 0;
};

/// How far a facing pass runs past the stock on each end (the tool wholly off it), mm.
inline constexpr double kFacingRunOutMm = 2.0;
/// The rapid down beside the stock stops this far above the level; the rest is fed, mm.
inline constexpr double kFacingFeedHeightMm = 1.0;

/// The facing operation "facing" by `mill` (a flat or bull end mill): per level, parallel passes
/// along the stock's longer side, both ways (zigzag), each running from kFacingRunOutMm beyond one
/// end to as far beyond the other, the first and last a tenth of the radius past the stock's sides
/// (no unfaced rim), evenly spaced at most `stepover_mm` apart; the step between passes and every
/// descent lie off the stock (rapid to kFacingFeedHeightMm above the level beside it, fed the rest).
/// Spindle on at the start and off at the end. Throws millnet::Error for a blank top ≤ 0 or not
/// below safe_z, a stepover outside (0, D] or an empty rectangle. O(levels · passes).
[[nodiscard]] Operation facing_operation(const tooling::Tool& mill, const FacingSpec& spec);

/// The drill a roughing tool's pre-drilled entries are drilled with: of the library's drills with a
/// diameter in [D/2, D] of the end mill's (the end mill drops into the hole and cuts only the ring
/// the drill left) and a stick-out and flute length that reach `depth_mm` (0 = not stated: taken to
/// reach), the largest, then the shortest. Null when none fits. O(tools).
[[nodiscard]] const tooling::Tool* drill_for(const std::vector<tooling::Tool>& library, const tooling::Tool& mill,
                                             double depth_mm);

/// The tool that reaches `depth_mm` below the stock top: `configured` when its stick-out does (or is
/// not stated), else the library's tool of the same type, diameter, corner radius, flutes and tool
/// material (so that the cutting data stay right) with the shortest stick-out that does. Null when none does (the job then refuses: never a deeper cut
/// than the tool reaches). O(tools).
[[nodiscard]] const tooling::Tool* tool_that_reaches(const std::vector<tooling::Tool>& library,
                                                     const tooling::Tool& configured, double depth_mm);

/// The library's tool of this shape (type, diameter, corner radius) with the longest stated
/// stick-out: what a tool given only by its shape (`--tool-diameter`, `ball:D`, a pocket file's
/// diameter) takes its stick-out, flutes and holder from. Null when the library has none. O(tools).
[[nodiscard]] const tooling::Tool* longest_of_shape(const std::vector<tooling::Tool>& library, tooling::ToolType type,
                                                    double diameter_mm, double corner_radius_mm);

/// The semi-finishing candidates, best first: the library's balls larger than `finisher`, no larger
/// than `rough`, whose stick-out reaches `depth_mm`, the smallest first, then the shortest stick-out.
/// Whether one's flutes take what the roughing leaves is the caller's to measure (its program's
/// axial engagement on the roughed stock: the stock's height over a steep wall is no measure of
/// it). O(tools log tools).
[[nodiscard]] std::vector<const tooling::Tool*> semi_finishing_tools(const std::vector<tooling::Tool>& library,
                                                                     const tooling::Tool& finisher,
                                                                     const tooling::Tool& rough, double depth_mm);

/// The semi-finishing tool (issue 38) when the roughing leaves more than the finishing tool's flutes
/// take: a ball of the library larger than `finisher`, no larger than `rough`, whose flutes take
/// `depth_of_cut_mm` and whose stick-out reaches `depth_mm` (none stated: it reaches); the smallest
/// such (it leaves the least in concave corners), then the shortest stick-out. nullptr: none.
/// O(tools).
[[nodiscard]] const tooling::Tool* semi_finishing_tool(const std::vector<tooling::Tool>& library,
                                                       const tooling::Tool& finisher, const tooling::Tool& rough,
                                                       double depth_of_cut_mm, double depth_mm);

/// The pass distance at which a ball of `radius` leaves cusps of `scallop_mm` between passes on a
/// plane (XY stepover on a flat, step-down on a wall): 2·√(2·r·h − h²), mm.
[[nodiscard]] double scallop_step(double radius, double scallop_mm);

/// Gives every operation's tool without a number (an inline tool: 0) the smallest number above every
/// number in use, the same number for operations sharing that tool; returns the operations renumbered.
[[nodiscard]] std::vector<Operation> numbered(std::vector<Operation> ops);

/// The operations' tools, one per tool number, in the order they are first used. O(ops²): ops are few.
[[nodiscard]] std::vector<tooling::Tool> tools_of(const std::vector<Operation>& ops);

/// The lowest Z any move of `program` goes to (0 when none goes below Z 0). O(items).
[[nodiscard]] double deepest_z(const gcode::Program& program);

/// One operation run alone: `header` as its header, then its tool change, then its items.
[[nodiscard]] gcode::Program operation_program(const Operation& op, std::vector<std::string> header);

/// The part's one program: `header`, then per operation a comment naming it, its tool change and its
/// items. Throws millnet::Error when an operation's tool has no number. O(items).
[[nodiscard]] gcode::Program job_program(const std::vector<Operation>& ops, std::vector<std::string> header);

/// A program split at its tool changes (what the simulator machines tool by tool): per tool change
/// its tool number and the items up to the next one; items before the first tool change (if any)
/// form a run with tool 0. Source lines are kept. O(items).
struct ToolRun {
  int tool_number = 0;
  gcode::Program program;
};
[[nodiscard]] std::vector<ToolRun> split_at_tool_changes(const gcode::Program& program);

/// How a tool's holder clears the part over a program: the holder is a cylinder of the holder's
/// radius from the tool's stick-out above the tip upwards; the part is the design z-map. Measured at
/// every feed move's end (and every `step_mm` along it).
struct HolderClearance {
  bool checked = false;         ///< false: the tool states no stick-out or no holder
  double min_clearance_mm = 0;  ///< smallest gap between the holder's face and the part below it (< 0: collision)
  double deepest_tip_z = 0;     ///< lowest Z the tip reaches (program frame)
  double reach_needed_mm = 0;   ///< how far below the highest part point under the holder the tip goes
  gcode::Point3 worst{};        ///< where the gap is smallest (tip position)
};
/// The check over the design heights `design` (NaN off the part) on `grid`, in the program frame.
/// O(feed moves × length / step + cells × holder disk cells / coarse²): the part is max-pooled to a
/// grid of `coarse_mm` cells first, then dilated by the holder's radius.
[[nodiscard]] HolderClearance holder_clearance(const gcode::Program& program, const tooling::Tool& tool,
                                               const simulate::GridSpec& grid, const std::vector<double>& design,
                                               double coarse_mm = 0.5, double step_mm = 1.0);

}  // namespace millnet::job
