#pragma once
// The height-grid CSV of `millnet sample` (adapter millnet::ingest_io).
#include <Eigen/Core>

#include <string>

namespace millnet::ingest {

/// n rows × n columns, rows from min y, columns from min x, shortest round-trip numbers
/// (millnet::format_double), no header.
[[nodiscard]] std::string grid_csv(const Eigen::MatrixXd& h);

}  // namespace millnet::ingest
