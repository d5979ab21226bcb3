#include "millnet/ingest/pointcloud.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/tolerances.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <utility>

namespace millnet::ingest {

namespace {

// Distinct values of a sorted list, merging runs closer than `tol`. O(n).
std::vector<double> distinct(std::vector<double> v, double tol) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > tol) out.push_back(x);
  return out;
}

std::size_t nearest(const std::vector<double>& lines, double x) {
  const auto it = std::lower_bound(lines.begin(), lines.end(), x);
  if (it == lines.end()) return lines.size() - 1;
  const auto k = static_cast<std::size_t>(it - lines.begin());
  if (k > 0 && x - lines[k - 1] < *it - x) return k - 1;
  return k;
}

/// A regular raster: every point snaps to a (column, row) of the distinct x and y lines (within
/// tol_xy), every node of the lines has a point (the highest z where several do). The mesh of its
/// cells, two triangles each; nullopt when the points are no such raster. O(P log P).
std::optional<Mesh> raster_mesh(const Vertices& points, const std::vector<double>& xs, const std::vector<double>& ys,
                                double tol_xy) {
  const std::size_t np = xs.size();
  const std::vector<double> cx = distinct(xs, tol_xy), cy = distinct(ys, tol_xy);
  if (!(cx.size() >= 2 && cy.size() >= 2 && cx.size() * cy.size() <= 4 * np)) return std::nullopt;
  const std::size_t nxl = cx.size(), nyl = cy.size();
  std::vector<double> top(nxl * nyl, -std::numeric_limits<double>::infinity());
  bool on_lines = true;
  for (std::size_t k = 0; k < np && on_lines; ++k) {
    const std::size_t j = nearest(cx, xs[k]), i = nearest(cy, ys[k]);
    if (std::abs(cx[j] - xs[k]) > tol_xy || std::abs(cy[i] - ys[k]) > tol_xy) on_lines = false;
    double& t = top[i * nxl + j];
    t = std::max(t, points(static_cast<Eigen::Index>(k), 2));
  }
  const bool complete = on_lines && std::all_of(top.begin(), top.end(), [](double z) { return std::isfinite(z); });
  if (!complete) return std::nullopt;
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(nxl * nyl), 3);
  for (std::size_t i = 0; i < nyl; ++i)
    for (std::size_t j = 0; j < nxl; ++j) {
      const auto r = static_cast<Eigen::Index>(i * nxl + j);
      m.V.row(r) << cx[j], cy[i], top[i * nxl + j];
    }
  m.F.resize(static_cast<Eigen::Index>(2 * (nxl - 1) * (nyl - 1)), 3);
  Eigen::Index f = 0;
  for (std::size_t i = 0; i + 1 < nyl; ++i)
    for (std::size_t j = 0; j + 1 < nxl; ++j) {
      const auto a = static_cast<std::int32_t>(i * nxl + j), b = a + 1;
      const auto c = static_cast<std::int32_t>((i + 1) * nxl + j), d = c + 1;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  return m;
}

/// The distinct XY positions of the cloud, centred and scaled for Subdiv2D (float), each with the
/// point of the highest z there.
struct UniqueXY {
  std::map<std::pair<float, float>, std::size_t> key_to_vertex;
  std::vector<cv::Point2f> uniq;
  std::vector<std::size_t> uniq_src;  ///< the point (row of `points`) of each
};

UniqueXY unique_xy(const Vertices& points, const std::vector<double>& xs, const std::vector<double>& ys,
                   const Eigen::Vector3d& lo, double scale) {
  UniqueXY u;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const cv::Point2f q(static_cast<float>((xs[k] - lo.x()) * scale), static_cast<float>((ys[k] - lo.y()) * scale));
    const auto [it, inserted] = u.key_to_vertex.try_emplace({q.x, q.y}, u.uniq.size());
    if (inserted) {
      u.uniq.push_back(q);
      u.uniq_src.push_back(k);
    } else if (points(static_cast<Eigen::Index>(k), 2) > points(static_cast<Eigen::Index>(u.uniq_src[it->second]), 2)) {
      u.uniq_src[it->second] = k;
    }
  }
  return u;
}

