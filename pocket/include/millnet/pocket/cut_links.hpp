#pragma once
// Tool-down links through material already cut (issue 11): the way from where one chain ends to
// where the next begins, at the cutting depth, cutting nothing the operation would not cut anyway,
// so that the tool needs no retraction and no entry (a helix into solid material costs ≈ 0.4 min
// at 300 mm/min).
//
//   raster  the area swept so far is a raster of cells (a cell is cut when its centre lies within R
//           of a tool centre: the feed map's rule). A position is clear when no uncut material
//           cell lies within R − cell of it, the disk at the link's start counted as cut (the tool
//           stands there).
//   search  one Dijkstra from the start over a lattice of clear positions that keep the walls'
//           clearance plus kLatticeMarginMm (8-neighbour moves) serves every target. The last move
//           into a target may also cut what the target's approach sweeps anyway: its disk, the
//           first kApproachDiameters·D of the chain it starts (that chain's first pass) and, within
//           D + R of it, the wall band the contour pass sweeps (a corner of the pocket beside the
//           target), as a zigzag's step along a wall from one pass to the next does. Candidates
//           (target, last lattice position) are tried cheapest first (lattice length + the
//           target's extra cost); the way is pulled taut, every straight move wall-checked exactly
//           (Clearance::move_ok) and clear at every cell step.
//   check   a way is accepted only where the exact swept area (Clipper) of its moves cuts at most
//           max_new_mm2 outside the swept area of every polyline marked so far, the start's disk and
//           the target's approach (the wall band near it: the disk of radius D + R round the target
//           minus the region offset inward by clearance + R): the raster finds the way, the
//           booleans vouch for it.
//
// Deterministic (no threads). Cost of a query: O(cells) for the distance transform + O(lattice log
// lattice) for the search + the candidates tried (at most kMaxCandidates) + the booleans of what
// was swept near the way.
#include "millnet/pocket/toolpath.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace millnet::pocket {

/// How far along the next chain its approach reaches, in tool diameters.
inline constexpr double kApproachDiameters = 1.0;

struct LinkTarget {
  Vec2 b;                      ///< where the next chain starts
  std::vector<Vec2> approach;  ///< that chain's first moves (b first), ≤ kApproachDiameters·D long
  double extra = 0;            ///< added to the link's length when targets are compared, mm
};

/// Uncut area a link may cut outside what its rules allow (slivers between passes the raster
/// cannot see), mm².
inline constexpr double kLinkSliverMm2 = 1.0;

/// The first kApproachDiameters·D of a polyline (its start first).
[[nodiscard]] std::vector<Vec2> approach_of(const std::vector<Vec2>& chain, double tool_diameter);

class CutLinker {
public:
  /// `region` validated and normalized; the tool's clearance is cut.clearance(). max_new_mm2: the
  /// uncut area a link may cut outside its rules (kLinkSliverMm2). cell_mm: the raster cell, 0 ⇒ D/40
  /// (doubled, up to D/5, while the raster would pass 1.6·10⁷ cells: a pocket over 1 × 1 m at Ø10).
  /// Throws millnet::Error when the raster would exceed 4·10⁷ cells.
  CutLinker(const Region& region, const CutParams& cut, double max_new_mm2, double cell_mm = 0);
  ~CutLinker();
  CutLinker(CutLinker&&) noexcept;
  CutLinker& operator=(CutLinker&&) noexcept;

  /// Marks what the tool's disk sweeps along the tool-centre polyline as cut (a single point: its
  /// disk). O(length · R / cell²).
  void sweep(const std::vector<Vec2>& polyline);
  /// The same for a chain (arcs flattened within tol::arc_chord_mm).
  void sweep(const Chain& chain);

  /// The cheapest way from a to one of the targets (a first, its b last; {a, b} where the straight
  /// move does): the target's index and the way, or nothing when no target is reachable.
  struct Link {
    std::size_t target = 0;
    std::vector<Vec2> way;
  };
  [[nodiscard]] std::optional<Link> best_link(const Vec2& a, const std::vector<LinkTarget>& targets) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace millnet::pocket
