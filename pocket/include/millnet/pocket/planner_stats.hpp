#pragma once
// Typed figures per planner (PlanResult::stats). A reader names a field, so a renamed figure is a
// compile error, not a silent 0. key_values() lists them for the metrics files, sorted by key (the
// order those files have had since the figures lived in a std::map).
#include "millnet/pocket/smoothing.hpp"

#include <cstddef>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace millnet::pocket {

/// The SOM planner's figures (plan_som).
struct SomStats {
  std::size_t tool_points = 0;
  int som_passes = 0;
  bool som_converged = false;
  std::size_t som_nodes = 0;
  SmoothingStats smoothing;         ///< smooth_tour's figures
  double cut_length_mm = 0;         ///< of the planned path (links included)
  double rapid_length_mm = 0;       ///< of the planned path (the smoothing's own figure is replaced)
  std::size_t retractions = 0;      ///< of the planned path (the smoothing's own figure is replaced)
  std::size_t predrill_points = 0;  ///< chain starts
  double grid_bound_mm = 0;         ///< (N − 1)·g, the shortest conceivable tour through N points
  double cut_over_bound = 0;        ///< cut_length_mm / grid_bound_mm (1 when the bound is 0)
  std::size_t wall_rings = 0;       ///< wall rings cut (SomPathParams::walls)
  std::size_t wall_ring_links = 0;  ///< of those, spliced into a chain with the tool down
  std::size_t corner_arcs = 0;      ///< corners blended by arcs (SomPathParams::blend_corners)

  /// Its own figures and the smoothing's (its own win on a shared key), sorted by key.
  [[nodiscard]] std::vector<std::pair<std::string, double>> key_values() const;
};

/// The zigzag planner's figures (plan_zigzag), for the chosen direction.
struct ZigzagStats {
  int regions = 0;          ///< zigzag chains = partition faces cut
  std::size_t faces = 0;    ///< partition faces
  std::size_t srps = 0;     ///< split reference points
  int nls = 0;              ///< NLS cuts kept (I-partition)
  int islands = 0;          ///< holes of the reachable area
  int components = 0;       ///< components of the reachable area
  int formula_regions = 0;  ///< n_s − n_i + n_c − nls
  std::size_t passes = 0;
  double angle_deg = 0;
  std::size_t angles_tried = 0;
  int nonmonotone_faces = 0;
  std::size_t region_links = 0;  ///< regions joined to the one before with the tool down (link_regions)
  double zigzag_cut_length_mm = 0;
  double zigzag_rapid_length_mm = 0;

  /// Sorted by key; with "contours" = 0 (the contour pass is machine_pocket's; the key stays in the
  /// metrics files).
  [[nodiscard]] std::vector<std::pair<std::string, double>> key_values() const;
};

/// The offset planner's figures (plan_offset).
struct OffsetStats {
  std::size_t rings = 0;        ///< loops cut (all offsets, walls included)
  std::size_t offsets = 0;      ///< offset distances with something left (K)
  std::size_t nodes = 0;        ///< connected components over all offsets
  std::size_t components = 0;   ///< components of the reachable area (roots)
  std::size_t splits = 0;       ///< nodes with more than one child (where the offsets split)
  std::size_t links = 0;        ///< ring-to-ring moves with the tool down
  std::size_t retractions = 0;  ///< of the planned path
  std::size_t arcs = 0;         ///< G2/G3 arcs fitted to the chorded rings (arc_fit.hpp)
  double cut_length_mm = 0;     ///< of the planned path (links included)
  double rapid_length_mm = 0;
  [[nodiscard]] std::vector<std::pair<std::string, double>> key_values() const;
};

/// The adaptive planner's figures (plan_adaptive).
struct AdaptiveStats {
  double target_deg = 0;                  ///< the engagement the planner kept to
  std::size_t components = 0;             ///< components of the tool centres' raster
  std::size_t entries = 0;                ///< helix entries (one per component)
  std::size_t entries_without_helix = 0;  ///< entries where no helix fits (a ramp or plunge)
  std::size_t reentries = 0;              ///< retractions to a cleared start no link reached
  std::size_t wall_retractions = 0;       ///< wall loops no link reached
  std::size_t passes = 0;                 ///< constant-engagement passes
  std::size_t idle_passes = 0;            ///< of them, passes that cut (almost) nothing: a stop wasted
  std::size_t links = 0;                  ///< pass-to-pass moves with the tool down
  double ride_length_mm = 0;              ///< rides back along fronts (tool down, cutting nothing)
  double link_length_mm = 0;              ///< links to the next pass's start through cut area
  double backtrack_length_mm = 0;         ///< retraced path before a link
  std::size_t steps = 0;                  ///< planning steps
  std::size_t vertices = 0;               ///< of the simplified path
  std::size_t retractions = 0;            ///< of the planned path
  double cut_length_mm = 0;               ///< of the planned path (links included)
  double rapid_length_mm = 0;
  double uncut_target_mm2 = 0;  ///< raster estimate of the target left after the wall pass
  [[nodiscard]] std::vector<std::pair<std::string, double>> key_values() const;
};

/// One alternative per planner; std::monostate when the planner stopped before planning (status
/// NoToolPoints) and has no figures.
using PlannerStats = std::variant<std::monostate, SomStats, ZigzagStats, OffsetStats, AdaptiveStats>;

/// The figures of whichever planner, as SomStats/ZigzagStats::key_values; none for std::monostate.
[[nodiscard]] std::vector<std::pair<std::string, double>> key_values(const PlannerStats& stats);

}  // namespace millnet::pocket
