#pragma once
// The 2D plan every planner produces, before it becomes G-code.
//   * A Chain is cut with the tool down at the cutting depth: vertices with bulges (segment k goes
//     from pts[k] to pts[k+1] with pts[k].bulge, 0 = straight), a feed per segment (mm/min,
//     0 = not assigned yet: the feed map or f2 fills it).
//   * Between two chains the tool retracts to safe Z, rapids above the next chain's start and plunges.
//     Entering a chain needs a pre-drilled hole (or a helix/ramp entry) unless the entry point has
//     already been cut at this depth.
#include "millnet/pocket/geometry.hpp"
#include "millnet/tooling/cutter.hpp"

#include <string>
#include <vector>

namespace millnet::pocket {

struct Chain {
  std::vector<Vertex> pts;
  std::vector<double> feed;  ///< pts.size() − 1 entries once assigned
  bool predrill = true;      ///< entry plunges into uncut material
  std::string role = "cut";  ///< "cut" (area clearing), "contour" (wall pass), "link" …
  /// > 0: pts[0] … pts[entry_turn] are a flat turn round the bore of the helix a helix entry makes
  /// at pts[0] (the adaptive planner's chains: it counts on that bore, and with any other entry
  /// these moves cut it). A program that enters this chain by that helix, whose own flat turn
  /// cuts the bore, goes on from pts[entry_turn] (= pts[0]) instead of turning round it twice.
  std::size_t entry_turn = 0;
};

struct Path2D {
  std::vector<Chain> chains;
  [[nodiscard]] double cut_length() const;    ///< Σ chain lengths (arcs exact)
  [[nodiscard]] double rapid_length() const;  ///< Σ XY distance between chain end and next start
  [[nodiscard]] std::size_t retractions() const { return chains.empty() ? 0 : chains.size() - 1; }
};

/// Tool, cut and machine parameters (all mm, mm/min, rpm). Flags > config > pocket file keys.
struct CutParams {
  /// The roughing tool (flat or bull nose): its diameter sets every clearance; its shape goes with
  /// the program to the simulation and the previews (issue 36: a bull nose was simulated as flat).
  tooling::Cutter tool = tooling::Cutter::flat(10);
  double stepover = 5;        ///< tool-point grid spacing g (SOM) / pass distance (zigzag)
  double stock_to_leave = 0;  ///< radial allowance left on walls and islands
  double depth = 5;           ///< pocket floor at Z = −depth (top is Z = 0)
  double step_down = 5;       ///< ≥ depth ⇒ one level
  double safe_z = 5;
  double feed_slot = 50;   ///< f1: full-width (slot) cut
  double feed_half = 100;  ///< f2: half-width cut (also the constant feed of comparisons)
  double feed_plunge = 30;
  double feed_min = 20, feed_max = 200;
  double spindle_rpm = 3000;
  double feed_grid = 0;  ///< feed-map cell, 0 ⇒ tool diameter / 10
  bool feed_adjust = true;
  /// The feed map pools steps shorter than a cell until they make a cell before reading an
  /// engagement (feedmap.hpp); false: every step scaled to a cell on its own, as the 1995 preset's
  /// programs were written (a 0.05 mm step with one fresh cell then reads as a slot).
  bool feed_pool_short_steps = true;
  double rapid_rate = 5000;  ///< mm/min, for time estimates of G0 moves
  double feed_entry = 0;     ///< helix and ramp entry feed; 0 ⇒ feed_plunge
  /// Feed of the pieces the feed map finds cutting no cell (links through cut material), mm/min,
  /// or the map's own feed for them where that is higher; 0 ⇒ the cutting feed like every other
  /// piece. Whatever feed_adjust says: such a move is not a cut.
  double feed_air = 0;
  /// > 1: below half-width engagement the feed map raises f₂ by the radial chip-thinning factor
  /// (tooling::chip_thinning_factor) capped at this value (and at feed_max); 0 ⇒ eq. 9 extrapolated
  /// below n₂ as the paper does.
  double max_chip_thinning = 0;
  std::vector<std::string> header;  ///< extra header comments (the tool and its cutting data)
  [[nodiscard]] double clearance() const { return tool.diameter / 2 + stock_to_leave; }
  /// The one check of the cutting parameters every planner and the feed map rely on: a finite
  /// tool diameter > 0, stepover in (0, tool diameter], stock_to_leave ≥ 0. Throws millnet::Error
  /// "<who>: <key> …" naming the value.
  void check(const std::string& who) const;
};

/// Outcome of planning; an empty path always comes with a non-Ok status and a message.
enum class PlanStatus { Ok, NoToolPoints, NothingToCut };
[[nodiscard]] const char* to_string(PlanStatus s);

}  // namespace millnet::pocket
