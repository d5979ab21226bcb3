// Mesh validation and preparation: units, up axes (explicit and auto), recentring, counts.
#include "ingest/builders.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/mesh.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace millnet::ingest;
using namespace millnet::testing_ingest;

namespace {

// A mould-like part: 80×60 block with a flat base at z = 0 and a free-form top (bump + slope).
Mesh mould_part() {
  return solid(
      [](double x, double y) {
        return 20 + 8 * std::exp(-((x - 30) * (x - 30) + (y - 35) * (y - 35)) / 150) + 0.05 * x;
      },
      0, 80, 0, 60, 40, 30);
}

// Rotate so that the part's +Z ends up along the file axis `up` (the inverse of prepare's turn).
Mesh turned_to(const Mesh& m, Up up) {
  Mesh r = m;
  r.V = m.V * up_rotation(up);  // v_file = Rᵀ·v  ⇔  row·R
  return r;
}

}  // namespace

TEST(Mesh, ParseUnitsAndUp) {
  EXPECT_EQ(parse_units("mm"), Units::mm);
  EXPECT_EQ(parse_units("Inch"), Units::inch);
  EXPECT_EQ(parse_units("in"), Units::inch);
  EXPECT_EQ(parse_units("m"), Units::m);
  EXPECT_EQ(units_to_mm(Units::inch), 25.4);
  EXPECT_EQ(units_to_mm(Units::m), 1000.0);
  try {
    (void)parse_units("cm");
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("cm"), std::string::npos);
  }
  for (Up u : {Up::PosZ, Up::NegZ, Up::PosY, Up::NegY, Up::PosX, Up::NegX, Up::Auto})
    EXPECT_EQ(parse_up(to_string(u)), u);
  EXPECT_EQ(parse_up("Z"), Up::PosZ);
  EXPECT_THROW((void)parse_up("up"), millnet::Error);
}

TEST(Mesh, UpRotationsAreProperAndMapTheAxisToZ) {
  const std::pair<Up, Eigen::Vector3d> cases[] = {{Up::PosZ, {0, 0, 1}}, {Up::NegZ, {0, 0, -1}},
                                                  {Up::PosY, {0, 1, 0}}, {Up::NegY, {0, -1, 0}},
                                                  {Up::PosX, {1, 0, 0}}, {Up::NegX, {-1, 0, 0}}};
  for (const auto& [up, axis] : cases) {
    const Eigen::Matrix3d r = up_rotation(up);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-15) << to_string(up);
    EXPECT_TRUE((r * r.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-15));
    EXPECT_TRUE((r * axis).isApprox(Eigen::Vector3d(0, 0, 1), 1e-15)) << to_string(up);
  }
  EXPECT_THROW((void)up_rotation(Up::Auto), millnet::Error);
}

TEST(Mesh, PrepareUndoesEveryUpAxisAndRecentres) {
  const Mesh part = mould_part();
  const Mesh ref = prepare(part, {});
  for (Up up : {Up::NegZ, Up::PosY, Up::NegY, Up::PosX, Up::NegX}) {
    const Mesh file = turned_to(part, up);
    MeshReport rep;
    const Mesh got = prepare(file, {Units::mm, up, true}, &rep);
    EXPECT_EQ(rep.up_used, up);
    EXPECT_LT((got.V - ref.V).cwiseAbs().maxCoeff(), 1e-12) << to_string(up);
  }
  const Box3 b = bounds(ref);
  EXPECT_EQ(b.min, Eigen::Vector3d::Zero());
  EXPECT_NEAR(b.max.x(), 80, 1e-12);
  EXPECT_NEAR(b.max.y(), 60, 1e-12);
}

TEST(Mesh, AutoUpFindsTheWorkingFaceTurnedAlongPlusY) {
  const Mesh part = mould_part();
  const Grid ref = sample_grid(prepare(part, {}), 1.0, 15);
  for (Up up : {Up::PosY, Up::NegY, Up::PosX, Up::NegX, Up::NegZ, Up::PosZ}) {
    MeshReport rep;
    const Mesh got = prepare(turned_to(part, up), {Units::mm, Up::Auto, true}, &rep);
    EXPECT_EQ(rep.up_used, up) << "expected " << to_string(up) << ", chose " << to_string(rep.up_used);
    const Grid g = sample_grid(got, 1.0, 15);
    EXPECT_LT((g.h - ref.h).cwiseAbs().maxCoeff(), 1e-9) << to_string(up);
  }
}

