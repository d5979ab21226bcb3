#pragma once
// Internal to finish/: iso-contours of a grid field by marching squares, chained into polylines
// oriented with the inside (value ≥ level) on the LEFT. The grid is padded with an outside ring,
// so every contour closes; crossings are placed by a caller-supplied function so the waterline can
// refine them with the drop-cutter and the equidistant strategy can interpolate.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <utility>

#include <cstddef>
#include <functional>
#include <vector>

namespace millnet::finish::detail {

struct GridSpec {
  double x0 = 0, y0 = 0, step = 1;
  int nx = 0, ny = 0;     ///< nodes; rows = y
  double x1 = 0, y1 = 0;  ///< the last real node is clamped to x1, y1 (the box edge)
  /// Node position; the padding ring (i or j = −1 or n) lies one step outside.
  [[nodiscard]] Eigen::Vector2d node(int i, int j) const {
    double x = x0 + step * j, y = y0 + step * i;
    if (j >= 0 && j < nx) x = std::min(x, x1);
    if (i >= 0 && i < ny) y = std::min(y, y1);
    if (j >= nx) x = x1 + step;
    if (i >= ny) y = y1 + step;
    return {x, y};
  }
  /// A grid over the box [x0, x1] × [y0, y1] with nodes ≤ step apart, the last one on the edge.
  [[nodiscard]] static GridSpec over(double x0, double y0, double x1, double y1, double step);
};

/// One contour vertex: where it lies and whether it is on the padding ring (the machining
/// boundary clips the contour there).
struct ContourPoint {
  Eigen::Vector2d xy;
  double aux = 0;  ///< what the placement function attached (the waterline: the slope)
  bool on_boundary = false;
  double lift = 0;     ///< the waterline: height above the level where a chord is lifted
  bool fresh = false;  ///< the waterline: added by a split of the chords into inside corners
};

/// Places the crossing on the grid edge from an inside node to an outside node. `outside_is_pad`
/// says the outside node is the padding ring (not a real sample).
using PlaceCrossing =
    std::function<std::pair<Eigen::Vector2d, double>(const Eigen::Vector2d& inside, const Eigen::Vector2d& outside,
                                                     double v_inside, double v_outside, bool outside_is_pad)>;

/// Closed contours (last point = first point) of {value ≥ level}, inside on the left (CCW around
/// the inside). values: nx·ny, row-major.
[[nodiscard]] std::vector<std::vector<ContourPoint>> iso_contours(const GridSpec& g, const std::vector<double>& values,
                                                                  double level, const PlaceCrossing& place);

/// A grid field traced at many levels (the waterline's Z levels, the equidistant strategy's
/// distances): per run of kRun cells of a padded row, the lowest and highest corner value (NaN and
/// the padding count as −∞, i.e. outside), so that a level skips the runs wholly inside or outside
/// it. The contours are those of iso_contours, point for point. Build O(nodes); a level
/// O(nodes / kRun + cells the contour crosses · kRun). Keeps references to g and values.
class IsoField {
public:
  static constexpr int kRun = 32;
  /// skip_runs = false: every cell is visited (the plain scan; the tests' reference).
  IsoField(const GridSpec& g, const std::vector<double>& values, bool skip_runs = true);
  [[nodiscard]] std::vector<std::vector<ContourPoint>> contours(double level, const PlaceCrossing& place) const;

private:
  const GridSpec& g_;
  const std::vector<double>& values_;
  int runs_ = 0;                 ///< runs per padded row (nx + 1 cells)
  std::vector<double> lo_, hi_;  ///< per (padded row, run)
};

}  // namespace millnet::finish::detail
