// Issue 5, roughing (rough/): Z-level regions of analytic solids (box on a plate, hemisphere on a
// plate) against their exact cross-sections, and a gouge replay of the program against the MESH
// TRIANGLES (exact maximum of the piecewise-linear surface under the tool disk), independent of the
// planner, the pocket module and the ingest z-buffer. The CLI batch contract is test_app's
// (tests/app/test_cli_rough.cpp).
#include "testing/program_text.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/mesh_gouge.hpp"

#include "millnet/core/error.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/ingest/zlevels.hpp"
#include "millnet/rough/rough.hpp"
#include "millnet/simulate/zmap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace {

using millnet::rough::Params;
using millnet::rough::Result;
using millnet::rough::rough_mesh;
using millnet::testing::GougeReport;
using millnet::testing::replay_against_mesh;
using millnet::testing::TopOracle;
namespace ingest = millnet::ingest;
namespace pocket = millnet::pocket;
namespace datasets = millnet::datasets;

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
         {{0, 2, 1},
          {1, 2, 3},  // bottom (−z)
          {4, 5, 6},
          {5, 7, 6},  // top (+z)
          {0, 1, 4},
          {1, 5, 4},  // −y
          {2, 6, 3},
          {3, 6, 7},  // +y
          {0, 4, 2},
          {2, 4, 6},  // −x
          {1, 3, 5},
          {3, 7, 5}});  // +x
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
      v.emplace_back(cx + r * std::cos(phi) * std::cos(th), cy + r * std::cos(phi) * std::sin(th),
                     zc + r * std::sin(phi));
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

