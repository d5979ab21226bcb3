#pragma once
// Meshes built in code for the ingest/augment tests (no files needed).
#include "millnet/ingest/mesh.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <array>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

namespace millnet::testing_ingest {

using ingest::Mesh;

/// Open surface z = f(x, y) on an (nx+1)×(ny+1) vertex grid over [x0,x1]×[y0,y1], CCW from +Z.
inline Mesh surface(const std::function<double(double, double)>& f, double x0, double x1, double y0, double y1, int nx,
                    int ny) {
  Mesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int i = 0; i <= ny; ++i)
    for (int j = 0; j <= nx; ++j) {
      const double x = x0 + (x1 - x0) * j / nx, y = y0 + (y1 - y0) * i / ny;
      m.V.row(i * (nx + 1) + j) << x, y, f(x, y);
    }
  m.F.resize(2 * nx * ny, 3);
  int t = 0;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j) {
      const int a = i * (nx + 1) + j, b = a + 1, c = a + nx + 1, d = c + 1;
      m.F.row(t++) << a, b, d;
      m.F.row(t++) << a, d, c;
    }
  return m;
}

/// Closed solid: the surface z = f on top, a flat base at z = base, side walls. Manifold.
inline Mesh solid(const std::function<double(double, double)>& f, double x0, double x1, double y0, double y1, int nx,
                  int ny, double base = 0) {
  const Mesh top = surface(f, x0, x1, y0, y1, nx, ny);
  const auto nv = top.V.rows();
  Mesh m;
  m.V.resize(2 * nv, 3);
  m.V.topRows(nv) = top.V;
  m.V.bottomRows(nv) = top.V;
  m.V.bottomRows(nv).col(2).setConstant(base);
  std::vector<std::array<int, 3>> F;
  for (Eigen::Index k = 0; k < top.F.rows(); ++k) {
    F.push_back({top.F(k, 0), top.F(k, 1), top.F(k, 2)});
    F.push_back(
        {top.F(k, 0) + static_cast<int>(nv), top.F(k, 2) + static_cast<int>(nv), top.F(k, 1) + static_cast<int>(nv)});
  }
  // Boundary loop, CCW seen from +Z.
  std::vector<int> loop;
  for (int j = 0; j < nx; ++j) loop.push_back(j);
  for (int i = 0; i < ny; ++i) loop.push_back(i * (nx + 1) + nx);
  for (int j = nx; j > 0; --j) loop.push_back(ny * (nx + 1) + j);
  for (int i = ny; i > 0; --i) loop.push_back(i * (nx + 1));
  const int n = static_cast<int>(loop.size());
  for (int k = 0; k < n; ++k) {
    const int a = loop[static_cast<std::size_t>(k)], b = loop[static_cast<std::size_t>((k + 1) % n)];
    const int ab = a + static_cast<int>(nv), bb = b + static_cast<int>(nv);
    F.push_back({a, ab, bb});  // outward facing wall
    F.push_back({a, bb, b});
  }
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t k = 0; k < F.size(); ++k) m.F.row(static_cast<Eigen::Index>(k)) << F[k][0], F[k][1], F[k][2];
  return m;
}

/// Axis-aligned closed box (12 triangles, outward CCW).
inline Mesh box(double x0, double y0, double z0, double x1, double y1, double z1) {
  Mesh m;
  m.V.resize(8, 3);
  for (int k = 0; k < 8; ++k) m.V.row(k) << ((k & 1) ? x1 : x0), ((k & 2) ? y1 : y0), ((k & 4) ? z1 : z0);
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3,  // bottom (−z)
      4, 5, 6, 5, 7, 6,     // top (+z)
      0, 1, 4, 1, 5, 4,     // −y
      2, 6, 3, 3, 6, 7,     // +y
      0, 4, 2, 2, 4, 6,     // −x
      1, 3, 5, 3, 7, 5;     // +x
  return m;
}

inline Mesh append(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F.topRows(a.F.rows()) = a.F;
  m.F.bottomRows(b.F.rows()) = b.F.array() + static_cast<std::int32_t>(a.V.rows());
  return m;
}

/// A per-test temporary folder, removed afterwards.
class TempDir {
public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("millnet_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
  std::filesystem::path path_;
};

}  // namespace millnet::testing_ingest
