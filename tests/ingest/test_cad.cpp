// Issue 16 §1: STEP and IGES parts in. The parts are built here with Open CASCADE (a block with a
// spherical dome and a cylindrical pocket, an assembly of two blocks), written as STEP (mm and inch)
// and IGES, and read back through millnet's loader; the height grid the pipeline uses is compared
// with the analytic heights.
#if MILLNET_HAVE_CAD

#include "app/cli_runner.hpp"
#include "testing/linuxcnc.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRep_Builder.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>

#include <gtest/gtest.h>

#include <map>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <algorithm>

namespace {

namespace fs = std::filesystem;
namespace ingest = millnet::ingest;
using millnet::testing::fresh_dir;
using millnet::testing::list_files;
using millnet::testing::run_millnet;
using millnet::testing::slurp;

// The part, mm: block [0,40]×[0,30]×[0,10]; dome = sphere (12,15,4) R 8 above z = 10 (rim radius
// √28 ≈ 5.29, top z = 12); pocket = cylinder (30,15) R 5 from z = 4 up (floor z = 4).
constexpr double kDomeX = 12, kDomeY = 15, kDomeZ = 4, kDomeR = 8;
constexpr double kPocketX = 30, kPocketY = 15, kPocketR = 5, kPocketFloor = 4;

TopoDS_Shape dome_pocket_block() {
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 40, 30, 10).Shape();
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(kDomeX, kDomeY, kDomeZ), kDomeR).Shape();
  const TopoDS_Shape upper = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 5), 40, 30, 20).Shape();
  const TopoDS_Shape dome = BRepAlgoAPI_Common(sphere, upper).Shape();
  const TopoDS_Shape fused = BRepAlgoAPI_Fuse(block, dome).Shape();
  const TopoDS_Shape cyl =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(kPocketX, kPocketY, kPocketFloor), gp_Dir(0, 0, 1)), kPocketR, 20).Shape();
  return BRepAlgoAPI_Cut(fused, cyl).Shape();
}

// Analytic top height at (x, y), and the distance to the nearest height discontinuity (the pocket
// rim) or kink (the dome rim), where a raster point may sit on either side.
double analytic_height(double x, double y, double* edge_distance) {
  const double rd = std::hypot(x - kDomeX, y - kDomeY), rp = std::hypot(x - kPocketX, y - kPocketY);
  const double dome_rim = std::sqrt(kDomeR * kDomeR - (10 - kDomeZ) * (10 - kDomeZ));
  *edge_distance = std::min({std::abs(rd - dome_rim), std::abs(rp - kPocketR), x, 40 - x, y, 30 - y});
  if (rd < dome_rim) return kDomeZ + std::sqrt(kDomeR * kDomeR - rd * rd);
  if (rp < kPocketR) return kPocketFloor;
  return 10;
}

// Open CASCADE 7.6's writer labels the file with write.step.unit but writes the session's numbers
// unchanged, so an inch file is written from the part scaled by 1/25.4 (the test checks the numbers).
void write_step(const TopoDS_Shape& part, const fs::path& file, const char* unit) {
  TopoDS_Shape shape = part;
  if (std::string(unit) == "INCH") {
    gp_Trsf t;
    t.SetScale(gp_Pnt(0, 0, 0), 1 / 25.4);
    shape = BRepBuilderAPI_Transform(part, t, Standard_True).Shape();
  }
  STEPControl_Writer w;
  Interface_Static::SetCVal("write.step.unit", unit);
  ASSERT_EQ(w.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
  ASSERT_EQ(w.Write(file.string().c_str()), IFSelect_RetDone);
  Interface_Static::SetCVal("write.step.unit", "MM");
}

// Raster at 0.25 mm: heights at raster points are exact on the facets (rasterize_top), so away from
// the rims the only error is the tessellation's chord (facets lie inside the sphere) plus the
// file's printed precision. Returns the largest |z − analytic| over points ≥ 0.3 mm from a rim.
double max_height_error(const ingest::Mesh& m, int* compared) {
  const ingest::HeightField f = ingest::rasterize_top(m, 0.25);
  double worst = 0;
  *compared = 0;
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      double edge = 0;
      const double want = analytic_height(f.x0 + j * f.step_x, f.y0 + i * f.step_y, &edge);
      if (edge < 0.3) continue;
      worst = std::max(worst, std::abs(f.at(i, j) - want));
      ++*compared;
    }
  return worst;
}

