// The tool-shop library (issue 39 §2): the fillet profile by hand, determinism, closed solids of the
// documented size and relief, and each family's geometric claim measured on the mesh.
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/shop_parts.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using namespace millnet::datasets;

namespace {

constexpr std::uint64_t kSeed = 7;
constexpr int kPerFamily = 6;  // parts checked per family

// Largest facet slope (degrees) of the top grid's two triangles per cell, per cell (rows = y).
Eigen::MatrixXd cell_slopes(const GeneratedMesh& g) {
  const Eigen::MatrixXd z = top_heights(g);
  const double dx = g.a / (g.res_x - 1), dy = g.b / (g.res_y - 1);
  Eigen::MatrixXd s(g.res_y - 1, g.res_x - 1);
  for (Eigen::Index i = 0; i + 1 < z.rows(); ++i)
    for (Eigen::Index j = 0; j + 1 < z.cols(); ++j) {
      const double gx = std::max(std::abs(z(i, j + 1) - z(i, j)), std::abs(z(i + 1, j + 1) - z(i + 1, j))) / dx;
      const double gy = std::max(std::abs(z(i + 1, j) - z(i, j)), std::abs(z(i + 1, j + 1) - z(i, j + 1))) / dy;
      s(i, j) = std::atan(std::hypot(gx, gy)) * 180 / std::numbers::pi;
    }
  return s;
}

double share(const Eigen::MatrixXd& m, double lo, double hi) {
  return static_cast<double>((m.array() >= lo && m.array() < hi).count()) / static_cast<double>(m.size());
}

// Connected groups (4-neighbour) of cells where `in` holds. O(cells).
int components(const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& in) {
  Eigen::MatrixXi seen = Eigen::MatrixXi::Zero(in.rows(), in.cols());
  int n = 0;
  for (Eigen::Index i = 0; i < in.rows(); ++i)
    for (Eigen::Index j = 0; j < in.cols(); ++j) {
      if (!in(i, j) || seen(i, j)) continue;
      ++n;
      std::vector<std::pair<Eigen::Index, Eigen::Index>> stack{{i, j}};
      seen(i, j) = 1;
      while (!stack.empty()) {
        const auto [r, c] = stack.back();
        stack.pop_back();
        const std::pair<Eigen::Index, Eigen::Index> next[] = {{r + 1, c}, {r - 1, c}, {r, c + 1}, {r, c - 1}};
        for (const auto& [rr, cc] : next)
          if (rr >= 0 && cc >= 0 && rr < in.rows() && cc < in.cols() && in(rr, cc) && !seen(rr, cc)) {
            seen(rr, cc) = 1;
            stack.emplace_back(rr, cc);
          }
      }
    }
  return n;
}

GeneratedMesh part(ShopFamily f, int i) { return make_shop_part(static_cast<int>(f) + i * kShopFamilies, kSeed); }

}  // namespace

