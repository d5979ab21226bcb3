// Mesh files: round trips, hand-written files in every format, messy STL, point clouds, errors.
#include "ingest/builders.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

#include <sys/stat.h>

using namespace millnet::ingest;
using namespace millnet::testing_ingest;
namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& p, const std::string& s) { millnet::write_file_atomic(p, s); }

// Expects load_mesh(p) to throw a millnet::Error whose message names the file and contains `what`.
void expect_load_error(const fs::path& p, const std::string& what) {
  try {
    (void)load_mesh(p);
    FAIL() << "no error for " << p;
  } catch (const millnet::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

// A binary STL by hand: `tris` are 9 floats each; normals all zero.
std::string binary_stl(const std::string& header, const std::vector<std::array<float, 9>>& tris) {
  std::string s(84 + 50 * tris.size(), '\0');
  std::memcpy(s.data(), header.data(), std::min<std::size_t>(80, header.size()));
  const auto n = static_cast<std::uint32_t>(tris.size());
  std::memcpy(s.data() + 80, &n, 4);
  for (std::size_t t = 0; t < tris.size(); ++t) std::memcpy(s.data() + 84 + 50 * t + 12, tris[t].data(), 36);
  return s;
}

// The three-triangle open tetrahedron corner used in the format tests: (0,0,0),(1,0,0),(0,2,0),(0,0,3).
void expect_tetra(const Mesh& m, std::size_t triangles) {
  EXPECT_EQ(static_cast<std::size_t>(m.F.rows()), triangles);
  EXPECT_EQ(m.V.rows(), 4);  // identical vertices joined
  const Box3 b = bounds(m);
  EXPECT_NEAR(b.max.x(), 1, 1e-6);
  EXPECT_NEAR(b.max.y(), 2, 1e-6);
  EXPECT_NEAR(b.max.z(), 3, 1e-6);
  EXPECT_NEAR(b.min.norm(), 0, 1e-6);
}

}  // namespace

TEST(MeshIO, BinaryStlRoundTrip) {
  TempDir dir;
  const Mesh m = append(box(0, 0, 0, 10.5, 20.25, 3), box(2, 2, 3, 4, 5, 7.75));
  save_stl_binary(m, dir / "part.stl");
  EXPECT_EQ(fs::file_size(dir / "part.stl"), 84u + 50u * 24u);
  MeshReport rep;
  const Mesh back = load_mesh(dir / "part.stl", &rep);
  EXPECT_EQ(rep.triangles, 24u);
  ASSERT_EQ(back.F.rows(), 24);
  EXPECT_EQ(back.V.rows(), 16);
  // Same triangles in the same order, bit for bit (all coordinates are exact in float).
  for (Eigen::Index t = 0; t < 24; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.V.row(back.F(t, k)), m.V.row(m.F(t, k)));
  EXPECT_EQ(sample_grid(back, 0.5, 15).h, sample_grid(m, 0.5, 15).h);
  // No temporary file left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(MeshIO, BinaryStlWithSolidHeaderZeroNormalsAndDuplicates) {
  TempDir dir;
  const std::array<float, 9> t0{0, 0, 0, 1, 0, 0, 0, 2, 0}, t1{0, 0, 0, 0, 0, 3, 1, 0, 0},
      t2{0, 0, 0, 0, 2, 0, 0, 0, 3};
  // 4 triangles (200 bytes) — the header claims "solid", which fools header-sniffing readers.
  write_text(dir / "solid.stl", binary_stl("solid part exported by some CAD", {t0, t1, t2, t0}));
  MeshReport rep;
  const Mesh m = load_mesh(dir / "solid.stl", &rep);
  expect_tetra(m, 4);
  EXPECT_EQ(rep.duplicate_triangles, 1u);
  bool noted_solid = false, noted_normals = false;
  for (const auto& n : rep.notes) {
    noted_solid |= n.find("starts with 'solid'") != std::string::npos;
    noted_normals |= n.find("4 stored facet normals are zero") != std::string::npos;
  }
  EXPECT_TRUE(noted_solid);
  EXPECT_TRUE(noted_normals);
}

TEST(MeshIO, HandWrittenAsciiStlObjPlyOff) {
  TempDir dir;
  write_text(
      dir / "a.stl",
      "solid corner\n"
      " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 2 0\n  endloop\n endfacet\n"
      " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 0 3\n   vertex 1 0 0\n  endloop\n endfacet\n"
      " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 2 0\n   vertex 0 0 3\n  endloop\n endfacet\n"
      "endsolid corner\n");
  expect_tetra(load_mesh(dir / "a.stl"), 3);
  // OBJ with a quad (triangulated) and a triangle.
  write_text(dir / "b.obj", "# corner\nv 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 0\nv 0 0 3\nf 1 2 3 4\nf 1 5 2\n");
  const Mesh obj = load_mesh(dir / "b.obj");
  EXPECT_EQ(obj.F.rows(), 3);
  EXPECT_NEAR(bounds(obj).max.z(), 3, 1e-6);
  write_text(dir / "c.ply",
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 2 0\n0 0 3\n3 0 1 2\n3 0 3 1\n3 0 2 3\n");
  expect_tetra(load_mesh(dir / "c.ply"), 3);
  write_text(dir / "d.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 2 0\n0 0 3\n3 0 1 2\n3 0 3 1\n3 0 2 3\n");
  expect_tetra(load_mesh(dir / "d.off"), 3);
}

TEST(MeshIO, UnitsAndUpAfterLoading) {
  TempDir dir;
  // A 2 × 1 inch plate, 0.5 inch thick, modelled with +Y up.
  Mesh m = box(0, 0, 0, 2, 0.5, 1);
  save_stl_binary(m, dir / "plate.stl");
  const Mesh p = prepare(load_mesh(dir / "plate.stl"), {Units::inch, Up::PosY, true});
  const Box3 b = bounds(p);
  EXPECT_NEAR(b.max.x(), 50.8, 1e-9);
  EXPECT_NEAR(b.max.y(), 25.4, 1e-9);  // the file's z (depth 1 inch) becomes y
  EXPECT_NEAR(b.max.z(), 12.7, 1e-9);  // the file's y (0.5 inch) becomes the height
}

TEST(MeshIO, PointCloudOnARasterAndScattered) {
  TempDir dir;
  // Regular raster 11×6 points, plane z = 1 + 0.5x + 0.2y, comma and blank separated, a comment.
  std::string grid = "# x y z\n";
  for (int i = 0; i <= 5; ++i)
    for (int j = 0; j <= 10; ++j)
      grid += std::to_string(j * 2.0) + (j % 2 ? ", " : " ") + std::to_string(i * 3.0) + " " +
              std::to_string(1 + 0.5 * j * 2.0 + 0.2 * i * 3.0) + "\n";
  write_text(dir / "raster.xyz", grid);
  const Mesh g = load_mesh(dir / "raster.xyz");
  EXPECT_EQ(g.F.rows(), 2 * 10 * 5);
  const Grid gg = sample_grid(g, 0.5, 15);
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c) EXPECT_NEAR(gg.h(r, c), 0.5 * 20.0 * c / 14 + 0.2 * 15.0 * r / 14, 1e-9);

  // Scattered points far from the origin with the 4 corners: any triangulation reproduces a plane.
  std::mt19937 rng(7);
  std::printf("seed 7\n");
  std::uniform_real_distribution<double> ux(0, 30), uy(0, 20);
  std::string cloud;
  char line[200];
  auto add = [&](double x, double y) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", 5e5 + x, 5e5 + y, 2 - 0.1 * x + 0.3 * y);
    cloud += line;
  };
  add(0, 0);
  add(30, 0);
  add(0, 20);
  add(30, 20);
  for (int k = 0; k < 400; ++k) add(ux(rng), uy(rng));
  write_text(dir / "scan.pts", cloud);
  const Mesh s = load_mesh(dir / "scan.pts");
  EXPECT_GT(s.F.rows(), 700);
  const HeightField f = rasterize_top(s, 0.5);
  for (int i = 0; i < f.ny; ++i)
    for (int j = 0; j < f.nx; ++j) {
      const double x = j * f.step_x, y = i * f.step_y;
      ASSERT_TRUE(f.hit[static_cast<std::size_t>(i * f.nx + j)]) << x << " " << y;
      ASSERT_NEAR(f.at(i, j), 2 - 0.1 * x + 0.3 * y, 1e-6);
    }
}

