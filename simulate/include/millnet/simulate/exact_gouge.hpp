#pragma once
// The exact gouge check (issue 37 §1): the real penetration of the swept cutter into the design,
// to confirm or refute what the z-map reports. A z-map cell straddling a vertical wall, a bore, a
// part edge, an open patch's border or an overhang compares a cut height with a design height
// taken at another point of the cell's footprint; the check here compares the cutter with the
// triangles themselves.
//
// The part as a 3-axis machine sees it: everything below its top surface seen from +Z, i.e. the
// union of the prisms below its triangles (a triangle and the vertical strips below its edges,
// down to −∞). For a closed solid this is the solid with its undercuts filled; an open surface
// patch has material below it and none beside it; a vertical wall or a bore's side adds nothing
// (its prism is flat), so a cutter beside a wall whose body stays outside is no gouge.
//
// Penetration of a cutter at one position (tip p, vertical axis, corner radius rc, core radius
// a = R − rc; the cutter solid is the core disk of radius a at height p.z + rc, widened by a
// ball of radius rc, and the shank above it):
//   ball (a = 0): R − distance(centre, part), exact; when the centre is inside the part, R + its
//                 depth below the top surface (vertical);
//   bull, flat:   max over samples q of the core disk (rings at most tol::exact_disk_step_mm
//                 apart, the rim inset by tol::exact_rim_inset_mm) of rc − distance(q, part), or
//                 rc + q's depth below the top surface when q is inside. The disk is sampled:
//                 a feature narrower than the step between samples can be missed (stated bound).
// Along a move (lines; arcs flattened into chords of sagitta ≤ ExactGougeOptions::chord_tol_mm)
// the penetration is 1-Lipschitz in the distance travelled outside the part, so a branch and
// bound on the move's parameter finds its maximum within ExactGougeOptions::resolution_mm
// (intervals whose Lipschitz bound cannot beat max(best + resolution, tolerance) are dropped).
#include "millnet/gcode/program.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/simulate/zmap.hpp"
#include "millnet/tooling/cutter.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace millnet::simulate {

/// The design's triangles in the program frame (z + z_shift) with a uniform XY grid of bins over
/// them, for distance queries against the part solid defined above.
class PartSolid {
public:
  /// O(F · bins per triangle) to build; the bin edge is about twice the mean triangle extent.
  /// Throws millnet::Error for an empty mesh or a face indexing outside V.
  PartSolid(const ingest::Mesh& mesh, double z_shift);

  /// Where a point stands against the part, looking at the triangles whose XY box lies within
  /// `reach` of the point (distances beyond `reach` come back as `reach`).
  struct Probe {
    bool inside = false;         ///< below the top surface of some triangle over its XY
    double distance = 0;         ///< outside: distance to the part (≤ reach); inside: 0
    double depth_below_top = 0;  ///< inside: top surface − z (vertical), else 0
  };
  /// O(triangles in the bins within `reach` of p's XY).
  [[nodiscard]] Probe probe(const gcode::Point3& p, double reach) const;
  [[nodiscard]] std::size_t triangles() const { return tri_.size(); }

private:
  std::vector<std::array<gcode::Point3, 3>> tri_;
  std::vector<std::array<double, 4>> box_;  ///< per triangle: xmin, ymin, xmax, ymax
  /// per triangle: its first bin column and row (a probe visits it in the first of its bins it meets)
  std::vector<std::array<std::uint32_t, 2>> first_bin_;
  double x0_ = 0, y0_ = 0, bin_ = 1;
  std::size_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_;  ///< CSR: bin b holds ids_[start_[b] .. start_[b+1])
  std::vector<std::uint32_t> ids_;
};

struct ExactGougeOptions {
  double tolerance_mm = 0.002;  ///< a penetration beyond this is a gouge
  double chord_tol_mm = 1e-3;   ///< arcs become chords of at most this sagitta
  double resolution_mm = 5e-4;  ///< the maximum along a move is found within this
  std::size_t max_places = 16;  ///< z-map gouge places checked (the deepest, one per move)
  std::size_t neighbours = 1;   ///< moves before and after a place's move also checked
};