TEST(ShopParts, FilletedStepMatchesTheHandComputedProfile) {
  // h 10, draft 45° (wall at 45°: slope 1, run 10), both radii 2: tangent length t = 2 tan 22.5°.
  const double t = 2 * std::tan(std::numbers::pi / 8), c = std::sqrt(0.5);
  EXPECT_DOUBLE_EQ(detail::filleted_step(-t, 10, 45, 2, 2), 0.0);
  EXPECT_NEAR(detail::filleted_step(0, 10, 45, 2, 2), 2 - std::sqrt(4 - t * t), 1e-12);        // on the foot fillet
  EXPECT_NEAR(detail::filleted_step(t * c, 10, 45, 2, 2), t * c, 1e-12);                       // its tangent point
  EXPECT_NEAR(detail::filleted_step(5, 10, 45, 2, 2), 5, 1e-12);                               // the straight wall
  EXPECT_NEAR(detail::filleted_step(10, 10, 45, 2, 2), 10 - 2 + std::sqrt(4 - t * t), 1e-12);  // top fillet
  EXPECT_DOUBLE_EQ(detail::filleted_step(10 + t, 10, 45, 2, 2), 10.0);
  EXPECT_DOUBLE_EQ(detail::filleted_step(50, 10, 45, 2, 2), 10.0);
  // Monotone, within [0, h], and tangent-continuous at both fillets' tangent points, for drafts
  // 0.5–60° and radii that must shrink to fit (h 1 with radii 10).
  for (const double draft : {0.5, 3.0, 20.0, 60.0})
    for (const auto& c : {std::tuple{10.0, 2.0, 1.0}, std::tuple{1.0, 10.0, 10.0}, std::tuple{5.0, 0.0, 3.0}}) {
      const double h = std::get<0>(c), r1 = std::get<1>(c), r2 = std::get<2>(c);  // a lambda captures them below
      const auto z = [&](double d) { return detail::filleted_step(d, h, draft, r1, r2); };
      const double phi = (90 - draft) * std::numbers::pi / 180, run = h / std::tan(phi);
      double prev = 0;
      for (double d = -r1 - 1; d <= run + r2 + 1; d += 1e-3) {
        ASSERT_GE(z(d), prev - 1e-12) << draft << " " << h << " at " << d;
        ASSERT_LE(z(d), h + 1e-12);
        prev = z(d);
      }
      EXPECT_DOUBLE_EQ(z(run + r2 + 1), h);
      if (r1 == 0) continue;
      // One-sided slopes on either side of the tangent points agree (the shrunk radii: the wall's
      // length h / sin φ shared in proportion).
      const double half = std::tan(phi / 2), len = h / std::sin(phi);
      const double shrink = std::min(1.0, len / ((r1 + r2) * half));
      const double t1 = r1 * half * shrink, t2 = r2 * half * shrink, cos_phi = std::cos(phi), e = 1e-7;
      for (const double at : {t1 * cos_phi, run - t2 * cos_phi}) {
        const double left = (z(at) - z(at - e)) / e, right = (z(at + e) - z(at)) / e;
        EXPECT_NEAR(left, right, 1e-3 * std::max(1.0, right)) << draft << " " << h << " at " << at;
      }
    }
}

TEST(ShopParts, SameSeedSameBytesAndALibraryIsThePrefixOfALargerOne) {
  const fs::path dir = fs::temp_directory_path() / "millnet_test_shop_parts";
  fs::remove_all(dir);
  const auto small = generate_shop_parts(dir / "a", kSeed, 9);
  const auto large = generate_shop_parts(dir / "b", kSeed, 12);
  const auto other = generate_shop_parts(dir / "c", kSeed + 1, 9);
  ASSERT_EQ(small.size(), 9u);
  ASSERT_EQ(large.size(), 12u);
  for (std::size_t k = 0; k < small.size(); ++k) {
    EXPECT_EQ(small[k].name, large[k].name);
    EXPECT_EQ(small[k].label, 0);
    EXPECT_EQ(millnet::read_file(small[k].file), millnet::read_file(large[k].file)) << small[k].name;
    EXPECT_NE(millnet::read_file(small[k].file), millnet::read_file(other[k].file)) << small[k].name;
  }
  EXPECT_EQ(small[0].name, "shop_0001_cavity");
  EXPECT_EQ(small[8].name, "shop_0009_cavity");
  EXPECT_EQ(large[7].name, "shop_0008_terraced_core");
  EXPECT_EQ(millnet::read_file(dir / "a" / "parts.csv").substr(0, 49),
            "name,file,label\nshop_0001_cavity,shop_0001_cavity");
  fs::remove_all(dir);
  EXPECT_THROW((void)make_shop_part(-1, kSeed), millnet::Error);
  EXPECT_THROW((void)make_shop_part(0, kSeed, 0.0), millnet::Error);
}

