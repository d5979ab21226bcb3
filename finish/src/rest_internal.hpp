#pragma once
// Rest machining's internals shared by rest.cpp, rest_stock.cpp and pencil.cpp (not installed).
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/rest.hpp"
#include "millnet/finish/tolerances.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace millnet::finish::detail {

/// A grid of axis positions: node (i, j) at (x0 + j·h, y0 + i·h), row-major.
struct Grid {
  double x0, y0, h;
  int nx, ny;
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  [[nodiscard]] double x(int j) const { return x0 + h * j; }
  [[nodiscard]] double y(int i) const { return y0 + h * i; }
  [[nodiscard]] std::size_t at(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(j);
  }
};

class Fence;

/// Sampled passes (steps ≤ 0.25 mm) cut to the machining boundary (pieces shorter than
/// tol::min_pass_mm dropped), then simplified to the chord tolerance.
[[nodiscard]] std::vector<Pass> clip_passes(const Fence& fence, const std::vector<Pass>& passes,
                                            double chord_tolerance_mm);

/// The plan's program made again from its passes, in their order (linked as every strategy's).
void relink(const ingest::Mesh& mesh, const DropCutter& tool, const FinishParams& p, FinishPlan& plan);

/// Triangle f's unit normal (+Z for a degenerate one or an index out of range).
inline Eigen::Vector3d unit_normal(const ingest::Mesh& mesh, std::ptrdiff_t f) {
  if (f < 0 || f >= mesh.F.rows()) return Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  return n.norm() > 0 ? Eigen::Vector3d(n / n.norm()) : Eigen::Vector3d::UnitZ();
}

/// The design points where the regions measure more than `over_mm` of rest (regions.material along
/// the design's normal; the caller's margin over the threshold), sampled `spacing` apart in XY
/// inside the kept regions (mask 2; a point probe's drop: the design seen from above, as a z-map's
/// cells see it), and which of them the tool has been brought within the threshold of: the test a
/// rest program's result is judged by (job::split_rest: a cell is missed where no program came
/// that near its design point). Nothing when the regions measure nothing or the sampling would
/// pass tol::rest_points_max. O(kept nodes · (cell / spacing)²) drops.
class RestPoints {
public:
  RestPoints(const ingest::Mesh& mesh, const RestRegions& regions, const tooling::Cutter& tool, double spacing,
             double over_mm);
  /// Whether the tool with its tip at `tip` comes within the threshold of a point not yet cleared
  /// (the exact distance to its solid, tooling::Cutter::distance_to_solid). Thread-safe.
  /// O(points within R + threshold in XY).
  [[nodiscard]] bool needed(const Eigen::Vector3d& tip) const;
  /// The points within the threshold of the tool placed every R/16 along `path` cleared.
  void clear_along(const std::vector<Eigen::Vector3d>& path);
  /// The points within the threshold of the tool with its tip at `tip` cleared; how many were not.
  std::size_t clear_at(const Eigen::Vector3d& tip);
  /// How many points not cleared the tool with its tip at `tip` comes within the threshold of.
  [[nodiscard]] std::size_t count_at(const Eigen::Vector3d& tip) const;
  [[nodiscard]] bool is_cleared(std::size_t k) const { return cleared_[k] != 0; }
  /// The points not cleared yet, ascending. O(points).
  [[nodiscard]] std::vector<std::size_t> uncleared() const;
  [[nodiscard]] std::size_t size() const { return points_.size(); }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& points() const { return points_; }
  /// The design's unit normal at each point (its triangle's).
  [[nodiscard]] const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  [[nodiscard]] const tooling::Cutter& tool() const { return tool_; }
  [[nodiscard]] double threshold() const { return threshold_; }

private:
  [[nodiscard]] std::size_t bucket(const Eigen::Vector3d& p) const;
  template <class Visit>
  void near(const Eigen::Vector3d& tip, Visit&& visit) const;
  tooling::Cutter tool_;
  double threshold_, side_, x0_ = 0, y0_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<Eigen::Vector3d> points_, normals_;
  std::vector<std::vector<std::size_t>> buckets_;
  std::vector<std::uint8_t> cleared_;
};

