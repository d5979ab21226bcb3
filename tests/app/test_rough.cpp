// Issue 5, roughing: Z-level regions of analytic solids (box on a plate, hemisphere on a plate)
// against their exact cross-sections, and a gouge replay of the written G-code against the MESH
// TRIANGLES (exact maximum of the piecewise-linear surface under the tool disk), independent of the
// planner, the pocket module and the ingest z-buffer. Plus the output files and the CLI batch
// contract (a broken mesh is reported, the good one still gets its outputs).
#include "cli_runner.hpp"
#include "config.hpp"
#include "rough.hpp"
#include "testing/gcode_replay.hpp"

#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/mesh_io.hpp"
#include "millnet/ingest/zlevels.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace {

using millnet::app::Json;
using millnet::app::RoughParams;
using millnet::app::RoughResult;
namespace ingest = millnet::ingest;
namespace pocket = millnet::pocket;
namespace datasets = millnet::datasets;
namespace fs = std::filesystem;
using millnet::testing::fresh_dir;
using millnet::testing::run_millnet;
using millnet::testing::slurp;

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Analytic solids, built as ingest::Mesh (closed shells, outward normals).

void append(ingest::Mesh& m, const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& f) {
  const Eigen::Index v0 = m.V.rows(), f0 = m.F.rows();
  m.V.conservativeResize(v0 + static_cast<Eigen::Index>(v.size()), 3);
  m.F.conservativeResize(f0 + static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V.row(v0 + static_cast<Eigen::Index>(i)) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      m.F(f0 + static_cast<Eigen::Index>(i), k) = static_cast<std::int32_t>(v0) + f[i][static_cast<std::size_t>(k)];
}

/// A closed axis-aligned box (12 triangles, outward normals).
void add_box(ingest::Mesh& m, double x0, double y0, double z0, double x1, double y1, double z1) {
  std::vector<Eigen::Vector3d> v;
  for (int k = 0; k < 8; ++k) v.emplace_back((k & 1) ? x1 : x0, (k & 2) ? y1 : y0, (k & 4) ? z1 : z0);
  append(m, v,
         {{0, 2, 1}, {1, 2, 3},    // bottom (−z)
          {4, 5, 6}, {5, 7, 6},    // top (+z)
          {0, 1, 4}, {1, 5, 4},    // −y
          {2, 6, 3}, {3, 6, 7},    // +y
          {0, 4, 2}, {2, 4, 6},    // −x
          {1, 3, 5}, {3, 7, 5}});  // +x
}

/// A closed hemisphere of radius r on the plane z = zc centred at (cx, cy): `az` segments around,
/// `el` rings up; vertices on the sphere, so chords lie inside it by at most the sagitta.
void add_hemisphere(ingest::Mesh& m, double cx, double cy, double zc, double r, int az, int el) {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  // Rings k = 0..el−1 at elevation k·(π/2)/el, then the pole; plus the base centre.
  for (int k = 0; k < el; ++k) {
    const double phi = 0.5 * kPi * k / el;
    for (int j = 0; j < az; ++j) {
      const double th = 2 * kPi * j / az;
      v.emplace_back(cx + r * std::cos(phi) * std::cos(th), cy + r * std::cos(phi) * std::sin(th), zc + r * std::sin(phi));
    }
  }
  const int pole = static_cast<int>(v.size());
  v.emplace_back(cx, cy, zc + r);
  const int base = static_cast<int>(v.size());
  v.emplace_back(cx, cy, zc);
  auto id = [az](int k, int j) { return k * az + (j % az); };
  for (int k = 0; k + 1 < el; ++k)
    for (int j = 0; j < az; ++j) {
      f.push_back({id(k, j), id(k, j + 1), id(k + 1, j + 1)});
      f.push_back({id(k, j), id(k + 1, j + 1), id(k + 1, j)});
    }
  for (int j = 0; j < az; ++j) f.push_back({id(el - 1, j), id(el - 1, j + 1), pole});
  for (int j = 0; j < az; ++j) f.push_back({id(0, j + 1), id(0, j), base});  // the flat base faces −z
  append(m, v, f);
}

/// Roughing parameters as the CLI builds them (all-defaults config + flags).
RoughParams params_for(const std::string& planner, double stock_to_leave, double step_down) {
  const Json config = millnet::app::default_config(MILLNET_SOURCE_DIR);
  millnet::app::PocketFlags fl;
  fl.planner = planner;
  fl.stock_to_leave = stock_to_leave;
  fl.step_down = step_down;
  return millnet::app::rough_params(config, Json::object(), fl);
}

std::vector<Eigen::Vector2d> pts_of(const pocket::Loop& l) {
  std::vector<Eigen::Vector2d> p;
  for (const auto& v : l) {
    EXPECT_EQ(v.bulge, 0.0) << "the slicing emits polylines";
    p.emplace_back(v.x, v.y);
  }
  return p;
}

double seg_dist(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

/// Signed distance of p to the axis-aligned rectangle (> 0 outside).
double rect_sdist(const Eigen::Vector2d& p, double x0, double y0, double x1, double y1) {
  const double dx = std::max(x0 - p.x(), p.x() - x1), dy = std::max(y0 - p.y(), p.y() - y1);
  if (dx <= 0 && dy <= 0) return std::max(dx, dy);
  return std::hypot(std::max(dx, 0.0), std::max(dy, 0.0));
}

/// Even-odd point-in-polygon.
bool inside(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
  }
  return in;
}

/// Smallest distance from p to the polygon's edges.
double poly_dist(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) d = std::min(d, seg_dist(p, poly[i], poly[(i + 1) % poly.size()]));
  return d;
}

