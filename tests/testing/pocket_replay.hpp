#pragma once
// A pocket region as the independent G-code replay reads it (testing/gcode_replay.hpp): the same
// loops of [x, y, bulge], so that the replay's own geometry checks the planners' output.
#include "millnet/pocket/geometry.hpp"
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

}  // namespace millnet::testing
