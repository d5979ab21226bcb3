#include "millnet/simulate/maps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace millnet::simulate {

std::vector<double> design_heights(const ingest::HeightField& hf, double z_shift) {
  std::vector<double> design(hf.z.size());
  const auto n = static_cast<std::ptrdiff_t>(hf.z.size());
#pragma omp parallel for schedule(static) if (n > 65536)
  for (std::ptrdiff_t k = 0; k < n; ++k) {  // O(cells)
    const auto i = static_cast<std::size_t>(k);
    design[i] = hf.hit[i] ? hf.z[i] + z_shift : std::numeric_limits<double>::quiet_NaN();
  }
  return design;
}

namespace {
template <class T>
Eigen::MatrixXd block_means_of(const std::vector<T>& v, std::size_t nx, std::size_t ny, std::size_t max_cells,
                               double empty) {
  const std::size_t k = std::max<std::size_t>(1, (std::max(nx, ny) + max_cells - 1) / max_cells);
  const std::size_t rx = (nx + k - 1) / k, ry = (ny + k - 1) / k;
  Eigen::MatrixXd m(static_cast<Eigen::Index>(ry), static_cast<Eigen::Index>(rx));
  // A row of blocks per iteration, each block summed in cell order: the same for any thread count.
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t bl = 0; bl < static_cast<std::ptrdiff_t>(ry); ++bl)
    for (std::size_t bi = static_cast<std::size_t>(bl), bj = 0; bj < rx; ++bj) {
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t i = bi * k; i < std::min(ny, (bi + 1) * k); ++i)
        for (std::size_t j = bj * k; j < std::min(nx, (bj + 1) * k); ++j) {
          const double x = v[i * nx + j];
          if (std::isfinite(x)) sum += x, ++n;
        }
      m(static_cast<Eigen::Index>(bi), static_cast<Eigen::Index>(bj)) = n ? sum / static_cast<double>(n) : empty;
    }
  return m;
}

}  // namespace

Eigen::MatrixXd block_means(const std::vector<double>& v, std::size_t nx, std::size_t ny, std::size_t max_cells,
                            double empty) {
  return block_means_of(v, nx, ny, max_cells, empty);
}

Eigen::MatrixXd block_means(const std::vector<float>& v, std::size_t nx, std::size_t ny, std::size_t max_cells,
                            double empty) {
  return block_means_of(v, nx, ny, max_cells, empty);
}

}  // namespace millnet::simulate