/// The stated contour tolerance of a level's islands (outward): grow + ½ raster diagonal + the
/// contour overshoot of material_contours().
double contour_tolerance(const RoughResult& r, const RoughParams& p) {
  return p.contour_tolerance_mm + 0.5 * std::hypot(r.field.step_x, r.field.step_y) +
         ingest::contour_overshoot_mm(r.field, p.contour_tolerance_mm);
}

// ---------------------------------------------------------------------------------------------
// Level regions of analytic solids.

TEST(RoughLevels, BoxOnPlateGivesOneSquareIslandPerLevelAndNoneAboveTheBox) {
  // Plate 100×80×5, box 30.1 × 29.9 × 20 on it (edges deliberately off the 0.25 mm raster lines).
  const double bx0 = 30.1, by0 = 20.05, bx1 = 60.2, by1 = 49.95, plate_top = 5, box_top = 25;
  for (const double stl : {0.0, 0.5}) {
    ingest::Mesh m;
    add_box(m, 0, 0, 0, 100, 80, plate_top);
    add_box(m, bx0, by0, plate_top, bx1, by1, box_top);
    RoughParams p = params_for("som", stl, 5.1);
    // Stock top 30.3, 6 levels of 5.05 mm (25.25, 20.2, …, 5.05, 0): the first lies above the box
    // top but within 0.5 mm of it, so with stock_to_leave 0.5 the box is already an island there;
    // 5.05 lies just above the plate (with stock_to_leave 0 the plate is not yet material).
    p.top_allowance_mm = 5.3;
    const RoughResult r = rough_mesh(m, p);
    ASSERT_EQ(r.levels.size(), 6u);
    EXPECT_DOUBLE_EQ(r.stock_top_part, 30.3);
    EXPECT_NEAR(r.stock_x0, -5, 1e-12);
    EXPECT_NEAR(r.stock_y1, 85, 1e-12);
    const double tol = contour_tolerance(r, p);
    std::printf("[box stl=%.1f] contour tolerance %.4f mm (raster %.4f × %.4f)\n", stl, tol, r.field.step_x, r.field.step_y);
    int box_levels = 0, empty_levels = 0;
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
      const auto& lv = r.levels[k];
      SCOPED_TRACE("level " + std::to_string(k + 1) + " z_part " + std::to_string(lv.z_part) + " stl " + std::to_string(stl));
      EXPECT_NEAR(lv.z, lv.z_part - 30.3, 1e-12);
      EXPECT_NEAR(lv.z_part, 30.3 - 5.05 * static_cast<double>(k + 1), 1e-9);
      const double thr = lv.z_part - stl;  // material = surface at or above this
      ASSERT_GE(lv.regions.size(), 1u);
      if (thr > box_top) {
        ++empty_levels;
        EXPECT_EQ(lv.islands, 0u);
        EXPECT_TRUE(lv.regions[0].islands.empty());
        EXPECT_EQ(lv.regions.size(), 1u);
        continue;
      }
      if (thr <= plate_top) continue;  // the plate (and at the floor the whole stock) is material
      ++box_levels;
      ASSERT_EQ(lv.regions.size(), 1u);
      ASSERT_EQ(lv.islands, 1u);
      ASSERT_EQ(lv.regions[0].islands.size(), 1u);
      const auto isl = pts_of(lv.regions[0].islands[0]);
      // Every vertex within the tolerance band around the true square, on the material side.
      double worst_out = -1e9, worst_in = 1e9;
      for (const auto& v : isl) {
        const double d = rect_sdist(v, bx0, by0, bx1, by1);
        worst_out = std::max(worst_out, d);
        worst_in = std::min(worst_in, d);
      }
      EXPECT_LE(worst_out, tol);
      EXPECT_GE(worst_in, 0.0) << "an island vertex lies inside the box: the pocket would cut the part";
      // The island contains the whole true square, every edge point at least at a small margin.
      double min_edge_clear = 1e9;
      for (int s = 0; s <= 400; ++s) {
        const double t = s / 400.0;
        for (const Eigen::Vector2d& q : {Eigen::Vector2d(bx0 + t * (bx1 - bx0), by0), Eigen::Vector2d(bx0 + t * (bx1 - bx0), by1),
                                        Eigen::Vector2d(bx0, by0 + t * (by1 - by0)), Eigen::Vector2d(bx1, by0 + t * (by1 - by0))}) {
          EXPECT_TRUE(inside(isl, q)) << q.transpose();
          min_edge_clear = std::min(min_edge_clear, poly_dist(isl, q));
        }
      }
      // Area between the square's and the square grown by the tolerance.
      double area = 0;
      for (std::size_t i = 0; i < isl.size(); ++i) {
        const auto &a = isl[i], &b = isl[(i + 1) % isl.size()];
        area += a.x() * b.y() - b.x() * a.y();
      }
      area = std::abs(area) / 2;
      const double w = bx1 - bx0, h = by1 - by0;
      EXPECT_GE(area, w * h);
      EXPECT_LE(area, (w + 2 * tol) * (h + 2 * tol));
      std::printf("[box stl=%.1f] level %zu z_part %.3f: island area %.2f mm² (square %.2f), vertices %+.4f..%+.4f mm from the "
                  "square, edges ≥ %.4f mm outside\n",
                  stl, k + 1, lv.z_part, area, w * h, worst_in, worst_out, min_edge_clear);
      // The regions sent to the planner: the stock grown by twice the tool clearance (centres may
      // pass a clearance outside the stock edge), with that island.
      const auto b = pts_of(lv.regions[0].boundary);
      double bx_min = 1e9, bx_max = -1e9;
      for (const auto& v : b) {
        bx_min = std::min(bx_min, v.x());
        bx_max = std::max(bx_max, v.x());
      }
      EXPECT_NEAR(bx_min, -5 - 2 * p.cut.clearance(), 1e-9);
      EXPECT_NEAR(bx_max, 105 + 2 * p.cut.clearance(), 1e-9);
    }
    EXPECT_EQ(empty_levels, stl > 0 ? 0 : 1);
    EXPECT_EQ(box_levels, 4);
    EXPECT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
  }
}

