// Cell rasters of a region (raster_internal.hpp).
#include "raster_internal.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace millnet::pocket::raster {

namespace {

/// The boundary's box and the grid's cell counts (as doubles: they may not fit an int).
struct Extent {
  Vec2 lo;
  double nx = 0, ny = 0;
};
Extent extent_of(const Region& region, double h, double margin) {
  const std::vector<Vec2> b = flatten(region.boundary, tol::arc_chord_mm);
  Vec2 lo = b.front(), hi = b.front();
  for (const Vec2& p : b) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return {lo, std::ceil((hi.x() - lo.x() + 2 * margin) / h) + 1, std::ceil((hi.y() - lo.y() + 2 * margin) / h) + 1};
}

}  // namespace

double cells_of(const Region& region, double h, double margin) {
  const Extent e = extent_of(region, h, margin);
  return e.nx * e.ny;
}

Grid grid_of(const Region& region, double h, double margin, const char* who, double max_cells) {
  const Extent e = extent_of(region, h, margin);
  Grid g;
  g.h = h;
  g.lo = e.lo - Vec2(margin, margin);
  const double nx = e.nx, ny = e.ny;
  if (!(nx * ny <= max_cells))
    throw Error(std::string(who) + ": raster of " + std::to_string(nx) + " x " + std::to_string(ny) +
                " cells is too fine; raise the cell size");
  g.nx = static_cast<int>(nx);
  g.ny = static_cast<int>(ny);
  return g;
}

std::vector<std::uint8_t> material(const Region& region, const Grid& g) {
  std::vector<std::uint8_t> m(g.size(), 0);
  std::vector<std::vector<Vec2>> loops{flatten(region.boundary, tol::arc_chord_mm)};
  for (const Loop& isl : region.islands) loops.push_back(flatten(isl, tol::arc_chord_mm));
  std::vector<double> xs;
  for (int y = 0; y < g.ny; ++y) {
    const double yc = g.centre(0, y).y();
    xs.clear();
    for (const auto& l : loops)
      for (std::size_t i = 0; i < l.size(); ++i) {
        const Vec2& a = l[i];
        const Vec2& c = l[(i + 1) % l.size()];
        if ((a.y() <= yc) == (c.y() <= yc)) continue;  // half-open: a vertex on the line counts once
        xs.push_back(a.x() + (yc - a.y()) * (c.x() - a.x()) / (c.y() - a.y()));
      }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int x0 = std::max(0, static_cast<int>(std::ceil((xs[k] - g.lo.x()) / g.h - 0.5)));
      const int x1 = std::min(g.nx - 1, static_cast<int>(std::floor((xs[k + 1] - g.lo.x()) / g.h - 0.5)));
      for (int x = x0; x <= x1; ++x) m[lin(x, y, g.nx)] = 1;
    }
  }
  return m;
}

std::vector<double> edt(const std::vector<std::uint8_t>& seed, int nx, int ny) {
  std::vector<double> d2(seed.size(), std::numeric_limits<double>::infinity());
  if (std::none_of(seed.begin(), seed.end(), [](std::uint8_t v) { return v != 0; })) return d2;
  cv::Mat src(ny, nx, CV_8U);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) src.at<unsigned char>(y, x) = seed[lin(x, y, nx)] ? 0 : 255;  // zero = seed
  cv::Mat dist;
  cv::distanceTransform(src, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double v = dist.at<float>(y, x);
      d2[lin(x, y, nx)] = v * v;
    }
  return d2;
}

}  // namespace millnet::pocket::raster