/// The Delaunay triangles of the distinct positions (indices into u.uniq, counter-clockwise seen
/// from +Z), without the super-triangle's and the flat ones.
std::vector<std::array<std::int32_t, 3>> delaunay_faces(const UniqueXY& u, double extent, const std::string& source) {
  // Subdiv2D starts from a finite super-triangle about 3× its rectangle; where that rectangle is
  // tight, the super-vertices fall inside the circumcircles of flat triangles along the convex
  // hull and those triangles go missing (holes along the cloud's border). A rectangle 10⁴× the
  // points' extent keeps them (the points keep float precision ~1e-3 of 1e4 units).
  cv::Subdiv2D subdiv(cv::Rect(-100000000, -100000000, 200010000, 200010000));
  std::vector<cv::Vec6f> tris;
  try {
    subdiv.insert(u.uniq);
    subdiv.getTriangleList(tris);
  } catch (const cv::Exception&) {  // degenerate or extreme input (fuzz_points): OpenCV's own text is no help
    throw Error(
        source + ": the points cannot be triangulated in XY (their spread of " + std::to_string(extent) +
        " mm leaves too little float precision, or they are degenerate); expected a height field's points in mm");
  }
  std::vector<std::array<std::int32_t, 3>> faces;
  faces.reserve(tris.size());
  for (const cv::Vec6f& t : tris) {
    std::array<std::int32_t, 3> idx{};
    bool real = true;
    for (int k = 0; k < 3 && real; ++k) {
      const auto it = u.key_to_vertex.find({t[2 * k], t[2 * k + 1]});
      if (it == u.key_to_vertex.end())
        real = false;  // a corner of Subdiv2D's outer triangle
      else
        idx[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(it->second);
    }
    if (!real) continue;
    const cv::Point2f& a = u.uniq[static_cast<std::size_t>(idx[0])];
    const cv::Point2f& b = u.uniq[static_cast<std::size_t>(idx[1])];
    const cv::Point2f& c = u.uniq[static_cast<std::size_t>(idx[2])];
    const double ax = static_cast<double>(a.x), ay = static_cast<double>(a.y);
    const double cr = (static_cast<double>(b.x) - ax) * (static_cast<double>(c.y) - ay) -
                      (static_cast<double>(b.y) - ay) * (static_cast<double>(c.x) - ax);
    if (cr == 0) continue;
    if (cr < 0) std::swap(idx[1], idx[2]);  // CCW seen from +Z
    faces.push_back(idx);
  }
  return faces;
}

}  // namespace

Mesh triangulate_height_field(const Vertices& points, const std::string& source) {
  const auto np = static_cast<std::size_t>(points.rows());
  if (np < 3) throw Error(source + ": a point cloud needs at least 3 points, found " + std::to_string(np));
  const Eigen::Vector3d lo = points.colwise().minCoeff().transpose(), hi = points.colwise().maxCoeff().transpose();
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(extent > 0)) throw Error(source + ": all points of the cloud have the same XY position");
  const double tol_xy = tol::cloud_raster_rel * extent;
  std::vector<double> xs(np), ys(np);
  for (std::size_t k = 0; k < np; ++k) {
    xs[k] = points(static_cast<Eigen::Index>(k), 0);
    ys[k] = points(static_cast<Eigen::Index>(k), 1);
  }
  if (std::optional<Mesh> m = raster_mesh(points, xs, ys, tol_xy)) return std::move(*m);

  // Scattered points: Delaunay in XY on coordinates centred and scaled to [0, 1e4] (Subdiv2D is
  // float; centring first keeps far-away clouds precise). Duplicate XY keeps the highest z.
  const UniqueXY u = unique_xy(points, xs, ys, lo, 1e4 / extent);
  if (u.uniq.size() < 3) throw Error(source + ": fewer than 3 distinct XY positions in the point cloud");
  const std::vector<std::array<std::int32_t, 3>> faces = delaunay_faces(u, extent, source);
  if (faces.empty()) throw Error(source + ": the point cloud's XY positions are collinear (no triangles)");
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(u.uniq.size()), 3);
  for (std::size_t k = 0; k < u.uniq.size(); ++k)
    m.V.row(static_cast<Eigen::Index>(k)) = points.row(static_cast<Eigen::Index>(u.uniq_src[k]));
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k)
    m.F.row(static_cast<Eigen::Index>(k)) << faces[k][0], faces[k][1], faces[k][2];
  return m;
}

}  // namespace millnet::ingest