TEST(RoughLevels, HemisphereGivesCircularIslandsOfTheRightRadius) {
  const double cx = 40, cy = 40, base = 5, R = 25;
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 80, 80, base);
  add_hemisphere(m, cx, cy, base, R, 256, 96);
  // Chord sagitta of the tessellation (in azimuth and in elevation): cross-sections of the mesh
  // lie inside the true sphere's by at most this much (radially, away from the pole).
  const double sag = R * (1 - std::cos(kPi / 256)) + R * (1 - std::cos(0.5 * kPi / 96 / 2));
  for (const double stl : {0.0, 0.5}) {
    const RoughParams p = params_for("som", stl, 4);
    const RoughResult r = rough_mesh(m, p);
    const double tol = contour_tolerance(r, p);
    int checked = 0;
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
      const auto& lv = r.levels[k];
      SCOPED_TRACE("level " + std::to_string(k + 1) + " stl " + std::to_string(stl));
      const double dz = lv.z_part - stl - base;  // height of the material threshold above the sphere's base
      if (dz >= R) {
        EXPECT_EQ(lv.islands, 0u);
        continue;
      }
      if (dz <= 0) continue;
      // Away from the pole, where a small slope turns the mesh's chord error into a large radial one.
      const double rr = std::sqrt(R * R - dz * dz);
      ASSERT_EQ(lv.regions.size(), 1u);
      ASSERT_EQ(lv.regions[0].islands.size(), 1u);
      const auto isl = pts_of(lv.regions[0].islands[0]);
      // Radial slack of the mesh below the true sphere: the sagitta divided by the cosine of the
      // surface slope angle at this height (≈ R/rr), at most 0.1 mm near the pole.
      const double mesh_tol = std::min(0.1, sag * R / rr);
      double mean = 0, lo = 1e9, hi = -1e9, area = 0;
      for (std::size_t i = 0; i < isl.size(); ++i) {
        const double d = (isl[i] - Eigen::Vector2d(cx, cy)).norm();
        mean += d;
        lo = std::min(lo, d);
        hi = std::max(hi, d);
        const auto &a = isl[i], &b = isl[(i + 1) % isl.size()];
        area += a.x() * b.y() - b.x() * a.y();
      }
      mean /= static_cast<double>(isl.size());
      area = std::abs(area) / 2;
      // Closest approach of the island's edges to the centre: the island contains the circle.
      const double edge_min = [&] {
        double e = 1e9;
        for (std::size_t i = 0; i < isl.size(); ++i) e = std::min(e, seg_dist({cx, cy}, isl[i], isl[(i + 1) % isl.size()]));
        return e;
      }();
      std::printf("[hemisphere stl=%.1f] level %zu z_part %.3f: r %.3f, island radius mean %.4f (min vertex %.4f, max %.4f, "
                  "edges ≥ %.4f), area %.1f vs πr² %.1f, tolerance %.4f\n",
                  stl, k + 1, lv.z_part, rr, mean, lo, hi, edge_min, area, kPi * rr * rr, tol);
      EXPECT_LE(hi, rr + tol);
      EXPECT_GE(edge_min, rr - mesh_tol) << "the island cuts into the sphere";
      EXPECT_GT(mean, rr);
      EXPECT_LT(mean, rr + tol);
      EXPECT_GE(area, kPi * (rr - mesh_tol) * (rr - mesh_tol));
      EXPECT_LE(area, kPi * (rr + tol) * (rr + tol));
      ++checked;
    }
    EXPECT_GE(checked, 6);
  }
}