/// The deepest penetration of a cutter along some moves.
struct Penetration {
  double depth_mm = -1e300;  ///< max penetration (negative: the clearance); -1e300 when nothing was swept
  gcode::Point3 tip{};       ///< tool tip where it is deepest
  std::size_t item = SIZE_MAX;
  std::size_t line = 0;  ///< 1-based source line when the program has them, else 0
};

/// The penetration of `cutter` at one tip position. O(probe) for a ball; O(disk samples · probe)
/// for flat and bull.
[[nodiscard]] double penetration_at(const PartSolid& part, const tooling::Cutter& cutter, const gcode::Point3& tip);

/// The start point of every item of `program` (the tool's position before it; NaN where unknown),
/// from `start` (NaN axes unknown). O(items).
[[nodiscard]] std::vector<gcode::Point3> item_starts(const gcode::Program& program, const gcode::Point3& start);

/// Deepest penetration of `cutter` swept along the moves `items` of `program` (rapids included),
/// each clipped to the XY disk of radius `window` around (cx, cy) (window ≤ 0: the whole move).
/// `starts` from item_starts. O(evaluations · penetration_at); evaluations per move ≤ its clipped
/// length / (2 · resolution) + 1 and far fewer where the cutter clears the part.
[[nodiscard]] Penetration sweep_penetration(const PartSolid& part, const gcode::Program& program,
                                            const std::vector<gcode::Point3>& starts,
                                            const std::vector<std::size_t>& items, const tooling::Cutter& cutter,
                                            double cx, double cy, double window, const ExactGougeOptions& options);

/// One program of a z-map pass (ZMap pass index = index here) and its cutter.
struct PassTool {
  const gcode::Program* program = nullptr;
  tooling::Cutter cutter;
};

/// The nearest approach of the swept cutters to design points (issue 41: a missed rest confirmed):
/// for each point, the least distance from it to the solid of a pass's cutter at any position along
/// any move of `passes` (rapids included; arcs as chords of sagitta ≤ options.chord_tol_mm), found
/// within options.resolution_mm by a branch and bound on each move near the point (the distance
/// is 1-Lipschitz in the distance travelled); a point no move comes within `reach` of reads `reach`.
/// The cutter solid: a vertical axis from tip t, the core disk of radius a = R − rc at t.z + rc
/// widened by a ball of radius rc (the torus; a ball: a = 0, flat: rc = 0), and its shank of
/// radius R above. A drill's passes are left out (a cone that finishes no surface). Points in
/// parallel, each on its own (any thread count). O(moves · bins each) to bin the moves, then
/// O(points · moves within R + reach of each · evaluations).
[[nodiscard]] std::vector<double> nearest_approach(const std::vector<PassTool>& passes,
                                                   const std::vector<gcode::Point3>& points, double reach,
                                                   const ExactGougeOptions& options);

/// Confirms or refutes the z-map's gouges in `m` (from surface_metrics on `machined`): the gouge
/// cells ((e·cos slope) < −tolerance, some move lowered them) are grouped by the move that cut
/// them; the deepest cell of each of the options.max_places deepest moves is a place, and that
/// move with options.neighbours moves either side is swept exactly within R + 2 cells of it.
/// Work: O(max_places · (2·neighbours + 1) · evaluations per move · penetration_at) + O(cells).
/// Then `m` carries the confirmed figures: max_gouge_mm = the deepest confirmed penetration (or
/// the deepest one found, ≤ tolerance, when none is confirmed), gouged, gouge_move,
/// first_gouge_move and gouge_cell from the exact check; the z-map's own figures move to
/// zmap_max_gouge_mm and the gouge_check counts; pass_max_gouge_mm the same per pass (the z-map's
/// where no place of the pass was checked). Nothing else (gouge_checked = false) when the z-map
/// reports no gouge. A place whose pass has no program in `passes` (null: machined before a saved
/// stock was read back) is left unchecked.
void confirm_gouges(SurfaceMetrics& m, const ZMap& machined, const std::vector<double>& design, const PartSolid& part,
                    const std::vector<PassTool>& passes, const ExactGougeOptions& options);

}  // namespace millnet::simulate
