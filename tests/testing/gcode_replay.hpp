#pragma once
// Independent G-code replay for the tests: re-reads RS-274 text (G0/G1/G2/G3 X Y Z I J F, modal,
// absolute G90, arc centres incremental) and checks that the tool disk never gouges a pocket wall.
// Deliberately shares NO code with millnet::pocket (own parser, own point–line/arc distances), so
// that a bug in the pocket module's Clearance cannot hide itself. mm throughout.
#include "linuxcnc.hpp"  // the file beside this one

#include <array>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace millnet::testing {

/// A closed loop of [x, y, bulge] (bulge = tan(sweep/4) of the segment to the next vertex).
using ReplayLoop = std::vector<std::array<double, 3>>;

struct ReplayPocket {
  ReplayLoop boundary;
  std::vector<ReplayLoop> islands;
};

struct ReplayMove {
  int g = 0;  ///< 0, 1, 2, 3
  std::array<double, 3> from{}, to{};
  std::array<double, 2> center{};  ///< arcs only (absolute)
  double feed = 0;                 ///< mm/min in effect (G1/G2/G3)
  int line = 0;                    ///< 1-based source line
};

struct ReplayResult {
  std::vector<ReplayMove> moves;
  double cut_length = 0;    ///< XY length of G1/G2/G3 moves below Z = 0 (pure Z moves add 0)
  double rapid_length = 0;  ///< XY length of G0 moves
  int retractions = 0;      ///< G0 moves up to ≥ safe Z after cutting that are followed by another entry
  int plunges = 0;          ///< descending feed moves right after a rapid (one per entry, drilling included)
  std::map<double, double> cut_length_by_z;  ///< XY cut length of moves at constant Z < 0
  // Gouge check (filled by check_gouge):
  int samples = 0;
  int violations = 0;
  double worst_mm = 0;          ///< largest intrusion of the disk into a wall (> tol ⇒ violation)
  std::string first_violation;  ///< "line N: (x, y, z) ..." of the first violation
  double min_z = 0;
  bool uses_feed_everywhere = true;  ///< every feed move had an F in effect
};

/// Parses G-code text; throws std::runtime_error naming the line on unsupported words (G91, G81…).
[[nodiscard]] ReplayResult replay_gcode(const std::string& text, double safe_z);

/// Samples every move below Z = 0 at ≤ step_mm (arcs exactly on the circle) and counts samples
/// where the tool disk (radius tool_radius) reaches more than tol_mm outside the boundary or into
/// an island.
void check_gouge(ReplayResult& r, const ReplayPocket& pocket, double tool_radius, double tol_mm = 0.01,
                 double step_mm = 0.05);

}  // namespace millnet::testing