TEST(RoughLevels, PlainBoxIsRoughedAroundDownToTheFloor) {
  // A 40×30×20 box alone: every level's material is the box, so all the cutting is the margin
  // ring (5 mm) around it, and the last level lies at the box's bottom. Before the fixes in
  // rough_mesh (stock region grown by 2 clearances; raster points off the part never material)
  // this program cut 0 mm: the ring was narrower than clearance + island growth, and the floor
  // level was all material.
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 40, 30, 20);
  const RoughParams p = params_for("som", 0, 5);
  const RoughResult r = rough_mesh(m, p);
  ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
  ASSERT_EQ(r.levels.size(), 5u);
  ASSERT_EQ(r.machining.levels.size(), 5u) << "every level cuts";
  EXPECT_NEAR(r.machining.levels.back().z, -21.0, 1e-9);
  for (const auto& lv : r.machining.levels) EXPECT_GT(lv.path.cut_length(), 100.0) << lv.z;
  // The floor level's cutting moves run in the ring around the box, at ≥ R from it and never
  // farther out than a clearance beyond the stock edge. (How much of the ring next to the wall
  // is swept depends on the planner's grid: rough_mesh runs no contour pass.)
  const auto rep = millnet::testing::replay_gcode(r.machining.gcode, p.cut.safe_z);
  int floor_moves = 0;
  for (const auto& mv : rep.moves) {
    if (mv.g == 0 || std::abs(mv.to[2] + 21.0) > 1e-3 || std::abs(mv.from[2] + 21.0) > 1e-3) continue;
    ++floor_moves;
    const Eigen::Vector2d q(mv.to[0], mv.to[1]);
    EXPECT_GE(rect_sdist(q, 0, 0, 40, 30), 5 - 1e-3) << "line " << mv.line;
    // Within the stock rectangle grown by one clearance (a rectangle: corners included).
    EXPECT_LE(std::max(std::abs(q.x() - 20) - 30, std::abs(q.y() - 15) - 25), 1e-3) << "line " << mv.line;
  }
  EXPECT_GT(floor_moves, 4);
}

// ---------------------------------------------------------------------------------------------
// The gouge oracle: the exact maximum height of the mesh's triangles under a disk.

