#pragma once
// Number formatting for reports and messages (data files use millnet::format_double instead, which
// round-trips bit for bit).
#include <iomanip>
#include <sstream>
#include <string>

namespace millnet::app {

/// `v` with exactly `decimals` digits after the point (for tables and messages people read).
[[nodiscard]] inline std::string fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

}  // namespace millnet::app
