#pragma once
// Rest machining (issue 41; docs/finishing.md, "Rest finishing"): where a previous, larger tool
// left material in concave corners, a smaller tool finishes only there.
//
// Rest regions from a reference tool (no simulation needed). The part is sampled on a grid of
// tool-axis positions of the NEW tool; at each, the new tool's drop-cutter contact point P (on the
// design) is tested against the reference tool: the material left at P is the distance from P to
// the nearest non-gouging placement of the reference tool (its drop-cutter CL on a grid of the same
// step), measured exactly to the tool's solid (flat bottom, toroidal corner, cylindrical side) —
// the normal thickness, so a wall the reference touches counts 0 however steep it is. Where it
// exceeds threshold_mm the new tool, standing there, would cut rest material: that axis position
// is in a rest region. Regions smaller than min_area_mm2 (slivers) are dropped, the rest grown by
// margin_mm, and the outlines traced (marching squares, CCW outside, CW around holes) into the
// machining boundary of the rest program. Its Z range is capped at the highest rest material in
// reach (the reference's envelope over the design by more than the threshold): a Z-level pass up a
// wall the reference touched cuts nothing, and is left out.
//
// Rest finishing: strategy 1's slope split inside that boundary (Z-levels on the steep pieces,
// raster on the shallow ones), the raster run along the corners: at the rest regions' principal
// direction (their cells' second moments, area-weighted over the regions by doubled angles), so
// that a shallow pass follows the corner instead of crossing it.
//
// Sampling: the reference is placed on grid nodes only, so between nodes its envelope stands up to
// f(step/√2) above a flat floor (ball: step²/(4R)); the automatic step keeps that ≤ threshold/4.
// O(nodes · (R_ref/step)²) distance tests at worst; a node is settled by the first placement that
// comes within the threshold (the nearest are tried first), so flat and touched ground costs a few.
#include "millnet/core/error.hpp"
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/tooling/cutter.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace millnet::finish {

/// What a tool placed over a stock takes off it: `height`, the most a cell stands above the tool's
/// surface (vertical: what the flutes meet); `thickness`, the most a cell's column reaches into the
/// tool's solid normal to its surface (what the scallop specification measures — on a wall it is
/// the height times the cosine of the slope). A removal known by one figure (Removal(h)) takes it
/// for both.
struct Removal {
  double height = 0, thickness = 0;
  Removal() = default;
  Removal(double h) : height(h), thickness(h) {}  // NOLINT(google-explicit-constructor): one figure
  Removal(double h, double t) : height(h), thickness(t) {}
};

/// The stock earlier programs left (rest from the stock, `finish --rest-from`): heights on a grid in
/// the mesh frame, node (i, j) standing for the square cell of side `cell` centred at
/// (x0 + j·cell, y0 + i·cell) — a simulated z-map (simulate::ZMap, shifted by the frame).
struct RestStock {
  double x0 = 0, y0 = 0, cell = 0;
  int nx = 0, ny = 0;
  std::vector<double> z;  ///< row-major, nx·ny heights, mm
  double z_offset = 0;    ///< added to every height (a stock saved in another frame: the program's)
  /// Optional (empty, or nx·ny each): the material measured exactly at the cells' design points —
  /// the programs' nearest approach to the design point under each cell centre, NaN where not
  /// measured — and those points' heights (the grid's frame, like z). A z-map knows a steep wall's
  /// place only to a part of a cell: its reading of the thin stock on an 82–85° wall differs from
  /// the exact one by ~0.02 mm, as much as a rest threshold (s4's job). Where measured, it decides
  /// (material_over).
  std::vector<float> exact_mm;
  std::vector<double> exact_z;
  /// Throws millnet::Error when the grid is empty, the step not > 0, a height not finite, or the
  /// exact measures are not one per cell.
  void check() const;
  /// The stock's height over (x, y): bilinear between the cells' centres; −infinity off the grid.
  [[nodiscard]] double height(double x, double y) const;
  /// The material over a design point p with unit normal n (pointing out of the part): how far
  /// from p along n the stock ends (its height below the point), found by doubling steps from a
  /// quarter cell and bisection, at most 64 cells; 0 when p is not under the stock. On a floor it
  /// is the stock's height over p, on a wall the stock's thickness beside it, less half a cell
  /// times the normal's horizontal part (where a wall stands within its columns is known to half a
  /// cell: a wall the stock is flush with would otherwise read up to a cell thick). O(log) heights.
  /// Where the nearest cell has an exact measure (exact_mm) and its design point lies on p's
  /// tangent plane within half a cell (the same surface), that measure instead. O(1).
  [[nodiscard]] double material(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
  /// material(p, n) where that exceeds floor_mm, else a value in [0, floor_mm] (the search stops as
  /// soon as the answer cannot exceed it: a test against a threshold costs ~2 heights, not ~18).
  [[nodiscard]] double material_over(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double floor_mm) const;
  /// The lowest tip height at which `tool` with its axis over (x, y) clears the stock: the highest
  /// of the cells within its reach less the tool's profile there, each cell taken at its corner
  /// nearest the axis (conservative). −infinity when no cell is within reach. O((R / cell)²).
  [[nodiscard]] double clearing_tip(const tooling::Cutter& tool, double x, double y) const;
  /// How deep `tool` with its tip at (x, y, tip) cuts: the most a cell within its radius stands
  /// above the tip where it stands above the tool's profile there (cells at their centres, cells
  /// not finite skipped; 0 when it cuts nothing). The simulation's axial engagement, on this
  /// stock. O((R / cell)²).
  [[nodiscard]] double engagement(const tooling::Cutter& tool, double x, double y, double tip) const;
  /// How much `tool` with its tip at (x, y, tip) takes off: the most a cell within its radius
  /// stands above the tool's surface over it, and the most its column reaches into the tool normal
  /// to the surface (Removal; cells at their centres, cells not finite skipped; 0 when it cuts
  /// nothing). Not the engagement: a cell grazed at the ball's rim is cut by a hair however high on
  /// the flutes. O((R / cell)²).
  [[nodiscard]] Removal removal(const tooling::Cutter& tool, double x, double y, double tip) const;
  /// removal() on the stock as `tool` leaves it placed at the tips before[0 … n) first (the
  /// samples of the same piece before this one): each cell within its radius taken at the lowest of
  /// its height and those placements' surfaces over it — what the tool takes that its own path has
  /// not already taken. Placements farther than 2R in XY are skipped. O((R / cell)² · n).
  [[nodiscard]] Removal removal_behind(const tooling::Cutter& tool, const Eigen::Vector3d& tip,
                                       const Eigen::Vector3d* before, std::size_t n) const;
  /// `tool` swept from a to b (tips, the grid's frame less z_offset): every cell within its radius
  /// lowered to the tool's surface over it, sampled every half cell along the segment.
  /// O(length / cell · (R / cell)²).
  void cut(const tooling::Cutter& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b);
  /// The most cut() from a to b would lower any cell (0 when it cuts nothing), the stock kept.
  /// O(length / cell · (R / cell)²).
  [[nodiscard]] double cut_depth(const tooling::Cutter& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
};

struct RestParams {
  /// The tool that machined before (rest from a reference tool; not used with `stock`).
  tooling::Cutter reference = tooling::Cutter::ball(6);
  /// Rest from the stock instead (not owned; outlives the call): where the material the earlier
  /// programs really left over the new tool's contact exceeds the threshold.
  const RestStock* stock = nullptr;
  double threshold_mm = 0.02;  ///< material thicker than this (normal to the design) is rest
  double margin_mm = -1;       ///< regions grown by this; < 0 ⇒ the new tool's radius / 2
  double min_area_mm2 = -1;    ///< regions smaller than this (axis area) dropped; < 0 ⇒ π r_new² / 4
  double cell_mm = 0;          ///< grid step; 0 ⇒ automatic (see above), at most 0.25 mm
  /// The mask, thickness, areas and material model only: no ceilings (RestRegion::z_max stays
  /// −∞) and no outlines (what unreachable_regions' callers need; the ceilings cost most of it).
  bool mask_only = false;
  /// Throws millnet::Error naming the parameter.
  void check() const;
};

/// The grid step the automatic rule gives for a reference tool and a threshold: the largest step
/// whose between-node envelope f(step/√2) stays ≤ threshold/4, within [0.02, 0.25] mm.
[[nodiscard]] double rest_cell_mm(const tooling::Cutter& reference, double threshold_mm);

/// The material a reference tool at tip height `tip` over (cx, cy) leaves above a point p: the
/// Euclidean distance from p to the tool's solid (0 when p is inside it). Exact for flat, bull and
/// ball (the solid: the profile of tooling::Cutter revolved, a cylinder above it).
[[nodiscard]] double distance_to_tool(const tooling::Cutter& tool, double cx, double cy, double tip,
                                      const Eigen::Vector3d& p);

/// One rest region (a 4-connected component of the grown axis nodes).
struct RestRegion {
  Boundary boundary;  ///< its outline; z_min/z_max: its tips' lowest CL, its rest's top
  double z_min = std::numeric_limits<double>::infinity();   ///< the new tool's lowest tip over it
  double z_max = -std::numeric_limits<double>::infinity();  ///< its highest rest (−inf: none in reach)
  double rest_axis_area_mm2 = 0;                            ///< its axis nodes that cut rest (before the growth)
  double axis_deg = 0;                                      ///< its principal direction, degrees from +X, in [0, 180)
};

struct RestRegions {
  double x0 = 0, y0 = 0, cell = 0;  ///< node (i, j) at (x0 + j·cell, y0 + i·cell)
  double threshold_mm = 0.02;       ///< the parameters' threshold
  int nx = 0, ny = 0;
  /// Per node (row-major): 1 where the new tool's contact point has rest material (before the
  /// slivers are dropped and the regions grown); 2 where it is in a kept region after the growth.
  std::vector<std::uint8_t> mask;
  /// Per node: the material at the new tool's contact point, mm (0 where settled below the
  /// threshold, the exact distance above it; NaN where the new tool touches nothing).
  std::vector<float> thickness;
  Boundary boundary;              ///< the outlines of the kept, grown regions (polygons, on the part)
  std::vector<RestRegion> parts;  ///< the grown regions one by one (margins may join kept ones)
  std::size_t regions = 0;        ///< kept regions (4-connected components of the rest nodes)
  std::size_t slivers = 0;        ///< components dropped for their size
  double rest_axis_area_mm2 = 0;  ///< XY area of the new tool's axis positions that cut rest (kept)
  double max_thickness_mm = 0;    ///< the largest rest found
  double axis_deg = 0;            ///< the regions' principal direction, degrees from +X, in [0, 180)
  /// The highest rest material (mesh z) within the new tool's reach of the regions (the highest of
  /// the parts' z_max): the boundary's z_max. −infinity when there is no rest.
  double rest_top_z = -std::numeric_limits<double>::infinity();
  /// The material over a design point (p, the design's unit normal there), measured
  /// as the regions were found: behind the reference's placements, or under the stock (which must
  /// outlive this). plan_rest keeps only the pieces of passes that cut it. Thread-safe.
  std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)> material;
  /// The lowest tip height at which the new tool over (x, y) clears what was left (an upper bound):
  /// the stock's (RestStock::clearing_tip), or the reference's drop-cutter tip there raised by the
  /// most the reference's profile rises above the new tool's within the new tool's radius (0 for a
  /// smaller ball: it lies inside the reference on the same tip) plus the threshold (the
  /// reference's cusps). plan_rest's links and entries use it. Thread-safe.
  std::function<double(double, double)> stock_tip;
  /// What was left as heights: the stock (not owned: it must outlive this), or the reference's
  /// envelope near the regions (+infinity elsewhere). plan_rest machines its pieces into a copy, in
  /// order, to know how deep each cuts (RestStock::engagement) and steps a piece that would cut
  /// deeper than half the tool's flutes down from the top.
  std::shared_ptr<const RestStock> left;
  /// `left` is a simulated stock (rest_regions' `stock`), not a reference's envelope.
  bool from_stock = false;
  [[nodiscard]] bool empty() const { return boundary.polygons.empty(); }
};

/// The regions against a floor (mesh z; e.g. the stock top less a tool's stick-out): how many go
/// below it (their lowest tip), how many have rest above it, and the lowest tip of those below.
struct RestAgainstFloor {
  std::size_t deeper = 0, within = 0;
  double lowest_z = std::numeric_limits<double>::infinity();
};
[[nodiscard]] RestAgainstFloor against_floor(const RestRegions& regions, double floor_z);

/// The rest regions of the new tool (its drop-cutter `new_tool`) behind `params.reference` over the
/// box [x0, x1] × [y0, y1] (mesh frame; empty box ⇒ the part's footprint). Throws millnet::Error for
/// bad parameters or a reference tool smaller than the new one in radius (it would leave nothing
/// the new one can take).
[[nodiscard]] RestRegions rest_regions(const ingest::Mesh& mesh, const DropCutter& new_tool, const RestParams& params,
                                       double x0 = 0, double y0 = 0, double x1 = 0, double y1 = 0);

/// Pencil tracing: the bitangent positions of the tool along concave edges, as passes. On a grid of
/// axis positions (step `cell_mm`; within `mask` when given: nodes ≠ 0 of a grid of the same origin
/// and step), a grid edge whose two drop-cutter contacts lie farther apart than max(6·cell, 0.5·R)
/// crosses a concave edge (the contact jumps from one surface to the other; over a convex edge it
/// stays on the edge); the crossing is found by bisection of real drops to 1e-5 mm, its tip the
/// lower of the two sides (the bitangent position itself, where the tool touches both). The points
/// are chained into polylines (neighbours within 2·√2·cell, from the chain ends) and sampled between
/// them like any pass (steps ≤ 0.25 mm, no chord below the drop-cutter by more than
/// tol::chord_below_mm): the caller cuts them to its boundary, then simplifies. O(nodes) drops + O(edges crossed · 17) drops + the sampling.
/// Multi-pencil (`offsets` > 0): beside each chain, `offsets` passes on each side at k·`spacing`
/// (k = offsets … 1) in XY from it (each vertex moved along the chain's XY normal there, the mean of
/// its segments' normals), the tool dropped along them like the chain: per chain the passes of one
/// side from the outermost in, then the other side's, then the bitangent pass itself, so that the
/// corner is cut last, with the least material left in it. (2·offsets + 1)× the sampling.
[[nodiscard]] std::vector<Pass> pencil_passes(const ingest::Mesh& mesh, const DropCutter& tool, double x0, double y0,
                                              double x1, double y1, double cell_mm, double chord_tolerance_mm,
                                              const std::vector<std::uint8_t>* mask = nullptr, int offsets = 0,
                                              double spacing = 0);

/// Pencil tracing alone over the box (params' box, else the part's footprint), grid step
/// min(0.1, R/4): the passes linked into a program like a strategy's (the header names pencil
/// tracing). `offsets` > 0: multi-pencil, that many passes each side params.stepover_mm apart
/// (pencil_passes). Throws millnet::Error when the part has no concave edge for the tool, or for
/// offsets outside 0…50.
[[nodiscard]] FinishPlan plan_pencil(const ingest::Mesh& mesh, const DropCutter& tool, FinishParams params,
                                     int offsets = 0);

/// Rest finishing inside `regions` with the new tool (params.tool, whose drop-cutter is `new_tool`):
/// the pencil passes of the regions first, then strategy 1 in each region with its outline as the
/// machining boundary, its Z range (from a step-down below its lowest tip to its rest's top, within
/// params.boundary's; on_part kept) and its raster along its principal direction; a region narrower
/// than the tool gets its pencil passes only. The passes, nearest first, are each cut to the pieces
/// where the tool removes rest that the regions measure and the pieces before it left (over half
/// the threshold at its contact, or from a stock where the tool there takes 1.5 thresholds off
/// what the pieces before left or comes within the threshold of a design point with rest over
/// it that they did not come that near; detail::trim_to_rest), run on by R/32 at
/// both ends
/// (tol::rest_run_on_radii). From a stock, passes aimed at the design points with rest that no
/// piece came near, where the tool reaches them inside the regions' fence, join them
/// (detail::aim_at_rest). The pieces are ordered nearest first again. Over what was left as
/// heights (regions.left) with the flutes known, each piece is cut again, from the top down, to
/// where it takes more than the scallop off the stock its own samples and the pieces before it
/// leave (detail::stepped_runs, no run-on), the stay-down links to them cut into it first. All
/// linked into one program whose links clear
/// regions.stock_tip and whose entries come down to tol::rest_approach_mm above it. The program's header names it
/// rest finishing and the reference tool. Throws millnet::Error when the regions are empty,
/// NoRestToCut when no pass removes rest.
/// `behind` names what left the rest ("ball D6", "the stock of FILE") in the header and errors.
/// plan_rest's error when the regions hold rest but no pass of the new tool removes any of it and
/// no concave edge is there to trace: a job leaves the rest operation out with a note.
class NoRestToCut : public Error {
public:
  using Error::Error;
};

[[nodiscard]] FinishPlan plan_rest(const ingest::Mesh& mesh, const DropCutter& new_tool, const RestRegions& regions,
                                   const std::string& behind, FinishParams params);

/// The XY area (mm²) of the design that `tool` cannot come within `threshold_mm` of without
/// gouging elsewhere: the rest regions of a point-like probe (a ball of Ø0.01 mm) behind `tool`,
/// with no margin and no sliver dropped, over the part's footprint (grid step rest_cell_mm). What a
/// rest program with `tool` must leave at worst: the yardstick of `simulate`'s rest figures.
[[nodiscard]] double unreachable_area_mm2(const ingest::Mesh& mesh, const tooling::Cutter& tool, double threshold_mm);
/// The same, as regions: mask 1 where `tool` cannot reach the design point under the node
/// (RestParams::mask_only: no ceilings, no outlines).
[[nodiscard]] RestRegions unreachable_regions(const ingest::Mesh& mesh, const tooling::Cutter& tool,
                                              double threshold_mm);

}  // namespace millnet::finish