/// Brute force over the mesh triangles (bucketed in XY only to find the candidates): the maximum z
/// of a triangle over a closed disk is the max of a linear function over a convex set, attained at
/// a triangle vertex inside the disk, at an edge–circle intersection, or at the circle point in
/// the direction of the plane's gradient when it lies inside the triangle (the centre when flat).
/// Vertical triangles: vertices and edge–circle intersections (exact as well).
class TopOracle {
 public:
  explicit TopOracle(const ingest::Mesh& m, double cell = 2.0) : cell_(cell) {
    x0_ = m.V.col(0).minCoeff() - 1;
    y0_ = m.V.col(1).minCoeff() - 1;
    nx_ = static_cast<int>((m.V.col(0).maxCoeff() + 1 - x0_) / cell_) + 1;
    ny_ = static_cast<int>((m.V.col(1).maxCoeff() + 1 - y0_) / cell_) + 1;
    zmax_ = m.V.col(2).maxCoeff();
    buckets_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
    // O(#F · cells per triangle).
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      Tri t;
      for (Eigen::Index k = 0; k < 3; ++k) t.v[static_cast<std::size_t>(k)] = m.V.row(m.F(f, k)).transpose();
      t.lo = t.v[0].head<2>().cwiseMin(t.v[1].head<2>()).cwiseMin(t.v[2].head<2>());
      t.hi = t.v[0].head<2>().cwiseMax(t.v[1].head<2>()).cwiseMax(t.v[2].head<2>());
      t.zmax = std::max({t.v[0].z(), t.v[1].z(), t.v[2].z()});
      const Eigen::Vector2d e1 = (t.v[1] - t.v[0]).head<2>(), e2 = (t.v[2] - t.v[0]).head<2>();
      t.det = e1.x() * e2.y() - e1.y() * e2.x();
      t.flat_xy = std::abs(t.det) <= 1e-12 * std::max(1.0, e1.squaredNorm() + e2.squaredNorm());
      if (!t.flat_xy) {
        // z = v0.z + g·(p − v0) on the plane.
        const double dz1 = t.v[1].z() - t.v[0].z(), dz2 = t.v[2].z() - t.v[0].z();
        t.g = Eigen::Vector2d((dz1 * e2.y() - dz2 * e1.y()) / t.det, (dz2 * e1.x() - dz1 * e2.x()) / t.det);
      }
      const std::size_t id = tris_.size();
      tris_.push_back(t);
      for (int i = cy(t.lo.y()); i <= cy(t.hi.y()); ++i)
        for (int j = cx(t.lo.x()); j <= cx(t.hi.x()); ++j) buckets_[idx(i, j)].push_back(id);
    }
    stamp_.assign(tris_.size(), 0);
  }

  [[nodiscard]] double zmax() const { return zmax_; }

  /// Max z of the surface over the closed disk (c, r), considering only triangles that reach above
  /// `floor`; returns −∞ when none does. O(triangles in the disk's buckets).
  double max_over_disk(const Eigen::Vector2d& c, double r, double floor = -std::numeric_limits<double>::infinity()) {
    ++cur_;
    double best = -std::numeric_limits<double>::infinity();
    for (int i = cy(c.y() - r); i <= cy(c.y() + r); ++i)
      for (int j = cx(c.x() - r); j <= cx(c.x() + r); ++j)
        for (const std::size_t id : buckets_[idx(i, j)]) {
          if (stamp_[id] == cur_) continue;
          stamp_[id] = cur_;
          const Tri& t = tris_[id];
          if (t.zmax <= floor || t.zmax <= best) continue;
          if (c.x() + r < t.lo.x() || c.x() - r > t.hi.x() || c.y() + r < t.lo.y() || c.y() - r > t.hi.y()) continue;
          best = std::max(best, tri_max(t, c, r));
        }
    return best;
  }

 private:
  struct Tri {
    std::array<Eigen::Vector3d, 3> v;
    Eigen::Vector2d lo, hi, g = Eigen::Vector2d::Zero();
    double zmax = 0, det = 0;
    bool flat_xy = false;
  };

  static double tri_max(const Tri& t, const Eigen::Vector2d& c, double r) {
    double best = -std::numeric_limits<double>::infinity();
    const double r2 = r * r;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& a = t.v[static_cast<std::size_t>(k)];
      const Eigen::Vector3d& b = t.v[static_cast<std::size_t>((k + 1) % 3)];
      if ((a.head<2>() - c).squaredNorm() <= r2) best = std::max(best, a.z());
      // |a + s(b − a) − c|² = r², s ∈ [0, 1].
      const Eigen::Vector2d d = (b - a).head<2>(), f = a.head<2>() - c;
      const double A = d.squaredNorm();
      if (A <= 0) continue;
      const double B = 2 * f.dot(d), C = f.squaredNorm() - r2, disc = B * B - 4 * A * C;
      if (disc < 0) continue;
      for (const double s : {(-B - std::sqrt(disc)) / (2 * A), (-B + std::sqrt(disc)) / (2 * A)})
        if (s >= 0 && s <= 1) best = std::max(best, a.z() + s * (b.z() - a.z()));
    }
    if (!t.flat_xy) {
      const double gn = t.g.norm();
      const Eigen::Vector2d q = gn > 0 ? Eigen::Vector2d(c + r * t.g / gn) : c;
      const Eigen::Vector2d e1 = (t.v[1] - t.v[0]).head<2>(), e2 = (t.v[2] - t.v[0]).head<2>(), w = q - t.v[0].head<2>();
      const double u = (w.x() * e2.y() - w.y() * e2.x()) / t.det, v = (e1.x() * w.y() - e1.y() * w.x()) / t.det;
      if (u >= 0 && v >= 0 && u + v <= 1) best = std::max(best, t.v[0].z() + t.g.dot(w));
    }
    return best;
  }
  int cx(double x) const { return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1); }
  int cy(double y) const { return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1); }
  std::size_t idx(int i, int j) const { return static_cast<std::size_t>(i) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(j); }

  double cell_, x0_ = 0, y0_ = 0, zmax_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<Tri> tris_;
  std::vector<std::vector<std::size_t>> buckets_;
  std::vector<unsigned> stamp_;
  unsigned cur_ = 0;
};

TEST(RoughOracle, MatchesAnalyticMaximaOfABoxAndAHemisphere) {
  // The oracle itself must be right, or the gouge replay proves nothing.
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 100, 80, 5);
  add_box(m, 30, 20, 5, 60, 50, 25);
  TopOracle o(m);
  EXPECT_DOUBLE_EQ(o.max_over_disk({10, 10}, 5), 5.0);
  EXPECT_DOUBLE_EQ(o.max_over_disk({25.01, 35}, 5), 25.0);  // reaches 0.01 mm over the box wall
  EXPECT_DOUBLE_EQ(o.max_over_disk({24.99, 35}, 5), 5.0);   // stops 0.01 mm short of it
  EXPECT_DOUBLE_EQ(o.max_over_disk({26.5, 16.5}, 5), 25.0);  // the corner (30,20) at √24.5 < 5
  EXPECT_DOUBLE_EQ(o.max_over_disk({26.4, 16.4}, 5), 5.0);   // √25.92 > 5
  EXPECT_EQ(o.max_over_disk({-20, -20}, 5), -std::numeric_limits<double>::infinity());
  ingest::Mesh h;
  add_hemisphere(h, 0, 0, 0, 20, 64, 32);
  TopOracle oh(h);
  EXPECT_NEAR(oh.max_over_disk({0, 0}, 1), 20.0, 1e-12);
  // Disk off to the side: the max lies on the disk's rim nearest the centre, at radius d − r.
  for (const double d : {8.0, 12.0, 17.0}) {
    const double rim = d - 3, expect = std::sqrt(400 - rim * rim);
    EXPECT_NEAR(oh.max_over_disk({d, 0}, 3), expect, 0.02) << d;  // chord error of the tessellation
    EXPECT_LE(oh.max_over_disk({d, 0}, 3), expect + 1e-9) << "the mesh lies inside the sphere";
  }
}

