#include "height_solid.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace millnet::datasets::detail {

GeneratedMesh height_field_solid(double a, double b, int res_x, int res_y, double plinth, const HeightFn& f) {
  GeneratedMesh g;
  g.res_x = res_x;
  g.res_y = res_y;
  g.a = a;
  g.b = b;
  const auto RX = static_cast<std::size_t>(res_x), RY = static_cast<std::size_t>(res_y);
  auto x_at = [&](std::size_t j) { return a * static_cast<double>(j) / static_cast<double>(res_x - 1); };
  auto y_at = [&](std::size_t i) { return b * static_cast<double>(i) / static_cast<double>(res_y - 1); };
  std::vector<double> z(RX * RY);
  double zmin = HUGE_VAL;
  for (std::size_t i = 0; i < RY; ++i)
    for (std::size_t j = 0; j < RX; ++j) {
      z[i * RX + j] = f(x_at(j), y_at(i));
      zmin = std::min(zmin, z[i * RX + j]);
    }
  // Boundary ring, counter-clockwise seen from +z: y = 0 (x up), x = a (y up), y = b (x down), x = 0.
  std::vector<std::size_t> ring;
  for (std::size_t j = 0; j + 1 < RX; ++j) ring.push_back(j);
  for (std::size_t i = 0; i + 1 < RY; ++i) ring.push_back(i * RX + RX - 1);
  for (std::size_t j = RX - 1; j > 0; --j) ring.push_back((RY - 1) * RX + j);
  for (std::size_t i = RY - 1; i > 0; --i) ring.push_back(i * RX);
  const std::size_t n_top = RX * RY;
  const std::size_t nv = n_top + ring.size() + 1;
  const std::size_t nf = 2 * (RX - 1) * (RY - 1) + 3 * ring.size();
  g.mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  g.mesh.F.resize(static_cast<Eigen::Index>(nf), 3);
  auto setv = [&](std::size_t k, double x, double y, double zz) {
    const auto e = static_cast<Eigen::Index>(k);
    g.mesh.V(e, 0) = x;
    g.mesh.V(e, 1) = y;
    g.mesh.V(e, 2) = zz;
  };
  for (std::size_t i = 0; i < RY; ++i)
    for (std::size_t j = 0; j < RX; ++j) setv(i * RX + j, x_at(j), y_at(i), plinth + z[i * RX + j] - zmin);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const auto e = static_cast<Eigen::Index>(ring[k]);
    setv(n_top + k, g.mesh.V(e, 0), g.mesh.V(e, 1), 0.0);
  }
  const std::size_t centre = nv - 1;
  setv(centre, a / 2, b / 2, 0.0);
  std::size_t f_at = 0;
  auto tri = [&](std::size_t p, std::size_t q, std::size_t r) {
    const auto e = static_cast<Eigen::Index>(f_at++);
    g.mesh.F(e, 0) = static_cast<std::int32_t>(p);
    g.mesh.F(e, 1) = static_cast<std::int32_t>(q);
    g.mesh.F(e, 2) = static_cast<std::int32_t>(r);
  };
  for (std::size_t i = 0; i + 1 < RY; ++i)
    for (std::size_t j = 0; j + 1 < RX; ++j) {
      const std::size_t v00 = i * RX + j, v01 = v00 + 1, v10 = v00 + RX, v11 = v10 + 1;
      tri(v00, v01, v11);
      tri(v00, v11, v10);
    }
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const std::size_t k1 = (k + 1) % ring.size();
    const std::size_t t0 = ring[k], t1 = ring[k1], b0 = n_top + k, b1 = n_top + k1;
    tri(b0, b1, t1);
    tri(b0, t1, t0);
    tri(centre, b1, b0);
  }
  MILLNET_ASSERT(f_at == nf, "generated face count");
  return g;
}

}  // namespace millnet::datasets::detail