/// How far apart two points are for chaining (`chain_points`), or +∞ when they may not follow each
/// other in a chain.
using Apart = std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)>;

/// Chains points into polylines (single points too): from the point with the fewest neighbours (a
/// chain's end; lowest index on ties), always to the nearest unvisited neighbour, nearest by
/// `apart`; neighbours lie within `link` in XY and by `apart`. O(points · neighbours) with a
/// bucket grid of side `link`. Defined in pencil.cpp (the bitangent points' chains).
[[nodiscard]] std::vector<std::vector<Eigen::Vector3d>> chain_points(const std::vector<Eigen::Vector3d>& pts,
                                                                     double link, const Apart& apart);

/// The pieces of each of `passes` (in their machining order) where the tool removes rest. Each
/// pass is probed along its straight segments (the path the machine follows): a probe
/// cuts when the material at its contact exceeds half the threshold as the regions measure it
/// (regions.material), unless the tool came within that of the contact along the kept pieces of
/// the passes before it (placements every R/8, its profile only): a pass does not cut again what an
/// earlier one cleared. From a stock (regions.from_stock) a probe also cuts where the tool standing
/// there takes more than tol::rest_keep_removal_thresholds thresholds off the stock as the pieces
/// kept before it leave it (RestStock::removal on its cells about R/16 apart, cut by each pass's
/// kept pieces in turn: O((R / cell)²) a probe and a placement): in a crease between two steep
/// faces the contact lies on one face or the other while the rest stands between them. From a
/// stock a probe cuts, too, where the tool comes within the threshold of a design point carrying
/// more than tol::rest_point_thresholds thresholds of rest that the kept pieces before have not
/// come within the threshold of (RestPoints, on the stock's cells): the yardstick the missed rest
/// is judged by, so that the crease's bands between the contacts are cut. The
/// contact is the drop's at the probe's XY, or, for a probe hanging above
/// its drop (beside a vertical wall), the tool's widest point on the side where the drops rise.
/// Probes stand tol::rest_probe_radii · R apart; each cutting probe keeps the stretch within
/// tol::rest_run_on_radii · R (path length) on either side, stretches within
/// tol::rest_bridge_radii · R of each other are joined (also across a closed pass's seam), and each
/// stretch is a piece: its ends interpolated on their segments, the pass's vertices between. Passes
/// in order, a pass's probes in parallel: any thread count. O(length / R) drops, each tested against
/// the O(1) placements near it.
/// With `left`: the design points (from a stock; empty otherwise) as the kept pieces leave them.
[[nodiscard]] std::vector<std::vector<Pass>> trim_to_rest(const std::vector<Pass>& passes, const DropCutter& tool,
                                                          const ingest::Mesh& mesh, const RestRegions& regions,
                                                          std::optional<RestPoints>* left = nullptr);

/// Passes aimed at the points of `points` not cleared yet, where the tool can come within the
/// threshold of them (rest_aim.cpp): each point's nearest placement by a pattern search over the
/// drop-cutter's placements, kept in the points' order where its point is still not cleared and it
/// reaches at least `min_points` points not cleared (it then clears them), chained
/// within tol::rest_aim_link_radii · R and sampled between like any pass (`chord_tolerance_mm`).
/// The points they reach are cleared. Any thread count. Placements outside `allowed` are not kept
/// (the rest program's fence), and a point lower than `lowest_tip` less the threshold is not
/// searched: the tool's solid lies on and above its tip, so no tip `allowed` can come that near it.
/// O(points left · rounds) drops + O(tips · samples between).
[[nodiscard]] std::vector<Pass> aim_at_rest(const ingest::Mesh& mesh, const DropCutter& tool, RestPoints& points,
                                            double chord_tolerance_mm,
                                            const std::function<bool(const Eigen::Vector3d&)>& allowed,
                                            double lowest_tip, std::size_t min_points = tol::rest_aim_min_points);