// ---------------------------------------------------------------------------------------------
// The gouge replay of the written G-code.

struct GougeReport {
  long samples = 0, checked = 0, near = 0, violations = 0;
  double worst_depth = 0, worst_radial = 0;
  std::string first, worst;
  double min_z = 0;
};

/// Samples every feed move (G1/G2/G3; arcs on the circle, helices linear in Z) at ≤ step mm and,
/// at each sample, asserts that the surface under the flat end mill's disk (radius R − 0.001 mm:
/// the 4-decimal rounding of the program) stays at or below tool Z − stock_to_leave + tol.
/// `stock_top` converts G-code Z (0 = stock top) to the part frame. Also counts "near" samples:
/// where a disk 1 mm larger would reach material above the tool tip (the check is not vacuous).
GougeReport replay_against_mesh(const std::string& gcode, const ingest::Mesh& part, double stock_top, double R, double stl,
                                double safe_z, double step = 0.1, double tol = 0.005, bool include_rapids = false) {
  const auto rep = millnet::testing::replay_gcode(gcode, safe_z);
  TopOracle oracle(part);
  GougeReport g;
  g.min_z = rep.min_z;
  const double r = R - 0.001;
  auto check = [&](const Eigen::Vector2d& c, double z_gcode, int line) {
    ++g.samples;
    const double z_part = z_gcode + stock_top;
    const double allowed = z_part - stl + tol;  // the surface may reach up to here under the disk
    if (allowed - 1.0 >= oracle.zmax()) return;  // far above the whole part
    ++g.checked;
    if (oracle.max_over_disk(c, r + 1.0, allowed) > allowed) ++g.near;
    const double top = oracle.max_over_disk(c, r, allowed);
    if (!(top > allowed)) return;
    ++g.violations;
    const double depth = top - (z_part - stl);
    // Radial intrusion: the largest disk radius that stays clear, by bisection.
    double lo = 0, hi = r;
    if (oracle.max_over_disk(c, 0, allowed) > allowed) hi = lo = 0;
    for (int it = 0; it < 40 && hi - lo > 1e-5; ++it) {
      const double mid = 0.5 * (lo + hi);
      (oracle.max_over_disk(c, mid, allowed) > allowed ? hi : lo) = mid;
    }
    const double radial = r - lo;
    char buf[256];
    std::snprintf(buf, sizeof buf, "line %d: tool at (%.4f, %.4f) Z %.4f (part z %.4f, level Z %.3f): surface %.4f under the disk, "
                  "%.4f mm too deep, %.4f mm radially into the part",
                  line, c.x(), c.y(), z_gcode, z_part, z_gcode, top, depth, radial);
    if (g.first.empty()) g.first = buf;
    if (depth > g.worst_depth) {
      g.worst_depth = depth;
      g.worst = buf;
    }
    g.worst_radial = std::max(g.worst_radial, radial);
  };
  for (const auto& mv : rep.moves) {
    if (mv.g == 0 && !include_rapids) continue;
    const Eigen::Vector2d a(mv.from[0], mv.from[1]), b(mv.to[0], mv.to[1]);
    if (mv.g <= 1) {
      const double len = std::max((b - a).norm(), std::abs(mv.to[2] - mv.from[2]));
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        check(a + t * (b - a), mv.from[2] + t * (mv.to[2] - mv.from[2]), mv.line);
      }
      continue;
    }
    const Eigen::Vector2d c(mv.center[0], mv.center[1]);
    const double r0 = (a - c).norm(), r1 = (b - c).norm();
    const double a0 = std::atan2(a.y() - c.y(), a.x() - c.x()), a1 = std::atan2(b.y() - c.y(), b.x() - c.x());
    double sw = a1 - a0;
    if (mv.g == 3) {
      while (sw <= 1e-12) sw += 2 * kPi;
    } else {
      while (sw >= -1e-12) sw -= 2 * kPi;
    }
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sw) * std::max(r0, r1) / step)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n, ang = a0 + t * sw, rr = r0 + t * (r1 - r0);
      check(c + rr * Eigen::Vector2d(std::cos(ang), std::sin(ang)), mv.from[2] + t * (mv.to[2] - mv.from[2]), mv.line);
    }
  }
  return g;
}