/// Roughing parameters as the CLI builds them from the all-defaults config (configs/schema) and the
/// flags --planner, --stock-to-leave, --step-down.
Params params_for(const std::string& planner, double stock_to_leave, double step_down) {
  Params p;  // rough section: the schema's defaults
  p.cut.stock_to_leave = stock_to_leave;
  p.cut.step_down = step_down;
  if (planner == "som") {
    pocket::SomSpec s;
    s.frame.spacing = p.cut.stepover;
    s.som.seed = 7;  // the config's /seed
    p.planner = s;
  } else if (planner == "offset") {
    p.planner = pocket::OffsetSpec{};  // climb, the schema's default
  } else {
    pocket::ZigzagSpec z;
    z.zigzag.angle_deg = std::nullopt;              // "auto"
    z.zigzag.partition = pocket::PartitionKind::I;  // the schema's default
    p.planner = z;
  }
  return p;
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
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
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
/// contour overshoot of material_contours(), + another ½ diagonal because rough slices the
/// cell-max raster (a raster point is material when material touches its cell).
double contour_tolerance(const Result& r, const Params& p) {
  return p.contour_tolerance_mm + std::hypot(r.field.step_x, r.field.step_y) +
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
    Params p = params_for("som", stl, 5.1);
    p.flat_levels = false;  // the even split's slices (the flats' own levels: RoughFlats)
    // Stock top 30.3, 6 levels of 5.05 mm (25.25, 20.2, …, 5.05, 0): the first lies above the box
    // top but within 0.5 mm of it, so with stock_to_leave 0.5 the box is already an island there;
    // 5.05 lies just above the plate (with stock_to_leave 0 the plate is not yet material).
    p.top_allowance_mm = 5.3;
    const Result r = rough_mesh(m, p);
    ASSERT_EQ(r.levels.size(), 6u);
    EXPECT_DOUBLE_EQ(r.stock_top_part, 30.3);
    EXPECT_NEAR(r.stock_x0, -5, 1e-12);
    EXPECT_NEAR(r.stock_y1, 85, 1e-12);
    const double tol = contour_tolerance(r, p);
    std::printf("[box stl=%.1f] contour tolerance %.4f mm (raster %.4f × %.4f)\n", stl, tol, r.field.step_x,
                r.field.step_y);
    int box_levels = 0, empty_levels = 0;
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
      const auto& lv = r.levels[k];
      SCOPED_TRACE("level " + std::to_string(k + 1) + " z_part " + std::to_string(lv.z_part) + " stl " +
                   std::to_string(stl));
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
        for (const Eigen::Vector2d& q :
             {Eigen::Vector2d(bx0 + t * (bx1 - bx0), by0), Eigen::Vector2d(bx0 + t * (bx1 - bx0), by1),
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
      std::printf(
          "[box stl=%.1f] level %zu z_part %.3f: island area %.2f mm² (square %.2f), vertices %+.4f..%+.4f mm from the "
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
    const Params p = params_for("som", stl, 4);
    const Result r = rough_mesh(m, p);
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
        for (std::size_t i = 0; i < isl.size(); ++i)
          e = std::min(e, seg_dist({cx, cy}, isl[i], isl[(i + 1) % isl.size()]));
        return e;
      }();
      std::printf(
          "[hemisphere stl=%.1f] level %zu z_part %.3f: r %.3f, island radius mean %.4f (min vertex %.4f, max %.4f, "
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
  Params p = params_for("som", 0, 5);
  p.flat_levels = false;  // the box's top would get a level of its own (RoughFlats)
  const Result r = rough_mesh(m, p);
  ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
  ASSERT_EQ(r.levels.size(), 5u);
  ASSERT_EQ(r.machining.levels.size(), 5u) << "every level cuts";
  EXPECT_NEAR(r.machining.levels.back().z, -21.0, 1e-9);
  for (const auto& lv : r.machining.levels) EXPECT_GT(lv.path.cut_length(), 100.0) << lv.z;
  // The floor level's cutting moves run in the ring around the box, at ≥ R from it and never
  // farther out than a clearance beyond the stock edge. (How much of the ring next to the wall
  // is swept depends on the planner's grid: rough_mesh runs no contour pass.)
  const auto rep = millnet::testing::replay_gcode(millnet::testing::linuxcnc_text(r.machining.program), p.cut.safe_z);
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

TEST(RoughOracle, MatchesAnalyticMaximaOfABoxAndAHemisphere) {
  // The oracle itself must be right, or the gouge replay proves nothing.
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 100, 80, 5);
  add_box(m, 30, 20, 5, 60, 50, 25);
  TopOracle o(m);
  EXPECT_DOUBLE_EQ(o.max_over_disk({10, 10}, 5), 5.0);
  EXPECT_DOUBLE_EQ(o.max_over_disk({25.01, 35}, 5), 25.0);   // reaches 0.01 mm over the box wall
  EXPECT_DOUBLE_EQ(o.max_over_disk({24.99, 35}, 5), 5.0);    // stops 0.01 mm short of it
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

struct GougeCase {
  datasets::Family family;
  int index;
  std::string planner;
  double stl;
};

// Stable test names for ctest (gtest_discover_tests keeps the printed parameter in the name; the
// default printer dumps the bytes, the string's address among them).
void PrintTo(const GougeCase& c, std::ostream* os) {
  *os << datasets::family_name(c.family) << c.index << " " << c.planner << " stl " << c.stl;
}

std::string case_name(const testing::TestParamInfo<GougeCase>& info) {
  return datasets::family_name(info.param.family) + std::to_string(info.param.index) + "_" + info.param.planner +
         "_stl" + (info.param.stl > 0 ? "05" : "0");
}

class RoughGouge : public testing::TestWithParam<GougeCase> {};

TEST_P(RoughGouge, WrittenGcodeNeverCutsBelowTheMeshPlusStockToLeave) {
  const GougeCase gc = GetParam();
  // Seed 7, 45×45 top grid (~4k top triangles): fast, and the walls stay steep.
  const auto gen = datasets::make_part(gc.family, gc.index, 7, 45);
  const ingest::Mesh part = ingest::prepare(gen.mesh, {});
  Params p = params_for(gc.planner, gc.stl, 5);
  // Every planner as configured (the SOM tour with its wall rings). Until rough sliced the
  // cell-max raster (2026-11-25), steep_plateaus0 at stock to leave 0.5 came 0.0069 mm radially
  // into the allowance with the SOM and offset planners (21 samples, worst 0.0351 mm deep at
  // Z −8.517): point samples on a steep slope lie below material between them.
  const Result r = rough_mesh(part, p);
  ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
  const std::string stem = case_name(testing::TestParamInfo<GougeCase>(gc, 0));
  const std::string& gcode = millnet::testing::linuxcnc_text(r.machining.program);
  ASSERT_FALSE(gcode.empty());
  // The frame, computed independently of Result: Z = 0 at the part's top + top allowance.
  const double stock_top = part.V.col(2).maxCoeff() + p.top_allowance_mm;
  const double R = p.cut.tool.diameter / 2;
  const GougeReport g = replay_against_mesh(gcode, part, stock_top, R, gc.stl, p.cut.safe_z);
  std::printf(
      "[gouge %s] %s kind=%s, %zu levels, %ld samples (%ld near the part, %ld within 1 mm radially), min Z %.3f, "
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
    std::printf("[gouge %s] with radius R + stock_to_leave: violations %ld, worst depth %.4f, worst radial %.4f\n",
                stem.c_str(), g2.violations, g2.worst_depth, g2.worst_radial);
    EXPECT_EQ(g2.violations, 0) << "radial stock to leave not kept; first: " << g2.first << "\nworst: " << g2.worst;
  }
  // Rapids too: a G0 into material would be a crash.
  const GougeReport g0 = replay_against_mesh(gcode, part, stock_top, R, gc.stl, p.cut.safe_z, 0.1, 0.005, true);
  EXPECT_EQ(g0.violations, 0) << g0.first;
  // The metrics agree with the replay (independent parser).
  const auto rep = millnet::testing::replay_gcode(gcode, p.cut.safe_z);
  double level_cut = 0;
  for (const auto& s : millnet::rough::level_summaries(r)) level_cut += s.cut_length_mm;
  EXPECT_NEAR(r.machining.metrics.cut_length_mm, rep.cut_length, 1e-3 * rep.cut_length + 0.5);
  EXPECT_NEAR(level_cut, r.machining.metrics.cut_length_mm, 1e-6 * level_cut + 1e-6);
}

INSTANTIATE_TEST_SUITE_P(GeneratedParts, RoughGouge,
                         // Each part with the planners and both allowances, each planner with both
                         // allowances (a pairwise cover of the 2×2×2 grid, for time).
                         // (steep_plateaus index 0 with zigzag is left out: its planning takes ~6 min.)
                         testing::Values(GougeCase{datasets::Family::DeepCavity, 0, "som", 0.0},
                                         GougeCase{datasets::Family::DeepCavity, 0, "zigzag", 0.5},
                                         GougeCase{datasets::Family::SteepPlateaus, 1, "zigzag", 0.0},
                                         GougeCase{datasets::Family::SteepPlateaus, 0, "som", 0.5},
                                         GougeCase{datasets::Family::SteepPlateaus, 0, "offset", 0.5},
                                         GougeCase{datasets::Family::DeepCavity, 0, "offset", 0.5},
                                         GougeCase{datasets::Family::SteepPlateaus, 1, "offset", 0.0}),
                         case_name);

}  // namespace

// Issue 42 §7: --step-down 0.01 planned 2,100 levels, each within its own estimate and the run
// unbounded. The levels × the stock outline's estimates are checked before the first level: here
// 2,100 × the feed map's 82 × 72 cells, refused under a limit that one level (5,904 cells) keeps.
TEST(RoughWork, TheLevelsTogetherAreEstimatedBeforeTheFirst) {
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 40, 30, 20);
  Params p = params_for("offset", 0, 0.01);
  p.limits.max_work = 1e6;
  try {
    (void)rough_mesh(m, p);
    ADD_FAILURE() << "not refused";
  } catch (const millnet::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("2100 Z levels (step_down 0.01 mm over 21 mm of stock) × feed_grid 1 mm over a 70 × 60 mm "
                        "pocket makes 1.2e7 feed-map cells"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("the limit is 1.0e6 (--max-work, /limits/max_work)"), std::string::npos) << what;
  }
  p = params_for("offset", 0, 5);
  p.limits.max_work = 1e6;
  EXPECT_EQ(rough_mesh(m, p).machining.status, pocket::PlanStatus::Ok);
}

// Issue 38: a floor between two step-down levels kept a step (1.29 mm here) instead of the
// allowance. A cavity 30 × 30 mm with its floor at z 12 in a 60 × 60 × 30 block: stock top 31,
// seven step-down levels of 31/7 = 4.43 mm (… 13.29, 8.86 …) straddle the floor. The program is
// machined on an independent z-map (simulate::machine, exact sweeps): with flat levels every floor
// cell the Ø10 tool reaches keeps the 0.5 mm allowance within 0.01 mm, never less; without them
// (the old behaviour, flat_levels false) the floor keeps 13.29 − 12 = 1.29 mm.
TEST(RoughFlats, ACavityFloorBetweenTwoLevelsKeepsTheAllowance) {
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 60, 15, 30);  // the block around the cavity: four walls …
  add_box(m, 0, 45, 0, 60, 60, 30);
  add_box(m, 0, 15, 0, 15, 45, 30);
  add_box(m, 45, 15, 0, 60, 45, 30);
  add_box(m, 15, 15, 0, 45, 45, 12);  // … and the cavity's floor
  const std::vector<millnet::rough::Flat> flats = millnet::rough::flat_areas(m, 0.1, 1);
  ASSERT_EQ(flats.size(), 2u);
  EXPECT_DOUBLE_EQ(flats[0].z, 30);
  EXPECT_NEAR(flats[0].area_mm2, 60 * 60 - 30 * 30, 1e-9);
  EXPECT_DOUBLE_EQ(flats[1].z, 12);
  EXPECT_NEAR(flats[1].area_mm2, 30 * 30, 1e-9);
  EXPECT_TRUE(millnet::rough::flat_areas(m, 0.1, 901).size() == 1u) << "the floor is smaller than 901 mm²";

  const double stl = 0.5, floor_z = 12;
  for (const bool flat_levels : {true, false}) {
    SCOPED_TRACE(flat_levels ? "flat levels" : "step-down levels only");
    Params p = params_for("offset", stl, 5);
    p.flat_levels = flat_levels;
    const Result r = rough_mesh(m, p);
    ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
    // 7 step-down levels, + the top face's and the floor's levels at 30.502 and 12.502.
    ASSERT_EQ(r.levels.size(), flat_levels ? 9u : 7u);
    int flat_count = 0;
    for (const auto& lv : r.levels)
      if (!std::isnan(lv.flat_z_part)) {
        ++flat_count;
        EXPECT_NEAR(lv.z_part, lv.flat_z_part + stl + millnet::rough::kFlatClearanceMm, 1e-12);
      }
    EXPECT_EQ(flat_count, flat_levels ? 2 : 0);
    for (std::size_t k = 1; k < r.levels.size(); ++k)
      EXPECT_LE(r.levels[k - 1].z_part - r.levels[k].z_part, p.cut.step_down + 1e-9) << "no level cuts deeper";

    // The cavity machined on a 0.1 mm z-map (program frame: Z 0 = stock top 31).
    millnet::simulate::GridSpec g;
    g.x0 = 15, g.y0 = 15, g.cell = 0.1, g.nx = 300, g.ny = 300;
    millnet::simulate::ZMap z = millnet::simulate::ZMap::flat(g, 0);
    (void)millnet::simulate::machine(z, r.machining.program, p.cut.tool);
    double lo = 1e9, hi = -1e9;
    std::size_t cells = 0;
    for (std::size_t iy = 0; iy < g.ny; ++iy)
      for (std::size_t ix = 0; ix < g.nx; ++ix) {
        const double x = g.x(ix), y = g.y(iy);
        // Where the Ø10 tool's bottom reaches: within its radius of the square of centres 5.5 mm
        // (radius + stock to leave) + 0.5 mm (the islands grow by the contour tolerance + a raster
        // diagonal: 0.40 mm) inside the walls.
        const double cx = std::clamp(x, 21.0, 39.0), cy = std::clamp(y, 21.0, 39.0);
        if (std::hypot(x - cx, y - cy) > 5) continue;
        const double left = z.at(ix, iy) + 31 - floor_z;
        lo = std::min(lo, left);
        hi = std::max(hi, left);
        ++cells;
      }
    std::printf("[flats %d] %zu floor cells: left %.4f … %.4f mm\n", flat_levels, cells, lo, hi);
    EXPECT_GT(cells, 75000u);
    if (flat_levels) {
      EXPECT_GE(lo, stl - 1e-9) << "into the allowance";
      EXPECT_LE(hi, stl + 0.01);
    } else {
      EXPECT_NEAR(lo, 31 - 4 * 31.0 / 7 - floor_z, 1e-6) << "the step-down level 13.29 over the floor";
    }
  }
}

// A flat's level clears only the regions that hold the flat: the cavity floor's level (12.502) has
// the cavity alone, not the margin ring around the block that the next step-down level clears
// anyway; everywhere (the stop-47 behaviour) it has both, and the roughing is longer for it.
TEST(RoughFlats, AFlatsLevelClearsOnlyTheRegionsThatHoldTheFlat) {
  ingest::Mesh m;
  add_box(m, 0, 0, 0, 60, 15, 30);
  add_box(m, 0, 45, 0, 60, 60, 30);
  add_box(m, 0, 15, 0, 15, 45, 30);
  add_box(m, 45, 15, 0, 60, 45, 30);
  add_box(m, 15, 15, 0, 45, 45, 12);
  const std::vector<millnet::rough::Flat> flats = millnet::rough::flat_areas(m, 0.1, 1);
  ASSERT_EQ(flats.size(), 2u);
  for (const Eigen::Vector2d& q : flats[1].samples) {  // the floor's faces: on the cavity's floor
    EXPECT_GE(q.x(), 15);
    EXPECT_LE(q.x(), 45);
    EXPECT_GE(q.y(), 15);
    EXPECT_LE(q.y(), 45);
  }
  double cut[2] = {0, 0};
  for (const bool everywhere : {false, true}) {
    SCOPED_TRACE(everywhere ? "everywhere" : "where the flat is");
    Params p = params_for("offset", 0.5, 5);
    p.flat_levels_everywhere = everywhere;
    const Result r = rough_mesh(m, p);
    ASSERT_EQ(r.machining.status, pocket::PlanStatus::Ok) << r.machining.message;
    std::size_t floor_levels = 0;
    for (const auto& lv : r.levels) {
      if (lv.flat_z_part != 12) continue;
      ++floor_levels;
      ASSERT_EQ(lv.regions.size(), everywhere ? 2u : 1u);
      // The kept region is the cavity (its outline within the block's inner walls).
      const auto& b = lv.regions.back().boundary;
      for (const auto& v : b) {
        EXPECT_GE(v.x, 15 - 1e-6);
        EXPECT_LE(v.x, 45 + 1e-6);
      }
    }
    EXPECT_EQ(floor_levels, 1u);
    cut[everywhere ? 1 : 0] = r.machining.metrics.cut_length_mm;
  }
  // The margin ring around the 60 × 60 block at one more level: about its perimeter's passes.
  EXPECT_LT(cut[0], cut[1] - 200) << cut[0] << " vs " << cut[1];
}
