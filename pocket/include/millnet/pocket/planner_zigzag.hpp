#pragma once
// The zigzag planner (direction-parallel rough cut) with T- or I-partition: the baseline next to the
// SOM planner, same PlanResult contract (pocket/planner.hpp).
//
// Example (the CLI's `--planner zigzag --partition i --angle auto`):
//   ZigzagParams zp;  zp.partition = PartitionKind::I;  zp.angle_deg = std::nullopt;  // auto
//   PlanResult r = plan_zigzag(region, cut, zp);
//   if (r.status != PlanStatus::Ok) { … r.message … }
#include "millnet/pocket/cut_links.hpp"
#include "millnet/pocket/partition.hpp"
#include "millnet/pocket/planner.hpp"
#include "millnet/pocket/planner_registry.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::pocket {

struct ZigzagParams {
  /// Reference (pass) direction in degrees from +x, counter-clockwise; nullopt = search.
  std::optional<double> angle_deg = 0.0;
  PartitionKind partition = PartitionKind::T;
  double angle_step_deg = 5;  ///< search grid; the pocket's straight-edge directions are added
  /// Search cost per pass (a turn: the machine stops and starts), mm of path; < 0 ⇒ one stepover.
  /// Direction cost = cut + rapid length + turn_penalty_mm · passes, after the fewest regions.
  double turn_penalty_mm = -1;
  /// After each region, go on with the tool down to the region (any of those left, from any of its
  /// corners) that a way through cut material reaches with the shortest link (pocket/cut_links.hpp:
  /// the tool's disk along it within the area already swept, the last move also through what that
  /// region's first pass and the contour pass cut anyway, ≤ kLinkSliverMm2 of slivers; exact
  /// Clipper check). Saves the retraction and the entry (a helix or ramp into uncut material costs
  /// ≈ 0.4 min at 300 mm/min and 3°, 5 mm deep). Where no region is reachable, the next of the
  /// planned order is entered anew.
  bool link_regions = true;
};

/// One evaluated direction (for reports and tests).
struct AngleScore {
  double angle_deg = 0;
  int regions = 0;
  double length_mm = 0;  ///< cut + rapid length of the zigzag (no contour)
  std::size_t passes = 0;
};

/// Plans a zigzag rough cut of `region` (validated and normalized: boundary CCW, islands CW, mm).
/// The tool centre stays in offset_inward(region, cut.clearance()) (Clipper, arcs within
/// tol::arc_chord_mm). Chains are in machining order in world coordinates, feeds unassigned.
/// PlanResult::planner = "zigzag-t" | "zigzag-i"; predrill = the entry of every zigzag chain;
/// stats: ZigzagStats of the chosen direction (none when the tool fits nowhere).
/// Throws millnet::Error for stepover ∉ (0, tool diameter] or a non-positive tool diameter.
/// Status NoToolPoints (empty path, message) when the tool fits nowhere.
[[nodiscard]] PlanResult plan_zigzag(const Region& region, const CutParams& cut, const ZigzagParams& params,
                                     std::vector<AngleScore>* scores = nullptr);

/// Candidate directions of the search: every `step_deg` in [0, 180) plus the direction (mod 180) of
/// every straight edge of the region, sorted and de-duplicated (1e-6°).
[[nodiscard]] std::vector<double> candidate_angles(const Region& region, double step_deg);

/// The zigzag planner with T- or I-partition.
struct ZigzagSpec {
  static constexpr std::string_view kPlanner = "zigzag";
  ZigzagParams zigzag;
};

/// A zigzag angle as text: degrees in [-360, 360], or "auto" (nullopt: searched). Throws
/// millnet::Error naming `where` (a flag or a JSON pointer) otherwise.
[[nodiscard]] std::optional<double> parse_zigzag_angle(const std::string& text, const std::string& where);

/// The registry's entry (planner_registry.hpp): settings /pocket/zigzag; `millnet compare` runs it
/// twice, T- and I-partition, the angle searched unless --angle says.
[[nodiscard]] PlannerEntry zigzag_planner();

}  // namespace millnet::pocket