struct GougeCase {
  datasets::Family family;
  int index;
  std::string planner;
  double stl;
};

std::string case_name(const testing::TestParamInfo<GougeCase>& info) {
  return datasets::family_name(info.param.family) + std::to_string(info.param.index) + "_" + info.param.planner + "_stl" + (info.param.stl > 0 ? "05" : "0");
}

class RoughGouge : public testing::TestWithParam<GougeCase> {};

TEST_P(RoughGouge, WrittenGcodeNeverCutsBelowTheMeshPlusStockToLeave) {
  const GougeCase gc = GetParam();
  // Seed 7, 45×45 top grid (~4k top triangles): fast, and the walls stay steep.
  const auto gen = datasets::make_part(gc.family, gc.index, 7, 45);
  const ingest::Mesh part = ingest::prepare(gen.mesh, {});
  const RoughParams p = params_for(gc.planner, gc.stl, 5);
  const RoughResult r = rough_mesh(part, p);
  ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
  const std::string stem = case_name(testing::TestParamInfo<GougeCase>(gc, 0));
  const auto dir = fresh_dir("rough_gouge_" + stem);
  const Json metrics = millnet::app::write_rough_outputs(dir, stem, r, p);
  const std::string gcode = slurp(dir / (stem + ".nc"));
  ASSERT_FALSE(gcode.empty());
  // The frame, computed independently of RoughResult: Z = 0 at the part's top + top allowance.
  const double stock_top = part.V.col(2).maxCoeff() + p.top_allowance_mm;
  const double R = p.cut.tool_diameter / 2;
  const GougeReport g = replay_against_mesh(gcode, part, stock_top, R, gc.stl, p.cut.safe_z);
  std::printf("[gouge %s] %s kind=%s, %zu levels, %ld samples (%ld near the part, %ld within 1 mm radially), min Z %.3f, "
              "violations %ld, worst depth %.4f mm, worst radial %.4f mm\n",
              stem.c_str(), datasets::family_name(gc.family).c_str(), gen.kind.c_str(), r.levels.size(), g.samples, g.checked,
              g.near, g.min_z, g.violations, g.worst_depth, g.worst_radial);
  if (g.violations) std::printf("  first: %s\n  worst: %s\n", g.first.c_str(), g.worst.c_str());
  EXPECT_EQ(g.violations, 0) << "first: " << g.first << "\nworst: " << g.worst;
  // Not vacuous: the program reaches the floor, and often comes within 1 mm of the material.
  EXPECT_NEAR(g.min_z, -(stock_top - p.floor_allowance_mm), 1e-3);
  EXPECT_GT(g.near, 100);
  std::printf("[gouge %s] planning %.2f s\n", stem.c_str(), r.planning_time_s);
  // The radial allowance as well (the planner keeps centres R + stock_to_leave off the islands).
  if (gc.stl > 0) {
    const GougeReport g2 = replay_against_mesh(gcode, part, stock_top, R + gc.stl, gc.stl, p.cut.safe_z);
    std::printf("[gouge %s] with radius R + stock_to_leave: violations %ld, worst depth %.4f, worst radial %.4f\n", stem.c_str(),
                g2.violations, g2.worst_depth, g2.worst_radial);
    EXPECT_EQ(g2.violations, 0) << "radial stock to leave not kept; first: " << g2.first << "\nworst: " << g2.worst;
  }
  // Rapids too: a G0 into material would be a crash.
  const GougeReport g0 = replay_against_mesh(gcode, part, stock_top, R, gc.stl, p.cut.safe_z, 0.1, 0.005, true);
  EXPECT_EQ(g0.violations, 0) << g0.first;
  // The metrics agree with the replay (independent parser).
  const auto rep = millnet::testing::replay_gcode(gcode, p.cut.safe_z);
  EXPECT_EQ(metrics["levels"].get<std::size_t>(), r.levels.size());
  EXPECT_NEAR(metrics["cut_length_mm"].get<double>(), rep.cut_length, 1e-3 * rep.cut_length + 0.5);
}

INSTANTIATE_TEST_SUITE_P(GeneratedParts, RoughGouge,
                         // Each part with both planners and both allowances, each planner with both
                         // allowances (a pairwise cover of the 2×2×2 grid, for time).
                         // (steep_plateaus index 0 with zigzag is left out: its planning takes ~6 min.)
                         testing::Values(GougeCase{datasets::Family::DeepCavity, 0, "som", 0.0},
                                         GougeCase{datasets::Family::DeepCavity, 0, "zigzag", 0.5},
                                         GougeCase{datasets::Family::SteepPlateaus, 1, "zigzag", 0.0},
                                         GougeCase{datasets::Family::SteepPlateaus, 0, "som", 0.5}),
                         case_name);

// ---------------------------------------------------------------------------------------------
// Outputs and the CLI.