/// The reference's envelope over the nodes within `reach_mm` of a `near` node (a grid x0 + j·h,
/// y0 + i·h of nx × ny nodes, its drop-cutter tips `ref_cl`): the lowest of its surfaces over each,
/// over all its placements within its radius, plus `add_mm`; +infinity at the other nodes (−infinity
/// where it meets nothing). What it leaves, as a stock whose clearing_tip is +infinity off them.
/// O(nodes near · (R / h)²).
[[nodiscard]] RestStock reference_envelope(const tooling::Cutter& reference, const std::vector<double>& ref_cl,
                                           double x0, double y0, double h, int nx, int ny,
                                           const std::vector<std::uint8_t>& near, double reach_mm, double add_mm);

/// The stretches of `piece` that cut, from the top down (issue 41: cut only where material is
/// left; `removal`: how much the tool with its tip at a point takes off the stock — the most a cell
/// stands above its surface, RestStock::removal — sampled every `sample_mm` along the piece). For
/// Δ = k·depth_mm, k = ⌈h/depth_mm⌉ − 1 … 0 for the most h met (k = 0 only when depth_mm ≤ 0), the
/// highest first: the stretches where the tool would take more than Δ + min_cut_mm (a copy raised
/// by Δ takes h − Δ), run on by `run_on` at both ends (merged where they meet or lie no more than
/// `bridge` apart: the tool stays on the pass rather than leaving it for a link), lifted by Δ, each
/// level's in the piece's order and direction — so that a deep corner's rest is taken a depth at
/// a time before the piece meets the rest of it, and the piece itself runs only where it cuts more
/// than min_cut_mm. A stretch keeps the piece's vertices and interpolates its ends: it lies on or
/// above the piece, which lies on or above the design's drop surface, and cannot gouge. The piece
/// itself, unchanged, when all of it cuts (or when nothing is known of the stock). None when no
/// part of it cuts. `raised`, when given, is set to the number of raised levels (k ≥ 1) that have a
/// stretch. O(samples · copies + points · stretches).
/// `behind`, when given, measures each sample instead of `removal`, on the stock as the piece's
/// samples before it leave it (RestStock::removal_behind): the tool's front takes the rest ahead of
/// it, so the end of a patch is found where the front leaves it, not where the back does (the
/// swept set of a path is the same run either way: the stretches hold whichever way the piece is
/// then cut). O(samples² / piece) distance tests besides.
using OwnSweep = std::function<Removal(const Eigen::Vector3d&, const Eigen::Vector3d*, std::size_t)>;
[[nodiscard]] std::vector<Pass> stepped_runs(const Pass& piece,
                                             const std::function<Removal(double, double, double)>& removal,
                                             double depth_mm, double min_cut_mm, double sample_mm, double run_on,
                                             double bridge = 0.0, int* raised = nullptr, const OwnSweep& behind = {});

/// The passes reordered nearest first from `at` (3D distance; updated to the last pass's end): an
/// open pass may be cut backwards, a loop may start at any vertex; `order` (one entry per pass),
/// when given, is permuted alike. O(passes · points).
[[nodiscard]] std::vector<Pass> order_nearest(std::vector<Pass> passes, Eigen::Vector3d& at,
                                              std::vector<std::size_t>* order = nullptr);

/// The pass not yet `done` nearest `at` (as order_nearest chooses), marked done and moved out,
/// turned to begin at its point nearest `at`; `index`, when given, receives its index. O(points)
/// over the passes left; `passes` must hold one not done.
[[nodiscard]] Pass take_nearest(std::vector<Pass>& passes, std::vector<std::uint8_t>& done, const Eigen::Vector3d& at,
                                std::size_t* index = nullptr);

/// What cut_pieces hands back: the runs in machining order, and how many pieces were stepped down
/// from the top or left out whole.
struct CutPieces {
  std::vector<Pass> passes;
  std::size_t stepped = 0, air = 0;
};

/// The pieces, pencil ones first, each the nearest to where the tool is, cut where they cut on a
/// copy of regions.left machined in order (the stay-down links to them included), stepped down
/// from the top by `depth` where a piece would take more (0: no stepping); as planned when there
/// is no stock or no step. Defined in rest_stock.cpp, where its reasons are.
[[nodiscard]] CutPieces cut_pieces(std::vector<Pass> pencil, std::vector<Pass> rest, const DropCutter& tool,
                                   const RestRegions& regions, const FinishParams& params, double depth,
                                   Eigen::Vector3d from);

}  // namespace millnet::finish::detail
