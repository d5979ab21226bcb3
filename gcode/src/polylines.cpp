#include "millnet/gcode/polylines.hpp"

#include <variant>

namespace millnet::gcode {

XyPaths xy_paths(const Program& prog) {
  XyPaths out;
  std::array<double, 2> at{0, 0};
  bool have = false, cutting = false;
  for (const auto& item : prog.items) {
    const auto* m = std::get_if<Move>(&item);
    if (m == nullptr) continue;
    const std::array<double, 2> to{m->to[0], m->to[1]};
    const bool cut = m->motion != Motion::Rapid;
    if (have && (to[0] != at[0] || to[1] != at[1] || cut)) {
      auto& list = cut ? out.cuts : out.rapids;
      if (list.empty() || cut != cutting) list.push_back({at});
      list.back().push_back(to);
      cutting = cut;
    }
    at = to;
    have = have || (m->axes & (kX | kY)) == (kX | kY);
  }
  return out;
}

}  // namespace millnet::gcode