TEST(RoughCli, BatchReportsTheBrokenMeshAndWritesTheGoodOnesOutputsInTheGcodeFrame) {
  const auto d = fresh_dir("rough_cli_batch");
  // The good part far from the origin, so that the frame contract (X/Y origin at the footprint's
  // lower-left after prepare, Z = 0 at the stock top) is exercised.
  const auto gen = datasets::make_part(datasets::Family::SteepPlateaus, 1, 7, 40);
  ingest::Mesh moved = gen.mesh;
  for (Eigen::Index i = 0; i < moved.V.rows(); ++i) moved.V.row(i) += Eigen::RowVector3d(250, -40, 13);
  ingest::save_stl_binary(moved, d / "good.stl");
  {
    std::ofstream f(d / "junk.stl", std::ios::binary);
    for (int i = 0; i < 1000; ++i) f.put(static_cast<char>((i * 7919) % 251));
  }
  const auto res = run_millnet("rough --mesh good.stl --mesh junk.stl --planner zigzag --stock-to-leave 0.5 --out o", d);
  EXPECT_EQ(res.code, 1) << res.err;
  EXPECT_NE(res.err.find("junk.stl"), std::string::npos) << res.err;
  EXPECT_EQ(res.err.find("good.stl"), std::string::npos) << res.err;
  const fs::path o = d / "o";
  ASSERT_TRUE(fs::exists(o / "good.nc")) << millnet::testing::list_files(o);
  EXPECT_FALSE(fs::exists(o / "junk.nc"));
  EXPECT_FALSE(fs::exists(o / "junk.metrics.json"));
  const Json summary = Json::parse(slurp(o / "rough_summary.json"));
  ASSERT_EQ(summary.size(), 2u);
  std::size_t errors = 0;
  for (const auto& s : summary)
    if (s["status"] == "error") {
      ++errors;
      EXPECT_EQ(s["part"], "junk");
      EXPECT_NE(s["error"].get<std::string>().find("junk.stl"), std::string::npos);
    } else {
      EXPECT_EQ(s["part"], "good");
    }
  EXPECT_EQ(errors, 1u);

  const Json m = Json::parse(slurp(o / "good.metrics.json"));
  EXPECT_EQ(m["status"], "ok");
  EXPECT_DOUBLE_EQ(m["stock_top_above_part_mm"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(m["stock_to_leave_mm"].get<double>(), 0.5);
  ASSERT_TRUE(m["per_level"].is_array());
  const std::size_t levels = m["levels"].get<std::size_t>();
  ASSERT_EQ(m["per_level"].size(), levels);
  const ingest::Mesh part = ingest::prepare(gen.mesh, {});
  const double part_top = part.V.col(2).maxCoeff();
  EXPECT_NEAR(m["stock"]["height_mm"].get<double>(), part_top + 1, 1e-4);  // STL is float32
  EXPECT_EQ(levels, static_cast<std::size_t>(std::ceil((part_top + 1) / 5 - 1e-9)));
  double prev = 0, cut_sum = 0;
  for (std::size_t k = 0; k < levels; ++k) {
    const Json& lv = m["per_level"][k];
    EXPECT_EQ(lv["level"].get<std::size_t>(), k + 1);
    EXPECT_LT(lv["z"].get<double>(), prev);
    EXPECT_LE(prev - lv["z"].get<double>(), 5 + 1e-9);
    prev = lv["z"].get<double>();
    for (const char* key : {"z_part_mm", "regions", "islands", "chains", "retractions", "cut_length_mm", "status"})
      EXPECT_TRUE(lv.contains(key)) << key;
    cut_sum += lv["cut_length_mm"].get<double>();
    const fs::path png = o / ("good.level_" + std::to_string(k + 1) + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
  }
  EXPECT_NEAR(prev, -(part_top + 1), 1e-4);  // the last level at the part's lowest point
  EXPECT_FALSE(fs::exists(o / ("good.level_" + std::to_string(levels + 1) + ".png")));
  EXPECT_NEAR(cut_sum, m["cut_length_mm"].get<double>(), 1e-6 * cut_sum + 1e-6);

  // The program is in the promised frame: replayed against the part as prepared (moved back to
  // the origin), it never gouges, and it reaches the floor.
  const std::string gcode = slurp(o / "good.nc");
  const GougeReport g = replay_against_mesh(gcode, part, part_top + 1, 5, 0.5, 5);
  EXPECT_EQ(g.violations, 0) << g.first;
  EXPECT_GT(g.near, 100);
  EXPECT_NEAR(g.min_z, -(part_top + 1), 1e-3);
  // …and the same program 1.5 mm off in X gouges: the check sees the frame.
  ingest::Mesh off = part;
  for (Eigen::Index i = 0; i < off.V.rows(); ++i) off.V(i, 0) += 1.5;
  const GougeReport bad = replay_against_mesh(gcode, off, part_top + 1, 5, 0.5, 5);
  EXPECT_GT(bad.violations, 0) << "a 1.5 mm frame error went unnoticed";
}

}  // namespace