TEST(MeshIO, ErrorsNameTheFile) {
  TempDir dir;
  expect_load_error(dir / "missing.stl", "no such file");
  std::string garbage(1000, '\0');
  std::mt19937 rng(3);
  for (char& c : garbage) c = static_cast<char>(rng() & 0x7F);
  garbage[0] = 'x';
  write_text(dir / "garbage.stl", garbage);
  expect_load_error(dir / "garbage.stl", "not an STL file");
  write_text(dir / "empty.stl", binary_stl("empty", {}));
  expect_load_error(dir / "empty.stl", "no triangles");
  write_text(dir / "empty_ascii.stl", "solid nothing\nendsolid nothing\n");
  expect_load_error(dir / "empty_ascii.stl", "");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  write_text(dir / "nan.stl", binary_stl("nan", {{0, 0, 0, 1, 0, 0, 0, nan, 0}}));
  expect_load_error(dir / "nan.stl", "non-finite");
  write_text(dir / "model.foo", "whatever");
  expect_load_error(dir / "model.foo", "unknown mesh format '.foo'");
  write_text(dir / "bad.xyz", "1 2 3\n4 five 6\n");
  expect_load_error(dir / "bad.xyz", ":2: expected three numbers");
  write_text(dir / "nan.xyz", "1 2 3\n4 5 nan\n");
  expect_load_error(dir / "nan.xyz", ":2: non-finite");
  write_text(dir / "garbage.obj", "this is not an obj file at all \x01\x02\n");
  expect_load_error(dir / "garbage.obj", "");
  fs::create_directories(dir / "folder.stl");
  expect_load_error(dir / "folder.stl", "is a folder");
}