// The pipeline's 15×15 model grid (heights above the lowest point, bilinear in the raster): its
// error adds the raster's interpolation, s²/8·(|h_xx| + |h_yy|) ≤ 0.25²/8 · 2 · 0.30 ≈ 0.0047 mm on
// the dome (|h''| ≤ R²/(R² − r²)^{3/2} = 0.30 /mm at the rim), to the chord tolerance.
double max_grid_error(const ingest::Mesh& m) {
  const ingest::Grid g = ingest::sample_grid(m, 0.25, 15);
  double worst = 0;
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c) {
      double edge = 0;
      const double want = analytic_height(c * 40.0 / 14, r * 30.0 / 14, &edge);
      if (edge < 0.3) continue;
      worst = std::max(worst, std::abs(g.h(r, c) - want));
    }
  return worst;
}

ingest::Mesh load(const fs::path& p, ingest::MeshReport* rep, const ingest::CadOptions& cad = {}) {
  ingest::PrepareOptions o;
  o.cad = cad;
  return ingest::load_prepared(p, o, rep);
}

// One millnet::Error naming the file, on one line.
std::string load_error(const fs::path& p, const ingest::CadOptions& cad = {}) {
  try {
    ingest::MeshReport rep;
    (void)load(p, &rep, cad);
  } catch (const millnet::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(p.string()), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    return what;
  }
  ADD_FAILURE() << p << ": no error";
  return {};
}

TEST(Cad, StepInMillimetresMatchesTheAnalyticHeightsWithinTheChordTolerance) {
  const auto d = fresh_dir("cad_step_mm");
  write_step(dome_pocket_block(), d / "part.step", "MM");
  ingest::MeshReport rep;
  const ingest::Mesh m = load(d / "part.step", &rep);
  ASSERT_TRUE(rep.is_cad);
  EXPECT_EQ(rep.cad.format, "STEP");
  EXPECT_EQ(rep.cad.file_unit, "mm");
  EXPECT_DOUBLE_EQ(rep.cad.chord_tolerance_mm, 0.005);
  EXPECT_EQ(rep.cad.bodies.size(), 1U);
  EXPECT_EQ(rep.boundary_edges, 0U) << "a closed solid tessellates into a closed mesh";
  const ingest::Box3 b = ingest::bounds(m);
  EXPECT_NEAR(b.max.x(), 40, 1e-6);
  EXPECT_NEAR(b.max.y(), 30, 1e-6);
  EXPECT_NEAR(b.max.z(), 12, 0.005 + 1e-6);  // dome top
  int n = 0;
  EXPECT_LE(max_height_error(m, &n), 0.005 + 1e-5);
  EXPECT_GT(n, 15000);
  EXPECT_LE(max_grid_error(m), 0.005 + 0.0047 + 1e-5);
}

// Issue 38: every triangle knows its B-rep face, and faces keep their names, over the pipe from
// the reader's process as in this one (tests/app/data/pocket_block.step: a 60 × 40 × 20 block with
// a 30 × 20 pocket 12 deep, its ADVANCED_FACEs named "top", "pocket wall" ×4, "pocket floor").
TEST(Cad, TrianglesKnowTheirFaceAndFacesTheirNames) {
  const fs::path step = fs::path(MILLNET_SOURCE_DIR) / "tests/app/data/pocket_block.step";
  for (const bool isolate : {true, false}) {
    ingest::CadOptions cad;
    cad.isolate = isolate;
    ingest::MeshReport rep;
    const ingest::Mesh m = load(step, &rep, cad);
    ASSERT_TRUE(rep.is_cad);
    ASSERT_EQ(rep.cad.faces, 11U);
    ASSERT_EQ(rep.cad.face_names.size(), 11U);
    ASSERT_EQ(rep.cad.triangle_face.size(), static_cast<std::size_t>(m.F.rows()));
    std::map<std::string, int> names;
    for (const std::string& n : rep.cad.face_names) ++names[n];
    EXPECT_EQ(names["top"], 1);
    EXPECT_EQ(names["pocket wall"], 4);
    EXPECT_EQ(names["pocket floor"], 1);
    EXPECT_EQ(names[""], 5);
    // Each named face's triangles lie on its plane (the block's frame: recentring moves nothing here).
    std::map<int, int> per_face;
    for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
      const int f = rep.cad.triangle_face[static_cast<std::size_t>(t)];
      ASSERT_GE(f, 1);
      ASSERT_LE(f, 11);
      ++per_face[f];
      const std::string& name = rep.cad.face_names[static_cast<std::size_t>(f - 1)];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d v = m.V.row(m.F(t, k));
        if (name == "pocket floor") {
          EXPECT_NEAR(v.z(), 8, 1e-9);
          EXPECT_GE(v.x(), 15 - 1e-9);
          EXPECT_LE(v.x(), 45 + 1e-9);
        }
        if (name == "top") EXPECT_NEAR(v.z(), 20, 1e-9);
        if (name == "pocket wall")
          EXPECT_TRUE(std::abs(v.x() - 15) < 1e-9 || std::abs(v.x() - 45) < 1e-9 || std::abs(v.y() - 10) < 1e-9 ||
                      std::abs(v.y() - 30) < 1e-9);
      }
    }
    EXPECT_EQ(per_face.size(), 11U);  // every face has triangles
  }
}