TEST(Mesh, AutoUpTallCoreAndOpenSurface) {
  // A tall core (30×30, 100 high, domed top) stands on its small base: side walls are flat at
  // both ends and must not win.
  const Mesh core =
      solid([](double x, double y) { return 100 + 3 * std::sin(x / 5) * std::cos(y / 7); }, 0, 30, 0, 30, 15, 15);
  EXPECT_EQ(choose_up(turned_to(core, Up::NegX)), Up::NegX);
  EXPECT_EQ(choose_up(core), Up::PosZ);
  // An open surface (no base) facing +X: the side with the most area facing it.
  const Mesh sheet = surface([](double x, double y) { return std::sin(x / 9) + 0.1 * y; }, 0, 50, 0, 40, 10, 10);
  EXPECT_EQ(choose_up(turned_to(sheet, Up::PosX)), Up::PosX);
  EXPECT_EQ(choose_up(sheet, Up::NegY), Up::NegY);  // explicit values pass through
}

TEST(Mesh, UnitsScaleAndFarFromOriginSamplesIdentically) {
  const Mesh part = mould_part();
  Mesh inch = part;
  inch.V /= 25.4;
  const Mesh a = prepare(inch, {Units::inch, Up::PosZ, true});
  EXPECT_LT((a.V - prepare(part, {}).V).cwiseAbs().maxCoeff(), 1e-11);
  Mesh metres = part;
  metres.V /= 1000;
  EXPECT_NEAR(bounds(prepare(metres, {Units::m, Up::PosZ, true})).max.x(), 80, 1e-11);

  // 1e6 mm away: recentring in double gives the same grid (coordinates here are exact binary
  // fractions, so even the bits agree).
  const Mesh box_part = append(box(0, 0, 0, 40, 30, 5), box(10.25, 5.5, 5, 20.75, 25, 12.125));
  Mesh far = box_part;
  far.V.rowwise() += Eigen::RowVector3d(1e6, -1e6, 1e6);
  MeshReport rep;
  const Mesh prepared = prepare(far, {}, &rep);
  EXPECT_EQ(rep.recentred_by, Eigen::Vector3d(1e6, -1e6, 1e6));
  const Grid g_far = sample_grid(prepared, 0.5, 15), g_ref = sample_grid(box_part, 0.5, 15);
  EXPECT_EQ(g_far.h, g_ref.h);
  // Even without recentring the rasterizer works in offsets from the footprint corner.
  const Grid g_raw = sample_grid(far, 0.5, 15);
  EXPECT_LT((g_raw.h - g_ref.h).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Mesh, ValidateCountsDefectsAndRejectsBadInput) {
  const Mesh b = box(0, 0, 0, 1, 2, 3);
  MeshReport clean;
  validate(b, "box", &clean);
  EXPECT_EQ(clean.triangles, 12u);
  EXPECT_EQ(clean.boundary_edges, 0u);
  EXPECT_EQ(clean.non_manifold_edges, 0u);
  EXPECT_EQ(clean.duplicate_triangles, 0u);
  EXPECT_EQ(clean.degenerate_triangles, 0u);

  // One triangle removed: a crack with 3 boundary edges.
  Mesh cracked = b;
  cracked.F.conservativeResize(11, 3);
  MeshReport r1;
  validate(cracked, "cracked", &r1);
  EXPECT_EQ(r1.boundary_edges, 3u);
  // One triangle repeated (reversed winding): duplicate, its 3 edges now non-manifold.
  Mesh dup = b;
  dup.F.conservativeResize(13, 3);
  dup.F.row(12) << b.F(0, 2), b.F(0, 1), b.F(0, 0);
  MeshReport r2;
  validate(dup, "dup", &r2);
  EXPECT_EQ(r2.duplicate_triangles, 1u);
  EXPECT_EQ(r2.non_manifold_edges, 3u);
  // A zero-area triangle on collinear points.
  Mesh degen = b;
  degen.V.conservativeResize(11, 3);
  degen.V.bottomRows(3) << 5, 5, 5, 6, 6, 6, 7, 7, 7;
  degen.F.conservativeResize(13, 3);
  degen.F.row(12) << 8, 9, 10;
  MeshReport r3;
  validate(degen, "degen", &r3);
  EXPECT_EQ(r3.degenerate_triangles, 1u);
  // Only that triangle: nothing with an area is left, refused (issue 42 §8), with or without a report.
  Mesh flat;
  flat.V = degen.V.bottomRows(3);
  flat.F.resize(1, 3);
  flat.F << 0, 1, 2;
  try {
    validate(flat, "flat");
    ADD_FAILURE() << "a mesh of one collinear triangle was accepted";
  } catch (const millnet::Error& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "flat: every triangle has zero area (1 triangles of collinear or coincident vertices), expected a surface");
  }

  Mesh nan = b;
  nan.V(3, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    validate(nan, "part.stl");
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("part.stl"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos);
  }
  Mesh bad_index = b;
  bad_index.F(4, 2) = 8;
  EXPECT_THROW(validate(bad_index, "x"), millnet::Error);
  try {
    validate(Mesh{}, "empty.obj");
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty.obj: no triangles"), std::string::npos);
  }
}
