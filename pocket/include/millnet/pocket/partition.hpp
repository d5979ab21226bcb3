#pragma once
// Region partitions for zigzag machining (Tang et al. 1998 "T-partition"; Suh & Kim 2001
// "I-partition"). Everything here works in the SCAN FRAME: the reachable area has been rotated so
// that the scan lines (zigzag passes) are horizontal, y is the direction normal to the passes.
//
//   * SRP (scan-reflex point): a local extremum in y of a reachable-area loop where the area lies on
//     both sides of the scan line through it (two scan-line segments meet there). Flat tops/bottoms
//     (horizontal edges) and Clipper's flattened arcs are merged into one SRP by a hysteresis of
//     tol::srp_flat_mm.
//   * Seed naming, mapped to this frame (the seed's normal axis "x" is our y): an R-SRP bulges toward
//     +y (a local maximum: an island's top, the tip of a wall prong pointing up); an L-SRP bulges
//     toward −y (a local minimum: an island's bottom, the floor of a notch between comb prongs).
//   * T-partition: one cut per SRP, along the scan line from the SRP toward −x (the seed's "lower
//     SLS") up to the first wall or cut. Faces: n_s − n_i + n_c (n_c connected components; the seed's
//     n_s − n_i + 1 per component). Every face is y-monotone: a scan line meets it in ≤ 1 interval.
//   * I-partition: pairs (R-SRP p, L-SRP q) with q above p are joined by one cut made of a normal line
//     segment (NLS, along y) and a scan-line part, replacing the two T-cuts; faces n_T − n_n.
//     Pairs are proposed in the seed's §4 order and each is kept only when the partition actually
//     built loses exactly one face and stays y-monotone.
// Faces are built for real: the cuts become slits of half-width tol::slit_half_mm that Clipper
// subtracts from the area, so every face is a polygon we can count, scan and walk.
#include "millnet/pocket/geometry.hpp"

#include <utility>
#include <vector>

namespace millnet::pocket {

namespace tol {
inline constexpr double srp_flat_mm = 1e-3;    ///< y-wiggles smaller than this do not make extrema
inline constexpr double slit_half_mm = 2e-4;   ///< half-width of the slits that realise cuts
inline constexpr double scan_clear_mm = 2e-3;  ///< passes keep this far from SRP heights (slits)
}  // namespace tol

enum class SrpKind { L, R };  ///< L: local minimum in y (bulges to −y); R: local maximum
enum class PartitionKind { T, I };

struct Srp {
  Vec2 p;                 ///< extreme vertex (scan frame); its cut starts here
  double span_x_min = 0;  ///< x-extent of the flat top/bottom at height p.y()
  double span_x_max = 0;
  SrpKind kind = SrpKind::L;
  int component = 0;   ///< index of the PolyArea
  int loop = 0;        ///< 0 = outer loop, k ≥ 1 = hole k − 1
  bool reflex = true;  ///< false only for the convex extrema find_extrema() also returns
};

/// A cut as a polyline (scan frame). T-cuts have 2 points (SRP → hit); I-cuts 3 (p → corner → q).
struct Cut {
  std::vector<Vec2> pts;
  bool nls = false;
};

struct Partition {
  PartitionKind kind = PartitionKind::T;
  std::vector<PolyArea> faces;  ///< y-monotone pieces (scan frame), outer CCW, normally no holes
  std::vector<Srp> srps;
  std::vector<Cut> cuts;
  int n_islands = 0;  ///< holes of the reachable area (islands after offsetting)
  int n_components = 0;
  int nls = 0;  ///< NLS cuts kept (I-partition)
  /// The seeds' count: n_s − n_i + n_c − nls.
  [[nodiscard]] int formula_regions() const { return static_cast<int>(srps.size()) - n_islands + n_components - nls; }
};

/// SRPs of every loop of the areas (scan frame). O(total vertices).
[[nodiscard]] std::vector<Srp> find_srps(const std::vector<PolyArea>& areas);

/// Every y-extremum of every loop (reflex = SRPs and convex ones), same merging. O(total vertices).
[[nodiscard]] std::vector<Srp> find_extrema(const std::vector<PolyArea>& areas);

/// T- or I-partition of the areas (scan frame, outer CCW, holes CW as offset_inward returns them).
/// Cost: O(n_s · V) ray casts + one Clipper difference; the I-partition adds one difference per
/// proposed pair (V = total vertices).
[[nodiscard]] Partition partition(const std::vector<PolyArea>& areas, PartitionKind kind);

/// Sorted [x0, x1] intervals where the horizontal line at height y meets the area (closed-open
/// crossing rule: vertices at exactly y count as below the line). O(V).
[[nodiscard]] std::vector<std::pair<double, double>> scan_intervals(const PolyArea& area, double y);

/// True when every horizontal line meets the area in at most one interval (checked between all
/// consecutive distinct vertex heights). O(V²); for tests and diagnostics.
[[nodiscard]] bool is_y_monotone(const PolyArea& area);

/// Rotation of the plane by −angle_deg (world → scan frame) and back.
[[nodiscard]] Vec2 to_scan_frame(const Vec2& p, double angle_deg);
[[nodiscard]] Vec2 from_scan_frame(const Vec2& p, double angle_deg);
[[nodiscard]] std::vector<PolyArea> to_scan_frame(const std::vector<PolyArea>& areas, double angle_deg);

}  // namespace millnet::pocket