TEST(Cad, StepInInchReadsBackInMillimetres) {
  const auto d = fresh_dir("cad_step_inch");
  write_step(dome_pocket_block(), d / "part_in.stp", "INCH");
  const std::string text = slurp(d / "part_in.stp");
  EXPECT_NE(text.find("INCH"), std::string::npos) << "the file states inch";
  EXPECT_NE(text.find("1.57480"), std::string::npos) << "and holds inch numbers (40 mm = 1.5748 in)";
  ingest::MeshReport rep;
  const ingest::Mesh m = load(d / "part_in.stp", &rep);
  EXPECT_EQ(rep.cad.file_unit, "inch");
  EXPECT_DOUBLE_EQ(rep.cad.file_unit_mm, 25.4);
  EXPECT_FALSE(rep.cad.units_overridden);
  EXPECT_NEAR(ingest::bounds(m).max.x(), 40, 1e-5);
  int n = 0;
  EXPECT_LE(max_height_error(m, &n), 0.005 + 1e-5);
  EXPECT_LE(max_grid_error(m), 0.005 + 0.0047 + 1e-5);

  // --units mm on an inch file: its numbers are read as mm (40 mm → 40/25.4), with a note.
  ingest::PrepareOptions o;
  o.units = ingest::Units::mm;
  o.units_explicit = true;
  ingest::MeshReport r2;
  const ingest::Mesh small = ingest::load_prepared(d / "part_in.stp", o, &r2);
  EXPECT_NEAR(ingest::bounds(small).max.x(), 40 / 25.4, 1e-6);
  EXPECT_TRUE(r2.cad.units_overridden);
  EXPECT_NE(r2.cad.units_note.find("inch"), std::string::npos) << r2.cad.units_note;
  // --units inch agrees with the file: nothing changes, no note.
  o.units = ingest::Units::inch;
  ingest::MeshReport r3;
  EXPECT_NEAR(ingest::bounds(ingest::load_prepared(d / "part_in.stp", o, &r3)).max.x(), 40, 1e-5);
  EXPECT_TRUE(r3.cad.units_note.empty());
}

TEST(Cad, CoarserChordToleranceGivesFewerTrianglesAndLargerButBoundedError) {
  const auto d = fresh_dir("cad_chord");
  write_step(dome_pocket_block(), d / "part.step", "MM");
  ingest::MeshReport fine, coarse;
  const ingest::Mesh a = load(d / "part.step", &fine);
  const ingest::Mesh b = load(d / "part.step", &coarse, {0.1, 0.5, ""});
  EXPECT_LT(b.F.rows(), a.F.rows());
  int n = 0;
  const double err = max_height_error(b, &n);
  EXPECT_GT(err, 0.005) << "0.1 mm chords must show on the dome";
  EXPECT_LE(err, 0.1 + 1e-5);
  // Deterministic: the same file read twice gives the same triangles.
  const ingest::Mesh again = load(d / "part.step", &fine);
  EXPECT_TRUE(again.V == a.V && again.F == a.F);
}

TEST(Cad, IgesRoundTrip) {
  const auto d = fresh_dir("cad_iges");
  IGESControl_Controller::Init();
  IGESControl_Writer w("MM", 1);  // 1: B-rep faces (entities 186/514/510)
  ASSERT_TRUE(w.AddShape(dome_pocket_block()));
  w.ComputeModel();
  ASSERT_TRUE(w.Write((d / "part.igs").string().c_str()));
  ingest::MeshReport rep;
  const ingest::Mesh m = load(d / "part.igs", &rep);
  EXPECT_EQ(rep.cad.format, "IGES");
  EXPECT_EQ(rep.cad.file_unit, "mm");
  EXPECT_NEAR(ingest::bounds(m).max.x(), 40, 1e-5);
  int n = 0;
  EXPECT_LE(max_height_error(m, &n), 0.005 + 1e-5);
  EXPECT_GT(n, 15000);
}

