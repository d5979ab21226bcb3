#pragma once
// The five finishing strategies of Korosec & Kopac §3 (the network's output slots 1..5) as real
// cutter-location paths on a part's mesh (ARCHITECTURE.md, finish/). How millnet reads each slot:
//
//   1  profile + Z finishing, slope mode: where the surface under the contact point is shallower
//      than the boundary angle, the raster of 2; where it is steeper, the Z-levels of 4; the two
//      overlap by tol::slope_overlap_deg so that no band between them is left uncut.
//   2  3D finishing, parallel (raster): passes at constant XY stepover p_f, at raster_angle_deg to
//      X, zigzag; points placed adaptively along each pass (chord deviation ≤ chord tolerance).
//   3  profile finishing, scallop-height mode: the raster of 2 whose pass spacing adapts so that
//      the 3D distance between neighbouring passes keeps the ball's scallop ≤ scallop_mm on slopes
//      too (extra passes where the slope across the passes needs them).
//   4  Z-level finishing (waterline): closed contours of constant Z every a_a, where the cutter
//      touches the part; contour points refined with the drop-cutter to the chord tolerance;
//      climb milling (material on the right), top-down per island, fewest lifts.
//   5  profile finishing, equidistant, constant in-feed: passes a constant 3D distance p_f apart
//      on the surface: level sets of the surface distance from the machining boundary, computed
//      by fast marching on the cutter-location height field (speed 1/√(1+|∇z|²)).
//
// Frame: the mesh is prepared (mm, +Z up); the program's Z = mesh z + z_shift (the caller puts
// Z = 0 at the stock top). Every CL point comes from the drop-cutter (the path never goes below
// it); straight feed moves between CL points never dip below the CL surface by more than
// tol::chord_below_mm; links between passes follow the surface (stay down) when short and clear,
// otherwise lift to the highest CL point under the link plus clearance_mm (a "lift").
// Spare slots 6–8 are unnamed: adding a strategy is one function and one registry line
// (finish/src/strategy.cpp).
#include "millnet/core/budget.hpp"
#include "millnet/tooling/cutter.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "millnet/gcode/program.hpp"
#include "millnet/gcode/stats.hpp"

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::finish {

enum class Strategy : int { SlopeMode = 1, Raster = 2, ScallopMode = 3, Waterline = 4, Equidistant = 5 };

/// The CL grids a strategy samples the part on (its work estimate: finish/work.hpp).
/// kScallopSampling: raster passes spaced by the scallop height (strategy 3), not by the stepover.
enum Sampling : unsigned {
  kRasterSampling = 1,
  kWaterlineSampling = 2,
  kEquidistantSampling = 4,
  kScallopSampling = 8
};

/// One strategy of the registry (finish/src/strategy.cpp): a new strategy is its passes function
/// and one entry there; the CLI's choices, the config schema's enum (checked by a test) and the
/// work estimate follow from it.
struct StrategyInfo {
  Strategy id;
  std::string_view name;  ///< the paper's name, without the slot number
  unsigned sampling;      ///< Sampling bits
};
/// The registry, in slot order.
[[nodiscard]] const std::vector<StrategyInfo>& strategy_registry();
/// The accepted values of a strategy choice: the slots ("1".."5") and "all".
[[nodiscard]] std::vector<std::string> strategy_choices();

/// "1".."5"; throws millnet::Error naming the accepted values.
[[nodiscard]] Strategy parse_strategy(std::string_view s);
/// The paper's name of the slot, e.g. "2 3D finishing (parallel)".
[[nodiscard]] std::string strategy_name(Strategy s);
/// All five, in slot order.
[[nodiscard]] std::vector<Strategy> all_strategies();

/// Where the tool may cut (issue 38; docs/finishing.md, "Machining boundaries"). Containment is of
/// the tool axis (its tip's XY) and the tip's height: a pass that leaves is cut where it crosses, on
/// its own straight segment (no new point off the planned path), and resumes where it comes back; a
/// short link between passes stays down only when it stays inside, else it lifts.
struct Boundary {
  /// Closed XY polygons, mesh frame (last point ≠ first; closed implicitly); a point is inside when
  /// an odd number of them enclose it (an outline and the islands within it). Empty: no polygon.
  std::vector<std::vector<Eigen::Vector2d>> polygons;
  /// The axis stays over the part: the XY projection of some face that is not vertical contains it
  /// (the part's silhouette, within tol::on_part_mm). No pass then runs down the outside walls to
  /// the table or drops off an open surface's edge onto the floor.
  bool on_part = true;
  /// A selection of the mesh's triangles (size F; empty: none): the axis stays over the XY
  /// projection of the selected triangles that are not vertical (a CAD part's faces picked by name
  /// or index, issue 38), whatever on_part says.
  std::vector<bool> triangles;
  /// The tip's height, mesh frame: pieces below z_min or above z_max are left out.
  double z_min = -std::numeric_limits<double>::infinity();
  double z_max = std::numeric_limits<double>::infinity();
  [[nodiscard]] bool limits_z() const { return std::isfinite(z_min) || std::isfinite(z_max); }
  /// Whether the polygons enclose (x, y) (even-odd; true when there are none). O(polygon points).
  [[nodiscard]] bool encloses(double x, double y) const;
};

struct FinishParams {
  tooling::Cutter tool = tooling::Cutter::ball(2);
  double stepover_mm = 0.2;           ///< p_f: XY pass distance (2, 1), 3D distance (5), start value (3)
  double step_down_mm = 0.04;         ///< a_a: Z-level step (4, 1)
  double chord_tolerance_mm = 0.005;  ///< CL path vs straight chord, above the surface
  double boundary_angle_deg = 30;     ///< slope mode split
  double scallop_mm = 0.005;          ///< scallop-height mode target
  double raster_angle_deg = 0;        ///< pass direction, degrees from +X
  double feed_mm_min = 1900;
  double plunge_feed_mm_min = 600;
  double spindle_rpm = 18000;
  double safe_z_mm = 5;     ///< program Z of rapids at start and end (above the stock top)
  double clearance_mm = 1;  ///< lifts clear the highest CL point under a link by this
  double z_shift = 0;       ///< program Z = mesh z + z_shift
  /// Rest finishing: the lowest tip height (mesh frame) at which the tool over (x, y) clears the
  /// stock left before it, an upper bound (−infinity where there is none). When set, lifts clear it
  /// as well as the design by clearance_mm, and each entry comes down at rapid to
  /// tol::rest_approach_mm above it (or above the entry, when that is higher) before it plunges.
  std::function<double(double, double)> stock_tip;
  /// With stock_tip: how deep the tool with its tip at (x, y, z) (mesh frame) would cut into that
  /// stock as the program's feed moves so far left it (each reported to `stock_cut`, tips from →
  /// to, as the linking writes it). A stay-down link that would cut deeper than `link_max_cut_mm`
  /// lifts instead (a link must not sink into a corner's rest its passes take a step at a time).
  std::function<double(double, double, double)> stock_engagement;
  std::function<void(const Eigen::Vector3d&, const Eigen::Vector3d&)> stock_cut;
  /// With stock_cut: the most the move from → to (tips) would lower that stock, mm (under
  /// tol::rest_air_cut_mm: it feeds through air). A stay-down link's run of air moves at least
  /// tol::rest_air_hop_radii tool radii long is hopped instead (FinishPlan::hops).
  std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)> stock_cut_depth;
  double link_max_cut_mm = HUGE_VAL;
  /// With stock_tip: the machine's motion, by which a short link that may stay down is timed
  /// against lifting (the planner of gcode::stats over the link's moves, from rest to rest): over a
  /// stock it stays down only when that is the quicker (a link that climbs over a ridge to reach the
  /// next piece is faster lifted than fed up and over it in air). Without a stock short links stay
  /// down as before (the strategies' programs, and the labels learned from them, unchanged).
  gcode::MotionModel motion;
  /// Machining box (XY box of tool-axis positions, mesh frame); empty ⇒ the part's footprint (or
  /// the boundary polygons' box, when they are given).
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  Boundary boundary;         ///< polygons, the part's silhouette, the Z range
  std::string program_name;  ///< first header comment
  /// What the program's tool comment names; empty ⇒ tool.describe(). A caller that plans with a
  /// grown cutter (a ball of R + allowance over the design) names the real tool here.
  std::string tool_label;
  std::vector<std::string> comments;  ///< further header comments (after "strategy: <name>")
  /// Budgets of the CL grids (finish/work.hpp), checked by plan_finish before any point is dropped.
  WorkLimits limits;
  /// Throws millnet::Error naming the parameter (zero stepover, step-down 0, non-finite …).
  void check() const;
};

