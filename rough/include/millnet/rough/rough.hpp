#pragma once
// Roughing a part from its mesh (issue 5): the part sits in a stock block; at each Z level the
// material to remove is a pocket whose islands are the part's cross-sections.
//
//   rough::Params p;  p.cut = …;  p.planner = pocket::SomSpec{…};  p.machining.entry = …;
//   rough::Result r = rough::rough_mesh(prepared_mesh, p);
//   if (r.machining.status == pocket::PlanStatus::Ok) write r.machining.gcode;
//
// Frames: the mesh is prepared (units, up → +Z, footprint lower-left at x = y = 0, lowest point at
// z = 0). The G-code frame keeps X/Y and puts Z = 0 at the stock top: z_gcode = z_part − stock_top.
//
// Levels: from the top down at ≤ step_down, the last at the part's lowest point plus
// floor_allowance_mm; and, with flat_levels, one level per flat area of the part (an upward
// horizontal face: flat_areas) at its height + stock_to_leave + kFlatClearanceMm, unless a level
// already leaves it within kFlatToleranceMm of that, so that a floor between two step-down levels
// keeps the allowance instead of a step (issue 38). A flat level only splits a step: no level cuts
// deeper than step_down, and none cuts air that the ones above it cleared. It clears only the
// regions of its height that hold the flat (the next step-down level clears the others).
//
// Per level z:
//   * islands = outlines of the raster points whose height ≥ z − stock_to_leave (axial allowance),
//     traced by ingest::material_contours, grown outward (never into the part) by
//     contour_tolerance_mm + half a raster diagonal, simplified on the material side. The raster
//     is the cell-max one (ingest::rasterize_top_cells: each point the mesh's highest z over its
//     cell), so every point of the part at or above the level lies within half a diagonal of a
//     raster point that is material: the islands contain the part's section exactly, also on
//     slopes between raster points (the point raster missed up to 0.007 mm there), and reach at
//     most contour_tolerance_mm + one raster diagonal + the contour overshoot beyond it;
//   * the stock region = the stock rectangle grown by twice the tool clearance (R + stock to leave),
//     so that tool centres may pass one clearance outside the stock edge: the disk clears the whole
//     margin down to the part (with only one clearance a margin narrower than the clearance plus
//     the contour growth left the tool no room, and a ring of material stood around the part);
//   * raster points off the part are set below every level's cut-off, so the margin is never
//     taken for material at the bottom level;
//   * holes in the material (cavities) become pockets of their own, with the material inside them
//     as islands (nesting by containment, level_regions);
//   * every region goes to the planner (pocket::plan); levels are machined top-down with safe
//     retracts, one feed map per level (pocket::machine_levels).
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/ingest/zlevels.hpp"
#include "millnet/core/budget.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"

#include <cstddef>
#include <Eigen/Core>

#include <limits>
#include <string>
#include <memory>
#include <vector>