TEST(Cad, AssemblyTakesEveryBodyOrOneByIndexAndListsThemForAnUnknownName) {
  const auto d = fresh_dir("cad_assembly");
  TopoDS_Compound two;
  BRep_Builder bb;
  bb.MakeCompound(two);
  bb.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 5).Shape());
  bb.Add(two, BRepPrimAPI_MakeBox(gp_Pnt(20, 0, 0), 10, 12, 8).Shape());
  write_step(two, d / "two.step", "MM");
  ingest::MeshReport all;
  const ingest::Box3 b_all = ingest::bounds(load(d / "two.step", &all));
  EXPECT_EQ(all.cad.bodies.size(), 2U);
  EXPECT_NEAR(b_all.max.x(), 30, 1e-9);
  EXPECT_NEAR(b_all.max.z(), 8, 1e-9);
  ingest::MeshReport second;
  const ingest::Box3 b2 = ingest::bounds(load(d / "two.step", &second, {0.005, 0.2, "2"}));
  EXPECT_NEAR(b2.max.x(), 10, 1e-9);  // recentred: the second box alone
  EXPECT_NEAR(b2.max.y(), 12, 1e-9);
  EXPECT_NEAR(b2.max.z(), 8, 1e-9);
  EXPECT_EQ(second.cad.body, "2");
  const ingest::Box3 b1 = ingest::bounds(load(d / "two.step", &second, {0.005, 0.2, "1"}));
  EXPECT_NEAR(b1.max.z(), 5, 1e-9);
  // By name (unnamed solids are "body N").
  EXPECT_NEAR(ingest::bounds(load(d / "two.step", &second, {0.005, 0.2, all.cad.bodies[1]})).max.z(), 8, 1e-9);
  const std::string unknown = load_error(d / "two.step", {0.005, 0.2, "no such body"});
  EXPECT_NE(unknown.find("no body named \"no such body\""), std::string::npos) << unknown;
  EXPECT_NE(unknown.find(all.cad.bodies[0]), std::string::npos) << unknown;
  EXPECT_NE(unknown.find(all.cad.bodies[1]), std::string::npos) << unknown;
  EXPECT_NE(load_error(d / "two.step", {0.005, 0.2, "3"}).find("no body 3"), std::string::npos);

  // CLI: --body 2 roughs the second block only (its footprint is the stock's).
  const auto r = run_millnet("sample --mesh two.step --body 2 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("10 × 12 mm"), std::string::npos) << r.err;
}

TEST(Cad, CorruptTruncatedAndEmptyFilesGiveOneClearLine) {
  const auto d = fresh_dir("cad_bad");
  write_step(dome_pocket_block(), d / "part.step", "MM");
  const std::string good = slurp(d / "part.step");
  {
    std::ofstream(d / "cut.step", std::ios::binary) << good.substr(0, good.size() / 2);
    std::string bad = good;
    // Garble the data section: every '(' of its middle third becomes '#'.
    for (std::size_t i = bad.size() / 3; i < 2 * bad.size() / 3; ++i)
      if (bad[i] == '(') bad[i] = '#';
    std::ofstream(d / "corrupt.step", std::ios::binary) << bad;
    std::ofstream(d / "junk.stp", std::ios::binary) << "this is not a STEP file\n";
    std::ofstream(d / "junk.igs", std::ios::binary) << "this is not an IGES file\n";
  }
  EXPECT_NE(load_error(d / "cut.step").find("truncated STEP file"), std::string::npos);
  EXPECT_NE(load_error(d / "junk.stp").find("not a STEP file"), std::string::npos);
  EXPECT_NE(load_error(d / "junk.igs").find("not an IGES file"), std::string::npos);
  const std::string corrupt = load_error(d / "corrupt.step");
  EXPECT_FALSE(corrupt.empty());
  // A file holding only a vertex: no solid, shell or face.
  write_step(BRepBuilderAPI_MakeVertex(gp_Pnt(1, 2, 3)).Shape(), d / "point.step", "MM");
  EXPECT_NE(load_error(d / "point.step").find("no solid, shell or face"), std::string::npos);

  // The CLI: exit 1, one line on stderr naming the file, nothing on stdout, nothing written.
  for (const char* f : {"cut.step", "corrupt.step", "point.step"}) {
    const auto r = run_millnet(std::string("rough --mesh ") + f + " --out o_" + f, d);
    EXPECT_EQ(r.code, 1) << f;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(f), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(list_files(d / (std::string("o_") + f)), "") << f;
  }
}

