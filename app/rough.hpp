#pragma once
// Roughing a part from its mesh (issue 5): the part sits in a stock block; at each Z level the
// material to remove is a pocket whose islands are the part's cross-sections.
//
// Frames: the mesh is prepared (units, up → +Z, footprint lower-left at x = y = 0, lowest point at
// z = 0). The G-code frame keeps X/Y and puts Z = 0 at the stock top: z_gcode = z_part − stock_top.
//
// Per level z (from the top down at ≤ step_down; the last level at the part's lowest point plus
// floor_allowance_mm):
//   * islands = outlines of the raster points whose height ≥ z − stock_to_leave (axial allowance),
//     traced by ingest::material_contours, grown outward (never into the part) by
//     contour_tolerance_mm + half a raster diagonal, simplified on the material side;
//   * the stock region = the stock rectangle grown by twice the tool clearance (R + stock to leave),
//     so that tool centres may pass one clearance outside the stock edge: the disk clears the whole
//     margin down to the part (with only one clearance a margin narrower than the clearance plus
//     the contour growth left the tool no room, and a ring of material stood around the part);
//   * raster points off the part are set below every level's cut-off, so the margin is never
//     taken for material at the bottom level;
//   * holes in the material (cavities) become pockets of their own, with the material inside them
//     as islands (nesting by containment);
//   * every region goes to the planner (SOM by default); levels are machined top-down with safe
//     retracts, one feed map per level (pocket::machine_levels).
#include "pocket_job.hpp"

#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/mesh.hpp"

#include <string>
#include <vector>

namespace millnet::app {

struct RoughParams {
  double margin_mm = 5;             ///< stock = footprint rectangle grown by this
  double top_allowance_mm = 1;      ///< stock top above the part's highest point
  double raster_mm = 0.25;          ///< height-field raster of the slicing
  double contour_tolerance_mm = 0.05;
  double floor_allowance_mm = 0;    ///< last level this far above the part's lowest point
  pocket::CutParams cut;            ///< depth is derived (stock top − last level)
  PlannerChoice choice;
};

struct RoughLevel {
  double z_part = 0;   ///< level height in the part frame (mm above the part's lowest point)
  double z = 0;        ///< G-code Z (≤ 0)
  std::vector<pocket::Region> regions;
  std::vector<pocket::PlanResult> plans;
  std::size_t islands = 0;
  std::string status = "ok";   ///< "ok", or why nothing is cut at this level
};

struct RoughResult {
  double stock_top_part = 0;            ///< stock top in the part frame
  double stock_x0 = 0, stock_y0 = 0, stock_x1 = 0, stock_y1 = 0;  ///< stock rectangle, mm
  ingest::HeightField field;            ///< the slicing height field (part frame)
  std::vector<RoughLevel> levels;
  pocket::MachiningResult machining;    ///< program over all levels
  double planning_time_s = 0;
  std::size_t tool_points = 0;
};

/// Plans and machines `mesh` (already prepared). Throws millnet::Error on bad parameters.
[[nodiscard]] RoughResult rough_mesh(const ingest::Mesh& mesh, const RoughParams& params);

/// Writes <stem>.nc, <stem>.metrics.json and <stem>.level_<k>.png (k = 1 = top level) into dir.
/// Returns the metrics JSON.
Json write_rough_outputs(const std::filesystem::path& dir, const std::string& stem, const RoughResult& r,
                         const RoughParams& params);

/// RoughParams from a checked config (rough + pocket sections) and the pocket flags.
[[nodiscard]] RoughParams rough_params(const Json& config, const Json& explicit_pocket, const PocketFlags& flags);

}  // namespace millnet::app
