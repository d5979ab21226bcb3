#include "millnet/ingest/io/grid_csv.hpp"

#include "millnet/core/atomic_file.hpp"

#include <sstream>

namespace millnet::ingest {

std::string grid_csv(const Eigen::MatrixXd& h) {
  std::ostringstream os;
  for (Eigen::Index i = 0; i < h.rows(); ++i) {
    for (Eigen::Index j = 0; j < h.cols(); ++j) os << (j ? "," : "") << format_double(h(i, j));
    os << "\n";
  }
  return os.str();
}

}  // namespace millnet::ingest