namespace {

// The cube of box() with its six sides as quads (fan (a,b,c),(a,c,d) = box()'s two triangles per side).
const std::array<std::array<int, 4>, 6> kCubeQuads = {
    {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};

Mesh cube_fans() {
  Mesh m = box(0, 0, 0, 10, 20, 5);
  m.F.resize(12, 3);
  for (int q = 0; q < 6; ++q) {
    const auto& v = kCubeQuads[static_cast<std::size_t>(q)];
    m.F.row(2 * q) << v[0], v[1], v[2];
    m.F.row(2 * q + 1) << v[0], v[2], v[3];
  }
  return m;
}

// Same triangles, same order, same corners (bit for bit), whatever the vertex numbering.
void expect_same_triangles(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.F.rows(), b.F.rows());
  for (Eigen::Index t = 0; t < a.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.V.row(a.F(t, k)), b.V.row(b.F(t, k))) << "triangle " << t;
}

template <class T>
void put(std::string& s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

// A binary PLY of cube_fans() with properties to skip: double x y z, float normals, uchar colour,
// an extra element between vertices and faces, a texture list before the indices, a flag after.
std::string binary_cube_ply(bool big) {
  const Mesh m = cube_fans();
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment made by hand\nelement vertex 8\nproperty double x\nproperty float nx\n"
                  "property double y\nproperty double z\nproperty uchar red\n"
                  "element material 2\nproperty list uchar float values\nproperty short id\n"
                  "element face 6\nproperty list uchar float texcoord\nproperty list uchar uint vertex_indices\n"
                  "property char flags\nend_header\n";
  for (Eigen::Index i = 0; i < 8; ++i) {
    put(s, m.V(i, 0), big);
    put(s, 0.5f, big);
    put(s, m.V(i, 1), big);
    put(s, m.V(i, 2), big);
    put(s, static_cast<unsigned char>(200), big);
  }
  for (int i = 0; i < 2; ++i) {
    put(s, static_cast<unsigned char>(i + 1), big);
    for (int j = 0; j <= i; ++j) put(s, 1.5f, big);
    put(s, static_cast<std::int16_t>(-7), big);
  }
  for (const auto& q : kCubeQuads) {
    put(s, static_cast<unsigned char>(2), big);
    put(s, 0.25f, big);
    put(s, 0.75f, big);
    put(s, static_cast<unsigned char>(4), big);
    for (int v : q) put(s, static_cast<std::uint32_t>(v), big);
    put(s, static_cast<char>(-1), big);
  }
  return s;
}

}  // namespace

// millnet's own PLY/OFF readers (issue 15): the same cube as quads in ASCII PLY, binary PLY (both
// endians, with properties and an element to skip) and OFF (comments, counts on the keyword line,
// a colour after a face) reads as the same triangles as its binary STL.
TEST(MeshIO, CubeInPlyAndOffReadsAsTheStlCube) {
  TempDir dir;
  const Mesh cube = cube_fans();
  save_stl_binary(cube, dir / "cube.stl");
  const Mesh stl = load_mesh(dir / "cube.stl");
  expect_same_triangles(stl, cube);

  std::string ascii =
      "ply\r\nformat ascii 1.0\r\nelement vertex 8\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nproperty uchar red\r\nelement face 6\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n";
  std::string off = "# a cube\nOFF 8 6 12\n";
  for (Eigen::Index i = 0; i < 8; ++i) {
    char line[100];
    std::snprintf(line, sizeof line, "%g %g %g", cube.V(i, 0), cube.V(i, 1), cube.V(i, 2));
    ascii += std::string(line) + " 255\r\n";
    off += std::string(line) + "  # vertex " + std::to_string(i) + "\n\n";
  }
  for (const auto& q : kCubeQuads) {
    const std::string f = "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
                          std::to_string(q[3]);
    ascii += f + "\r\n";
    off += f + " 0.5 0.5 0.5\n";
  }
  write_text(dir / "cube.ply", ascii);
  write_text(dir / "le.ply", binary_cube_ply(false));
  write_text(dir / "be.ply", binary_cube_ply(true));
  write_text(dir / "cube.off", off);
  for (const char* f : {"cube.ply", "le.ply", "be.ply", "cube.off"}) {
    SCOPED_TRACE(f);
    const Mesh m = load_mesh(dir / f);
    EXPECT_EQ(m.V.rows(), 8);
    expect_same_triangles(m, stl);
  }
  // Counts on their own line after the keyword, and no keyword at all (both allowed by OFF).
  write_text(dir / "own_line.off", "OFF\n# counts next\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  write_text(dir / "no_keyword.off", "4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  EXPECT_EQ(load_mesh(dir / "own_line.off").F.rows(), 2);
  EXPECT_EQ(load_mesh(dir / "no_keyword.off").F.rows(), 2);
}

// A path that is not a regular file is refused before it is opened (a FIFO would block the open,
// /dev/zero never ends).
TEST(MeshIO, NotARegularFileIsRefusedAtOnce) {
  TempDir dir;
  fs::create_symlink("/dev/zero", dir / "zero.stl");
  expect_load_error(dir / "zero.stl", "not a regular file");
  ASSERT_EQ(::mkfifo((dir / "pipe.ply").c_str(), 0600), 0);
  expect_load_error(dir / "pipe.ply", "not a regular file");
  EXPECT_THROW((void)millnet::read_file(dir / "pipe.ply"), millnet::Error);
}

// The format registry is the one list: every extension once, lower case with its dot; the folder
// list and the point-cloud list are derived from it.
TEST(MeshIO, TheFormatRegistryIsTheOneExtensionList) {
  std::vector<std::string> all, clouds;
  for (const MeshFormat& f : mesh_formats()) {
    EXPECT_FALSE(f.extensions.empty()) << f.name;
    EXPECT_NE(f.read, nullptr) << f.name;
    for (const std::string& e : f.extensions) {
      EXPECT_EQ(e.front(), '.') << e;
      EXPECT_TRUE(std::none_of(e.begin(), e.end(), [](char c) { return std::isupper(static_cast<unsigned char>(c)); }))
          << e;
      all.push_back(e);
      if (f.kind == MeshFormatKind::PointCloud) clouds.push_back(e);
    }
  }
  EXPECT_EQ(all, mesh_extensions());
  EXPECT_EQ(clouds, point_cloud_extensions());
  std::vector<std::string> sorted = all;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "an extension listed twice";
  for (const char* e : {".stl", ".obj", ".ply", ".off", ".3mf", ".xyz", ".step", ".igs"})
    EXPECT_NE(std::find(all.begin(), all.end(), e), all.end()) << e;
}
