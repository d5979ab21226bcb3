#include "millnet/ingest/zlevels.hpp"

#include "millnet/core/shoelace.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/tolerances.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace millnet::ingest {

namespace {

// The image the contours are traced on: pixel p (mm), simplification e (mm), and the radius
// drawn around every material raster point. Why r_draw = R + e + 2.5p: the pixel-rounded raster
// point is ≤ 0.71p off, the traced polygon through boundary pixel centres lies ≤ 1.42p inside
// the drawn disk, and approxPolyDP may cut ≤ e inward; so every point within R of a material
// raster point stays inside. Outward, a contour point is ≤ r_draw + 0.71p + e from one.
struct Layout {
  double R, p, e, r_draw, overshoot;
};

Layout layout(const HeightField& f, double grow_mm) {
  Layout l{};
  const double sx = f.nx > 1 ? f.step_x : f.step_y, sy = f.ny > 1 ? f.step_y : f.step_x;
  l.R = grow_mm + 0.5 * std::hypot(sx, sy);
  l.p = tol::contour_pixel_per_step * std::min(sx, sy);
  for (int pass = 0; pass < 2; ++pass) {
    l.e = tol::contour_simplify_px * l.p;
    l.r_draw = l.R + l.e + 2.5 * l.p;
    const double margin = l.r_draw + 2 * l.p;
    const double extent = std::max(f.width(), f.height()) + 2 * margin;
    if (extent / l.p > tol::contour_max_image_px) l.p = extent / tol::contour_max_image_px * 1.01;
  }
  l.e = tol::contour_simplify_px * l.p;
  l.r_draw = l.R + l.e + 2.5 * l.p;
  l.overshoot = l.r_draw + 0.75 * l.p + l.e - l.R;
  return l;
}

}  // namespace

double contour_overshoot_mm(const HeightField& field, double grow_mm) { return layout(field, grow_mm).overshoot; }

double signed_area(const std::vector<Eigen::Vector2d>& loop) { return shoelace_area(loop); }

std::vector<ContourLoop> material_contours(const HeightField& f, double level_z, double grow_mm) {
  if (f.nx < 1 || f.ny < 1 || f.z.size() != static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny))
    throw Error("material_contours: the height field is empty or its z has the wrong size");
  if (!std::isfinite(level_z)) throw Error("material_contours: level_z must be finite");
  if (!(grow_mm >= 0) || !std::isfinite(grow_mm))
    throw Error("material_contours: grow_mm must be ≥ 0, got " + std::to_string(grow_mm));
  const Layout l = layout(f, grow_mm);
  const double margin = l.r_draw + 2 * l.p;
  const double ox = f.x0 - margin, oy = f.y0 - margin;
  const int cols = static_cast<int>(std::ceil((f.width() + 2 * margin) / l.p)) + 1;
  const int rows = static_cast<int>(std::ceil((f.height() + 2 * margin) / l.p)) + 1;

  // Seeds: the material raster points as zero pixels (image row = y, col = x). O(raster points).
  cv::Mat seeds(rows, cols, CV_8U, cv::Scalar(255));
  bool any = false;
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      if (f.at(i, j) < level_z) continue;
      const int c = static_cast<int>(std::lround((f.x0 + j * f.step_x - ox) / l.p));
      const int r = static_cast<int>(std::lround((f.y0 + i * f.step_y - oy) / l.p));
      seeds.at<unsigned char>(r, c) = 0;
      any = true;
    }
  if (!any) return {};
  // Exact Euclidean distance to the nearest seed, thresholded: the union of disks. O(pixels).
  cv::Mat dist;
  cv::distanceTransform(seeds, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  cv::Mat mask;
  cv::threshold(dist, mask, l.r_draw / l.p, 255.0, cv::THRESH_BINARY_INV);
  mask.convertTo(mask, CV_8U);

  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(mask, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);

  std::vector<ContourLoop> out;
  std::vector<int> index_of(contours.size(), -1);
  auto convert = [&](std::size_t k, bool hole, int parent) {
    std::vector<cv::Point> approx;
    cv::approxPolyDP(contours[k], approx, tol::contour_simplify_px, true);
    if (approx.size() < 3) return -1;  // a hole of a pixel or two: dropping it keeps more material
    ContourLoop loop;
    loop.hole = hole;
    loop.parent = parent;
    loop.pts.reserve(approx.size());
    for (const cv::Point& q : approx) loop.pts.emplace_back(ox + q.x * l.p, oy + q.y * l.p);
    const double a = signed_area(loop.pts);
    if ((a < 0) != hole) std::reverse(loop.pts.begin(), loop.pts.end());
    out.push_back(std::move(loop));
    return static_cast<int>(out.size()) - 1;
  };
  // Outer loops first (hierarchy parent −1 in RETR_CCOMP), then their holes. O(contour length).
  for (std::size_t k = 0; k < contours.size(); ++k)
    if (hierarchy[k][3] < 0) index_of[k] = convert(k, false, -1);
  for (std::size_t k = 0; k < contours.size(); ++k) {
    const int parent = hierarchy[k][3];
    if (parent >= 0 && index_of[static_cast<std::size_t>(parent)] >= 0)
      index_of[k] = convert(k, true, index_of[static_cast<std::size_t>(parent)]);
  }
  return out;
}

}  // namespace millnet::ingest