TEST(ShopParts, PartsAreClosedSolidsOfTheDocumentedSizeAndRelief) {
  std::set<std::string> kinds;
  for (int k = 0; k < kShopFamilies * kPerFamily; ++k) {
    const GeneratedMesh g = make_shop_part(k, kSeed);
    kinds.insert(g.kind);
    EXPECT_GE(g.a, kShopSideMinMm);
    EXPECT_LE(g.a, kShopSideMaxMm);
    EXPECT_GE(g.b, kShopSideMinMm);
    EXPECT_LE(g.b, kShopSideMaxMm);
    EXPECT_LE(std::max(g.a, g.b) / std::min(g.a, g.b), 1.8 + 1e-12);
    EXPECT_NEAR(g.a / (g.res_x - 1), 0.8, 0.8 / (g.res_x - 1)) << k;  // the requested spacing
    const Eigen::MatrixXd z = top_heights(g);
    EXPECT_GE(z.minCoeff(), 5.0 - 1e-9) << k;  // the plinth under the lowest point
    EXPECT_LE(z.maxCoeff() - z.minCoeff(), kShopMaxReliefMm) << k << " " << g.kind;
    EXPECT_GT(z.maxCoeff() - z.minCoeff(), 2.0) << k << " " << g.kind;  // never a plain block
    // Every directed edge once and its reverse once: closed, manifold, consistently oriented.
    std::map<std::pair<int, int>, int> edges;
    for (Eigen::Index t = 0; t < g.mesh.F.rows(); ++t)
      for (int e = 0; e < 3; ++e) ++edges[{g.mesh.F(t, e), g.mesh.F(t, (e + 1) % 3)}];
    for (const auto& [e, count] : edges) {
      ASSERT_EQ(count, 1) << k;
      ASSERT_EQ(edges.count({e.second, e.first}), 1u) << k;
    }
    // Volume by the divergence theorem = the top's integral over the footprint (trapezoidal, exact
    // for the piecewise-linear top): outward normals.
    double vol = 0;
    for (Eigen::Index t = 0; t < g.mesh.F.rows(); ++t) {
      const Eigen::Vector3d p0 = g.mesh.V.row(g.mesh.F(t, 0)), p1 = g.mesh.V.row(g.mesh.F(t, 1)),
                            p2 = g.mesh.V.row(g.mesh.F(t, 2));
      vol += p0.dot(p1.cross(p2)) / 6;
    }
    const double dx = g.a / (g.res_x - 1), dy = g.b / (g.res_y - 1);
    double integral = 0;
    for (Eigen::Index i = 0; i + 1 < z.rows(); ++i)
      for (Eigen::Index j = 0; j + 1 < z.cols(); ++j)
        integral += dx * dy * (z(i, j) + z(i, j + 1) + z(i + 1, j) + z(i + 1, j + 1)) / 4;
    EXPECT_NEAR(vol, integral, 1e-3 * integral) << k;
  }
  EXPECT_GE(kinds.size(), 16u);  // the families' sub-types all occur in the first 48 parts
}

TEST(ShopParts, CavitiesAndFreeformPocketsAreSunkWithSteepWalls) {
  for (const ShopFamily f : {ShopFamily::Cavity, ShopFamily::FreeformPocket})
    for (int i = 0; i < kPerFamily; ++i) {
      const GeneratedMesh g = part(f, i);
      const Eigen::MatrixXd z = top_heights(g), s = cell_slopes(g);
      const double rim = z(0, 0);
      EXPECT_DOUBLE_EQ(rim, z.maxCoeff()) << g.kind;  // the block's top is the highest
      EXPECT_GT(rim - z.minCoeff(), 3.9) << g.kind;   // ≥ 4 mm deep
      EXPECT_GT(share(s, 60, 91), 0.01) << g.kind;    // steep walls
      EXPECT_GT(share(s, 0, 1), 0.2) << g.kind;       // flat top (and floor)
    }
}