TEST(Cad, RoughOnAStepPartWritesAProgramRs274AcceptsAndTheCadMetrics) {
  const auto d = fresh_dir("cad_rough_cli");
  write_step(dome_pocket_block(), d / "part.step", "INCH");
  const auto r = run_millnet("rough --mesh part.step --tool-diameter 6 --planner zigzag --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(d / "o" / "part.nc"));
  const auto metrics = nlohmann::json::parse(slurp(d / "o" / "part.metrics.json"));
  ASSERT_TRUE(metrics.contains("cad")) << metrics.dump();
  EXPECT_EQ(metrics["cad"]["file_unit"], "inch");
  EXPECT_EQ(metrics["cad"]["chord_tolerance_mm"], 0.005);
  EXPECT_EQ(metrics["cad"]["angular_deflection_rad"], 0.2);
  EXPECT_NEAR(metrics["stock"]["x1"].get<double>() - metrics["stock"]["x0"].get<double>(), 40 + 2 * 5, 1e-6)
      << "the stock spans the part in mm plus 2 × /rough/margin_mm (5), not 40/25.4";
  if (fs::exists("/usr/bin/rs274")) {
    EXPECT_EQ(millnet::testing::linuxcnc_status((d / "o" / "part.nc").string()), 0);
  }
  // --units mm contradicts the inch file: one note on stderr, not an error.
  const auto s = run_millnet("sample --mesh part.step --units mm --raster 0.1 --out s", d);
  EXPECT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.err.find("note: "), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("inch"), std::string::npos) << s.err;
}

// "Done means" of issue 16: `millnet predict … part.step` ranks a STEP part with its unit read from
// the file, exactly as it ranks the same part given as a mesh (millnet's own tessellation of it
// saved as binary STL: floats instead of doubles, so the probabilities agree to 1e-3).
TEST(Cad, PredictRanksAStepPartAsTheSameMeshInStl) {
  const auto d = fresh_dir("cad_predict_cli");
  write_step(dome_pocket_block(), d / "part.step", "MM");
  ingest::MeshReport rep;
  ingest::save_stl_binary(load(d / "part.step", &rep), d / "same.stl");
  std::ofstream(d / "c.json") << R"({
  "seed": 7,
  "dataset": {
    "parts_dir": "parts",
    "generate": {"seed": 11, "per_family": 1, "resolution": 40},
    "augment": {"angles_deg": [-10, 0, 10], "axes": ["x"], "flip": false}
  },
  "predict": {"augment": {"angles_deg": [0, 10], "axes": ["z"], "flip": false}}
})";
  ASSERT_EQ(run_millnet("dataset --config c.json --quiet --out D", d).code, 0);
  const auto t = run_millnet("train --dataset D/vectors.csv --config c.json --quiet --out M", d);
  ASSERT_EQ(t.code, 0) << t.err;
  const auto r = run_millnet("predict --model M --config c.json --quiet --out P part.step same.stl", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto pred = nlohmann::json::parse(slurp(d / "P" / "predictions.json"));
  std::map<std::string, nlohmann::json> by;
  for (const auto& p : pred["parts"]) by[p["part"].get<std::string>()] = p;
  ASSERT_TRUE(by.count("part") && by.count("same")) << pred.dump().substr(0, 400);
  EXPECT_EQ(by["part"]["status"], "ok");
  EXPECT_EQ(by["same"]["status"], "ok");
  ASSERT_TRUE(by["part"].contains("cad"));
  EXPECT_EQ(by["part"]["cad"]["file_unit"], "mm");
  EXPECT_FALSE(by["same"].contains("cad"));
  EXPECT_EQ(by["part"]["top"], by["same"]["top"]);
  const auto& a = by["part"]["ranking"];
  const auto& b = by["same"]["ranking"];
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k]["slot"], b[k]["slot"]);
    EXPECT_NEAR(a[k]["probability"].get<double>(), b[k]["probability"].get<double>(), 1e-3);
  }
}

}  // namespace

#endif  // MILLNET_HAVE_CAD
