#pragma once
// Zigzag (direction-parallel) passes inside the faces of a partition, in the scan frame (passes
// horizontal, see partition.hpp), and the order in which the faces are cut.
//   * Pass heights are one global grid over all faces (spacing ≤ stepover, the first and last pass
//     tol::scan_clear_mm inside the area's extreme heights), nudged away from SRP heights so that no
//     pass runs inside a slit.
//   * Each face is cut as one connected chain: consecutive passes are joined by walking the face's
//     boundary (the offset wall, or a cut), so the tool never leaves the reachable area.
//   * A face that no grid pass meets (a sliver thinner than the spacing) gets one pass at mid-height.
#include "millnet/pocket/partition.hpp"

#include <array>
#include <vector>

namespace millnet::pocket {

/// Global pass heights for areas spanning [y_lo, y_hi] (scan frame). O(passes · n_s).
[[nodiscard]] std::vector<double> pass_heights(const std::vector<PolyArea>& areas, const std::vector<Srp>& srps,
                                               double stepover);

/// The zigzag of one face. Corner c: bit 0 = start at the top (else bottom), bit 1 = start at the
/// right end of the first pass (else left).
class FaceZigzag {
public:
  FaceZigzag(const PolyArea& face, const std::vector<double>& ys);
  [[nodiscard]] bool empty() const { return passes_.empty(); }
  [[nodiscard]] std::size_t passes() const { return passes_.size(); }
  /// False when some pass met the face in more than one interval (partition not monotone there);
  /// only the first interval of such a pass is used by chain(), the others come from extra_chains().
  [[nodiscard]] bool monotone() const { return extra_.empty(); }
  [[nodiscard]] Vec2 entry(int corner) const;
  [[nodiscard]] Vec2 exit(int corner) const;
  /// The connected polyline: passes alternating in direction, joined along the face boundary.
  /// O(passes · face vertices).
  [[nodiscard]] std::vector<Vec2> chain(int corner) const;
  /// Passes left over by a non-monotone face, one polyline each (normally none).
  [[nodiscard]] std::vector<std::vector<Vec2>> extra_chains() const;

private:
  struct End {
    Vec2 p;
    std::size_t edge = 0;  ///< outer-ring edge (from vertex edge to edge + 1) the end lies on
  };
  struct Pass {
    End left, right;
  };
  [[nodiscard]] std::vector<Vec2> walk(const End& a, const End& b) const;
  std::vector<Vec2> ring_;
  std::vector<Pass> passes_;  ///< bottom to top
  std::vector<Pass> extra_;
};

/// An item to order: its entry and exit point and its own cutting length for each of its 4 corners
/// (the length differs by corner: the walks between passes change sides).
struct OrderItem {
  std::array<Vec2, 4> entry, exit;
  std::array<double, 4> length{0, 0, 0, 0};
};

struct Ordering {
  std::vector<std::size_t> order;  ///< indices into the items, in cutting order
  std::vector<int> corner;         ///< chosen corner per position in `order`
  double rapid_length = 0;         ///< Σ |exit − next entry|, mm
  double item_length = 0;          ///< Σ item lengths at the chosen corners, mm
};

/// Order items (faces) and pick their corners to keep rapid travel + cutting length short: nearest-neighbour start,
/// then 2-opt and single-item moves over the order with the corners re-chosen optimally by dynamic
/// programming (O(n · 16)) for each tried order. O(n³ · 16) per improvement sweep; n = faces.
[[nodiscard]] Ordering order_items(const std::vector<OrderItem>& items);

}  // namespace millnet::pocket