TEST(ShopParts, CoresAndTerracesStandOnAFlatPlate) {
  for (const ShopFamily f : {ShopFamily::Core, ShopFamily::TerracedCore})
    for (int i = 0; i < kPerFamily; ++i) {
      const GeneratedMesh g = part(f, i);
      const Eigen::MatrixXd z = top_heights(g), s = cell_slopes(g);
      EXPECT_DOUBLE_EQ(z(0, 0), z.minCoeff()) << g.kind;  // the plate around is the lowest
      EXPECT_GT(z(z.rows() / 2, z.cols() / 2) - z(0, 0), 3.9) << g.kind;
      EXPECT_GT(share(s, 50, 91), 0.005) << g.kind;
    }
  // Terraces: 2, 3, 4 levels ⇒ as many flat plateaus above the plate, at distinct heights.
  for (int i = 0; i < 3; ++i) {
    const GeneratedMesh g = part(ShopFamily::TerracedCore, i);
    const Eigen::MatrixXd z = top_heights(g), s = cell_slopes(g);
    std::set<long> levels;
    for (Eigen::Index r = 0; r < s.rows(); ++r)
      for (Eigen::Index c = 0; c < s.cols(); ++c)
        if (s(r, c) < 0.01) levels.insert(std::lround(z(r, c) * 10));
    const auto n = static_cast<std::size_t>(std::stoi(g.kind.substr(g.kind.rfind('_') + 1)));
    EXPECT_GE(n, 2u) << g.kind;
    EXPECT_EQ(levels.size(), n + 1) << g.kind;  // the plate + the levels
  }
}

TEST(ShopParts, RibbedAndBoredPlatesHaveTheirFeatures) {
  for (int i = 0; i < kPerFamily; ++i) {
    const GeneratedMesh g = part(ShopFamily::RibbedPlate, i);
    const Eigen::MatrixXd z = top_heights(g);
    const double base = z.minCoeff(), top = z.maxCoeff();
    EXPECT_GE(components((z.array() > base + (top - base) / 2).matrix()), 1) << g.kind;
    // Ribs are thin: less than half the plate stands up, more than 2 %.
    const double up = static_cast<double>((z.array() > base + 1).count()) / static_cast<double>(z.size());
    EXPECT_GT(up, 0.02) << g.kind;
    EXPECT_LT(up, 0.5) << g.kind;
    // Across the ribs (a row and a column through the middle) at least two ribs are crossed.
    int crossings = 0;
    const Eigen::Index r = z.rows() / 2 + 1, c = z.cols() / 2 + 1;
    for (Eigen::Index j = 1; j < z.cols(); ++j) crossings += (z(r, j) > base + 1) && !(z(r, j - 1) > base + 1);
    for (Eigen::Index k = 1; k < z.rows(); ++k) crossings += (z(k, c) > base + 1) && !(z(k - 1, c) > base + 1);
    EXPECT_GE(crossings, 2) << g.kind;
  }
  int with_bosses = 0;
  for (int i = 0; i < kPerFamily; ++i) {
    const GeneratedMesh g = part(ShopFamily::BoredPlate, i);
    const Eigen::MatrixXd z = top_heights(g);
    const double plate = z(0, 0);
    EXPECT_GE(components((z.array() < plate - 2).matrix()), 2)
        << g.kind << " part " << i;  // ≥ 2 bores (or a bore and a pocket)
    // Bosses stand above the plate (the first two parts of every five have them: kind "…_bosses").
    const bool bosses = g.kind.ends_with("_bosses");
    with_bosses += bosses;
    if (bosses) EXPECT_GE(components((z.array() > plate + 2).matrix()), 1) << g.kind << " part " << i;
  }
  EXPECT_GE(with_bosses, kPerFamily / 5);
}

TEST(ShopParts, FreeformSurfacesAreSmoothAndBlendsMixSteepAndShallow) {
  for (int i = 0; i < kPerFamily; ++i) {
    const GeneratedMesh g = part(ShopFamily::FreeformSurface, i);
    const Eigen::MatrixXd s = cell_slopes(g);
    EXPECT_LT(s.maxCoeff(), 60) << g.kind;       // no wall
    EXPECT_LT(share(s, 0, 0.5), 0.2) << g.kind;  // curved nearly everywhere
    EXPECT_GT(s.maxCoeff() - s.minCoeff(), 5) << g.kind;
  }
  for (int i = 0; i < kPerFamily; ++i) {
    const GeneratedMesh g = part(ShopFamily::SteepShallowBlend, i);
    const Eigen::MatrixXd s = cell_slopes(g);
    EXPECT_GT(share(s, 0, 15), 0.5) << g.kind;    // mostly shallow
    EXPECT_GT(share(s, 30, 91), 0.01) << g.kind;  // a steep scarp
  }
}
