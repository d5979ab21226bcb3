// Default training-part generator: determinism, closed meshes, and each family's geometric claim
// (README) measured on the mesh itself.
#include "millnet/core/atomic_file.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/datasets/rng.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

namespace fs = std::filesystem;
using namespace millnet::datasets;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct FacetStats {
  std::vector<double> slope_deg;  // per top facet
  std::vector<double> area;       // true area, mm²
  std::vector<double> proj_area;  // area projected on XY, mm²
};

// Slopes of the top-surface facets (the first 2(res−1)² faces, generator.hpp's layout). O(#F).
FacetStats top_facets(const GeneratedMesh& g) {
  FacetStats s;
  const auto n_top = static_cast<Eigen::Index>(2 * (g.res_x - 1) * (g.res_y - 1));
  for (Eigen::Index f = 0; f < n_top; ++f) {
    const Eigen::Vector3d p0 = g.mesh.V.row(g.mesh.F(f, 0)).transpose();
    const Eigen::Vector3d p1 = g.mesh.V.row(g.mesh.F(f, 1)).transpose();
    const Eigen::Vector3d p2 = g.mesh.V.row(g.mesh.F(f, 2)).transpose();
    const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
    const Eigen::Vector3d nrm(e1.y() * e2.z() - e1.z() * e2.y(), e1.z() * e2.x() - e1.x() * e2.z(),
                              e1.x() * e2.y() - e1.y() * e2.x());
    const double len = nrm.norm();
    s.area.push_back(len / 2);
    s.proj_area.push_back(std::abs(nrm.z()) / 2);
    s.slope_deg.push_back(std::acos(std::clamp(nrm.z() / len, -1.0, 1.0)) / kDeg);
  }
  return s;
}

double area_fraction(const FacetStats& s, const std::vector<double>& w, double lo_deg, double hi_deg) {
  double in = 0, all = 0;
  for (std::size_t k = 0; k < s.slope_deg.size(); ++k) {
    all += w[k];
    if (s.slope_deg[k] >= lo_deg && s.slope_deg[k] < hi_deg) in += w[k];
  }
  return in / all;
}

double top_z(const GeneratedMesh& g, int i, int j) { return g.mesh.V(static_cast<Eigen::Index>(i) * g.res_x + j, 2); }

constexpr int kPerFamily = 6;
constexpr std::uint64_t kSeed = 7;
constexpr int kRes = 110;

}  // namespace