/// One cutting pass: CL points in the mesh frame, cut in order.
struct Pass {
  std::vector<Eigen::Vector3d> points;
  bool closed = false;  ///< waterline / equidistant loop (last point = first point)
};

struct FinishPlan {
  Strategy strategy = Strategy::Raster;
  std::vector<Pass> passes;   ///< in machining order
  gcode::Program program;     ///< passes linked, in the program frame
  double path_length_mm = 0;  ///< 3D length of feed moves (cuts and stay-down links)
  std::size_t lifts = 0;      ///< links that retract (rapid over, plunge back)
  std::size_t hops = 0;       ///< of the lifts, hops over a stay-down link's air (rest finishing)
  std::size_t cl_points = 0;  ///< CL points in the program
  std::size_t drops = 0;      ///< drop-cutter queries spent
  /// Drop-cutter queries the strategy's path needs, shared pieces included: the same whether it
  /// is planned alone or with others (drops counts only the work this call did for it).
  std::size_t drops_needed = 0;
  double planning_s = 0;  ///< wall time spent planning (timing only, not deterministic)
};

/// The strategy's passes on the part (mesh prepared, the drop-cutter built on it with the tool),
/// linked into a program. Throws millnet::Error on bad parameters or when the cutter is larger
/// than the machining boundary.
[[nodiscard]] FinishPlan plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper, Strategy strategy,
                                     const FinishParams& params);

/// Several strategies on the same part, one plan each in the order given. Pieces that strategies
/// share are computed once: the raster lines of 2 are the shallow runs' source in 1, the Z-level
/// loops of 4 the steep pieces' source in 1, so planning 1, 2 and 4 together costs about what 2
/// and 4 cost. Each plan equals what plan_finish(…, strategy, …) returns alone; its `drops` and
/// `planning_s` count the work done for it (a shared piece is charged to the first plan that
/// needs it).
[[nodiscard]] std::vector<FinishPlan> plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper,
                                                  const std::vector<Strategy>& strategies, const FinishParams& params);

/// Several strategies, each with its own parameters (params[i] for strategies[i], e.g. derived from
/// a surface specification: finish/spec.hpp). They must agree on the tool, the frame, the boundary
/// and the limits (the first one's are used for the part's checks); a shared piece is reused only
/// between strategies whose parameters for it agree. Throws millnet::Error when the counts differ.
[[nodiscard]] std::vector<FinishPlan> plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper,
                                                  const std::vector<Strategy>& strategies,
                                                  const std::vector<FinishParams>& params);

}  // namespace millnet::finish
