#pragma once
// Feed adjustment from a feed map (Shin & Suh §6, eq. 9). A fine grid over the pocket (cell =
// CutParams::feed_grid, 0 ⇒ D/10) starts uncut; cells whose centre lies outside the region hold no
// material. As the tool moves along the path in steps of one cell, the cells under its disk become
// cut; the engagement of a step is the number of newly cut cells per cell of travel (steps shorter
// than a cell are pooled until they make one, CutParams::feed_pool_short_steps, so that one
// column of cells on a 0.05 mm step does not read as a slot). For
// each stepover-long piece of the path, n₃ = the largest engagement of its steps and
//     f = f₂ + (f₂ − f₁)/(n₂ − n₁)·(n₃ − n₂),  n₁ = D/grid (slot), n₂ = R/grid (half slot),
// clamped to [f_min, f_max]. A full slot (n₃ = n₁) gets f₁, a half slot f₂. With
// CutParams::max_chip_thinning > 1 (cutting data from the tool library, docs/CUTTING.md) a piece
// engaged less than half (n₃ < n₂) gets f₂·RCTF(a_e) instead, a_e = D·n₃/n₁, the radial
// chip-thinning factor capped at max_chip_thinning, then clamped likewise. A piece none of whose
// steps cuts a cell (a link through cut material) gets CutParams::feed_air where that is set.
#include "millnet/pocket/toolpath.hpp"

#include <vector>

namespace millnet::pocket {

/// Eq. 9 for engagement n3 (cells per step), clamped to [feed_min, feed_max], mm/min.
[[nodiscard]] double feed_for_engagement(double n3, double n1, double n2, const CutParams& cut);

struct FeedPiece {
  std::size_t chain = 0, segment = 0;  ///< the piece is this segment of this chain
  double s_mm = 0;                     ///< cut length along the path at the piece's start
  double length_mm = 0;
  double engagement = 0;   ///< n₃, cells per cell step
  double width_mm = 0;     ///< engaged width ≈ n₃ · grid
  double feed = 0;         ///< mm/min (what Chain::feed holds)
  double mrr_mm3_min = 0;  ///< feed × width × axial depth
  /// The widest cut of the piece from the area newly swept (cells' covered shares, pooled over a
  /// cell of travel), mm: what max_engagement_deg reads; width_mm is the seed's centre count.
  double swept_width_mm = 0;
};

struct FeedProfile {
  double grid_mm = 0, n1 = 0, n2 = 0;
  double axial_depth_mm = 0;
  std::vector<FeedPiece> pieces;
};

/// A disk an entry has already cleared when chain `chain` starts (a helix: its centre, radius
/// rh + R): the feed map marks it cut there instead of the tool's own disk.
struct EntryHole {
  std::size_t chain = 0;
  Vec2 centre = Vec2::Zero();
  double radius_mm = 0;
};

/// Splits segments longer than 1.5 × stepover into equal pieces (geometry unchanged), runs the feed
/// map over the chains in order and fills every Chain::feed (f₂ everywhere when cut.feed_adjust is
/// false, the profile still reported). axial_depth_mm (> 0) only scales the MRR column. `holes`:
/// what entries clear before their chain starts (empty: each chain start marks the tool's disk, a
/// plunge). O(path length / grid · (D/grid)²) plus O(cells · walls) to seed the map.
FeedProfile assign_feeds(Path2D& path, const Region& region, const CutParams& cut, double axial_depth_mm,
                         const std::vector<EntryHole>& holes = {});

}  // namespace millnet::pocket