TEST(SplitMix64, ReferenceSequence) {
  // First outputs for seed 0 (reference implementation by Vigna, splitmix64.c).
  SplitMix64 r(0);
  EXPECT_EQ(r.next(), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(r.next(), 0x6e789e6aa1b965f4ULL);
  EXPECT_EQ(r.next(), 0x06c45d188009454fULL);
  SplitMix64 u(42);
  for (int k = 0; k < 1000; ++k) {
    const double x = u.uniform(2.0, 3.0);
    ASSERT_GE(x, 2.0);
    ASSERT_LT(x, 3.0);
    const int i = u.uniform_int(-2, 2);
    ASSERT_GE(i, -2);
    ASSERT_LE(i, 2);
  }
}

TEST(Generator, SameSeedSameBytesDifferentSeedDifferentBytes) {
  const fs::path d1 = fs::temp_directory_path() / "millnet_test_gen_a";
  const fs::path d2 = fs::temp_directory_path() / "millnet_test_gen_b";
  const fs::path d3 = fs::temp_directory_path() / "millnet_test_gen_c";
  for (const auto& d : {d1, d2, d3}) fs::remove_all(d);
  const auto p1 = generate_default_parts(d1, {kSeed, 2, 40});
  const auto p2 = generate_default_parts(d2, {kSeed, 2, 40});
  const auto p3 = generate_default_parts(d3, {kSeed + 1, 2, 40});
  ASSERT_EQ(p1.size(), 10u);
  ASSERT_EQ(p3.size(), 10u);
  for (std::size_t k = 0; k < p1.size(); ++k) {
    EXPECT_EQ(p1[k].name, p2[k].name);
    EXPECT_EQ(p1[k].label, static_cast<int>(k / 2) + 1);
    const std::string a = millnet::read_file(p1[k].file), b = millnet::read_file(p2[k].file),
                      c = millnet::read_file(p3[k].file);
    EXPECT_EQ(a, b) << p1[k].name;
    EXPECT_NE(a, c) << p1[k].name;
    EXPECT_EQ(a.size(), 84u + 50u * 2u * 39u * 39u + 50u * 3u * 4u * 39u) << "binary STL of the documented size";
  }
  EXPECT_EQ(millnet::read_file(d1 / "parts.csv"), millnet::read_file(d2 / "parts.csv"));
  EXPECT_EQ(millnet::read_file(d1 / "parts.csv").substr(0, 64),
            "name,file,label\ns1_steep_plateaus_01,s1_steep_plateaus_01.stl,1\n");
  // A part does not depend on how many parts per family were asked for.
  EXPECT_EQ(make_part(Family::DeepCavity, 1, kSeed, 40).mesh.V, make_part(Family::DeepCavity, 1, kSeed, 40).mesh.V);
}

TEST(Generator, PartsAreClosedOrientedSolidsOfTheDocumentedSize) {
  for (int f = 1; f <= kFamilies; ++f)
    for (int k = 0; k < 2; ++k) {
      const GeneratedMesh g = make_part(static_cast<Family>(f), k, kSeed, kRes);
      SCOPED_TRACE(family_name(static_cast<Family>(f)) + " " + std::to_string(k));
      const auto nf = g.mesh.F.rows();
      EXPECT_GE(nf, 10000);
      EXPECT_LE(nf, 30000);
      // Every directed edge appears once and its reverse once: closed, manifold, consistently oriented.
      std::map<std::pair<int, int>, int> edges;
      double volume = 0;
      for (Eigen::Index t = 0; t < nf; ++t) {
        for (int e = 0; e < 3; ++e) ++edges[{g.mesh.F(t, e), g.mesh.F(t, (e + 1) % 3)}];
        const Eigen::Vector3d a = g.mesh.V.row(g.mesh.F(t, 0)).transpose(),
                              b = g.mesh.V.row(g.mesh.F(t, 1)).transpose(),
                              c = g.mesh.V.row(g.mesh.F(t, 2)).transpose();
        volume += a.dot(Eigen::Vector3d(b.y() * c.z() - b.z() * c.y(), b.z() * c.x() - b.x() * c.z(),
                                        b.x() * c.y() - b.y() * c.x())) /
                  6;
      }
      for (const auto& [e, count] : edges) {
        ASSERT_EQ(count, 1);
        ASSERT_EQ(edges.count({e.second, e.first}), 1u);
      }
      EXPECT_GT(volume, 0) << "outward normals";
      EXPECT_GE(g.a, 100);
      EXPECT_LE(g.a, 130);
      EXPECT_GE(g.b, 100);
      EXPECT_LE(g.b, 130);
      const double zmax = g.mesh.V.col(2).maxCoeff();
      EXPECT_GE(zmax, 10);
      EXPECT_LE(zmax, 60);
      EXPECT_EQ(g.mesh.V.col(2).minCoeff(), 0.0);
    }
}

TEST(Generator, SteepPlateausHaveFlatAreasAndSteepWalls) {
  for (int k = 0; k < kPerFamily; ++k) {
    const GeneratedMesh g = make_part(Family::SteepPlateaus, k, kSeed, kRes);
    const FacetStats s = top_facets(g);
    SCOPED_TRACE(g.kind + " " + std::to_string(k));
    EXPECT_GE(area_fraction(s, s.proj_area, 0, 1), 0.85) << "flat (< 1°) share of the footprint";
    EXPECT_GE(area_fraction(s, s.area, 70, 91), 0.10) << "steep (> 70°) share of the surface";
  }
}

TEST(Generator, GentleFreeFormIsCurvedAndNeverSteep) {
  for (int k = 0; k < kPerFamily; ++k) {
    const GeneratedMesh g = make_part(Family::GentleFreeForm, k, kSeed, kRes);
    const FacetStats s = top_facets(g);
    SCOPED_TRACE(g.kind + " " + std::to_string(k));
    EXPECT_LT(*std::max_element(s.slope_deg.begin(), s.slope_deg.end()), 30.0);
    // Curved, not a plane: the slope varies over the surface by more than 5°.
    const auto [lo, hi] = std::minmax_element(s.slope_deg.begin(), s.slope_deg.end());
    EXPECT_GT(*hi - *lo, 5.0);
    EXPECT_LT(area_fraction(s, s.proj_area, 0, 1), 0.2) << "little flat area";
  }
}

TEST(Generator, VaryingCurvatureRidgesGoFromSharpToFlat) {
  for (int k = 0; k < kPerFamily; ++k) {
    const GeneratedMesh g = make_part(Family::VaryingCurvature, k, kSeed, kRes);
    SCOPED_TRACE(g.kind + " " + std::to_string(k));
    // Crest curvature of every cross-section x = const (the ridge runs along x): −z_yy at the
    // highest point of the section, by second differences on the top grid.
    const double dy = g.b / (g.res_y - 1);
    double kmin = HUGE_VAL, kmax = 0;
    for (int j = 2; j < g.res_x - 2; ++j) {
      int best = 1;
      for (int i = 1; i < g.res_y - 1; ++i)
        if (top_z(g, i, j) > top_z(g, best, j)) best = i;
      const double kappa = -(top_z(g, best - 1, j) - 2 * top_z(g, best, j) + top_z(g, best + 1, j)) / (dy * dy);
      kmin = std::min(kmin, kappa);
      kmax = std::max(kmax, kappa);
    }
    EXPECT_GT(kmax, 1.0 / 2) << "a sharp end (crest radius < 2 mm)";
    EXPECT_LT(kmin, 1.0 / 10) << "a flat end (crest radius > 10 mm)";
    EXPECT_GT(kmax / std::max(kmin, 1e-9), 10.0) << "curvature varies along the ridge by > 10×";
  }
}

TEST(Generator, DeepCavitiesAreDeepWithSteepWalls) {
  for (int k = 0; k < kPerFamily; ++k) {
    const GeneratedMesh g = make_part(Family::DeepCavity, k, kSeed, kRes);
    const FacetStats s = top_facets(g);
    SCOPED_TRACE(g.kind + " " + std::to_string(k));
    const double rim = top_z(g, 0, 0);
    double floor = HUGE_VAL;
    for (int i = 0; i < g.res_y; ++i)
      for (int j = 0; j < g.res_x; ++j) floor = std::min(floor, top_z(g, i, j));
    EXPECT_GE(rim - floor, 24.0) << "cavity depth below the rim, mm";
    EXPECT_GE(area_fraction(s, s.area, 70, 91), 0.25) << "steep (> 70°) share of the surface";
  }
}

TEST(Generator, ShallowSlopesAreUniformAndShallow) {
  for (int k = 0; k < kPerFamily; ++k) {
    const GeneratedMesh g = make_part(Family::ShallowSlopes, k, kSeed, kRes);
    const FacetStats s = top_facets(g);
    SCOPED_TRACE(g.kind + " " + std::to_string(k));
    const auto [lo, hi] = std::minmax_element(s.slope_deg.begin(), s.slope_deg.end());
    EXPECT_GE(*lo, 7.9);
    EXPECT_LE(*hi, 14.1);
    EXPECT_LT(*hi - *lo, 1e-6) << "one uniform slope";
  }
}