namespace millnet::rough {

struct Params {
  gcode::StockBlock stock{5, std::nullopt,
                          std::nullopt};  ///< the stock block around the footprint (a margin on every side by default)
  double top_allowance_mm = 1;            ///< stock top above the part's highest point
  double raster_mm = 0.25;                ///< height-field raster of the slicing
  double contour_tolerance_mm = 0.05;
  double floor_allowance_mm = 0;  ///< last level this far above the part's lowest point
  /// A level per flat area (flat_areas) between the stock top and the last level; false: the
  /// evenly split levels alone (millnet before 2026-11-27: floors kept up to a step-down).
  bool flat_levels = true;
  /// A flat's level clears every region of its height; false (default): only the regions that hold
  /// the flat (a cavity's floor level does not clear the rest of the part's surround again).
  bool flat_levels_everywhere = false;
  double flat_min_area_mm2 = 1;     ///< smaller flats get no level of their own
  double flat_max_angle_deg = 0.1;  ///< a face this close to horizontal (facing up) is flat
  pocket::CutParams cut;            ///< depth is derived (stock top − last level)
  pocket::PlannerSpec planner;      ///< the planner of every region
  /// Entry and program options; rough_mesh sets contour = false and the header comment.
  pocket::MachiningOptions machining;
  /// Budgets of the slicing raster (ingest::raster_work over the stock) and of every region's plan
  /// (pocket::check_work), checked before each is allocated (issue 12).
  WorkLimits limits;
  /// The stock to rough when it is not the block (issue 38: an earlier job's roughing, a casting):
  /// its top at the slicing raster's points (Result::field's: the footprint + the block's margins
  /// from its lower-left corner, raster_mm apart), part frame. Only what the roughing may take
  /// counts (Result::stock_left); a level clears only where that stands more than kStockSkinMm above
  /// it: its regions are cut to its outline there, grown by the tool's clearance + kStockReachMm (so
  /// that the tool's edge reaches every bit of it), with the margin ring the block's regions have
  /// beyond the block's outline (a stock as full as the block plans the block's levels). Null: the block.
  std::shared_ptr<const ingest::HeightField> stock_top;
};

/// Stock thinner than this above a level is no material for the level (a floor an earlier roughing
/// left at the same height), mm.
inline constexpr double kStockSkinMm = 0.01;
/// The stock's outline at a level is grown by the tool's clearance and this, mm.
inline constexpr double kStockReachMm = 0.5;

/// A flat level sits this far above its flat + stock_to_leave (the slicing's material test is
/// "height ≥ level − stock_to_leave": the flat itself must fall below it), mm.
inline constexpr double kFlatClearanceMm = 0.002;
/// A level this close above a flat's level (and not below it) already keeps its allowance, mm.
inline constexpr double kFlatToleranceMm = 0.01;

/// An upward horizontal area of the part: faces within the angle of horizontal whose heights lie
/// within kFlatZToleranceMm of each other.
struct Flat {
  double z = 0;         ///< its highest point, part frame
  double area_mm2 = 0;  ///< the faces' area (projected on XY)
  /// Where it lies: the centroid and corners of its faces (of at most kFlatSamples faces, spread
  /// over them). A flat's level clears only the regions that hold one of them
  /// (Params::flat_levels_everywhere).
  std::vector<Eigen::Vector2d> samples;
};
inline constexpr std::size_t kFlatSamples = 256;
inline constexpr double kFlatZToleranceMm = 0.005;

/// The part's flats of at least `min_area_mm2`, highest first. O(triangles · log triangles).
[[nodiscard]] std::vector<Flat> flat_areas(const ingest::Mesh& mesh, double max_angle_deg, double min_area_mm2);

struct Level {
  double z_part = 0;  ///< level height in the part frame (mm above the part's lowest point)
  /// A flat's level (flat_levels): the flat's height, part frame; NaN for a step-down level.
  double flat_z_part = std::numeric_limits<double>::quiet_NaN();
  double z = 0;  ///< G-code Z (≤ 0)
  std::vector<pocket::Region> regions;
  std::vector<pocket::PlanResult> plans;
  std::size_t islands = 0;
  std::string status = "ok";  ///< "ok", or why nothing is cut at this level
};

struct Result {
  double stock_top_part = 0;                                      ///< stock top in the part frame
  double stock_x0 = 0, stock_y0 = 0, stock_x1 = 0, stock_y1 = 0;  ///< stock rectangle, mm
  double part_x0 = 0, part_y0 = 0, part_x1 = 0, part_y1 = 0;      ///< the part's footprint inside it, mm
  ingest::HeightField field;                                      ///< the slicing height field (part frame)
  /// With Params::stock_top: the stock the roughing may take — its top, but below every level where
  /// it lies within the stock to leave + kStockSkinMm of the part's top anywhere within the stock to
  /// leave + √2 raster steps + the contour tolerance (what the roughing from the block leaves the
  /// finishing, on floors and along walls: its outline is grown to the raster). Empty otherwise.
  ingest::HeightField stock_left;
  /// With Params::stock_top: per slicing point the part's highest point within that distance (a
  /// level's stock within its island, so grown, is the finishing's, not the roughing's).
  std::vector<double> stock_part_near;
  std::vector<Level> levels;
  pocket::MachiningResult machining;  ///< program over all levels
  double planning_time_s = 0;
  std::size_t tool_points = 0;
};

/// Plans and machines `mesh` (already prepared). Throws millnet::Error on bad parameters.
[[nodiscard]] Result rough_mesh(const ingest::Mesh& mesh, const Params& params);

/// Regions of one level: the stock region (boundary `stock`, every top-level material outline as an
/// island), then one region per material hole (cavity) with the outlines nested in it as islands.
/// `islands` (optional) receives the number of islands over all regions. O(outlines · holes · vertices).
[[nodiscard]] std::vector<pocket::Region> level_regions(const std::vector<ingest::ContourLoop>& loops,
                                                        const pocket::Loop& stock, std::size_t* islands = nullptr);

/// What a report shows of one level: its machined paths (with feeds, program order) and counts.
struct LevelSummary {
  pocket::Path2D path;          ///< the level's machined chains
  std::size_t tool_points = 0;  ///< over the level's regions
  std::size_t chains = 0;       ///< planned chains over the level's regions
  double cut_length_mm = 0;
  double uncut_area_mm2 = 0;  ///< reachable area of the level's regions left uncut
};

/// One summary per level of `r`, in level order.
[[nodiscard]] std::vector<LevelSummary> level_summaries(const Result& r);

}  // namespace millnet::rough
