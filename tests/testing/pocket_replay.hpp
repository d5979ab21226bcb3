#pragma once
// A pocket region as the independent G-code replay reads it (testing/gcode_replay.hpp): the same
// loops of [x, y, bulge], so that the replay's own geometry checks the planners' output.
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpath.hpp"
#include "testing/gcode_replay.hpp"

namespace millnet::testing {

inline ReplayPocket to_replay(const pocket::Region& r) {
  ReplayPocket p;
  for (const pocket::Vertex& v : r.boundary) p.boundary.push_back({v.x, v.y, v.bulge});
  for (const pocket::Loop& l : r.islands) {
    p.islands.emplace_back();
    for (const pocket::Vertex& v : l) p.islands.back().push_back({v.x, v.y, v.bulge});
  }
  return p;
}

/// Issue 11's bench setting (configs/bench/roughing-issue11.json): Ø10, stepover 5, depth 5 in one
/// level, every cutting move at 1500 mm/min, plunges and entries at 300 mm/min, no feed map.
inline pocket::CutParams issue11_bench_cut() {
  pocket::CutParams cut;
  cut.tool_diameter = 10;
  cut.stepover = 5;
  cut.depth = 5;
  cut.step_down = 5;
  cut.feed_slot = cut.feed_half = cut.feed_min = cut.feed_max = 1500;
  cut.feed_plunge = 300;
  cut.feed_adjust = false;
  return cut;
}

}  // namespace millnet::testing
