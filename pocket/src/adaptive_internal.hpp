#pragma once
// Private to the adaptive planner (planner_adaptive.hpp): its constants and the Planner whose
// members its passes are, one file per pass:
//   planner_adaptive.cpp   plan_adaptive, the clearing loop (entries, what follows each pass)
//   adaptive_raster.cpp    the cleared-area raster and the material sense (adaptive_raster.hpp)
//   adaptive_prepare.cpp   the target cells, the components' entries, the link lattice
//   adaptive_passes.cpp    step selection: one pass at the target engagement
//   adaptive_rides.cpp     rides back along a front, pulled taut
//   adaptive_links.cpp     links through cut area: the lattice search, taut links, backtracking
//   adaptive_chains.cpp    the wall pass and the chains of the result
#include "millnet/pocket/planner_adaptive.hpp"

#include "adaptive_raster.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

namespace millnet::pocket::adaptive {

inline constexpr double kPi = std::numbers::pi;

/// Link lattice spacing, mm: positions a link may pass through and passes may start from.
inline constexpr double kLatticeMm = 1.0;
/// Lattice positions keep this much more than the cutting clearance from the walls, mm: a chord
/// between two of them then cannot dip into the clearance round a convex island (sagitta of a
/// 1.5 mm chord on a 5 mm arc: 0.06 mm).
inline constexpr double kLinkMarginMm = 0.1;
/// Turn per step while cutting (the first step of a pass searches ±90°), degrees.
inline constexpr double kMaxTurnDeg = 12;
/// A pass senses uncut material this far beyond the tool's radius, mm; it also ends after R plus
/// this much path that cut nothing.
inline constexpr double kSenseMm = 3.0;
/// A pass ends when the best step it may take points more than this off the front's tangent, away
/// from the material (it could only back away), degrees.
inline constexpr double kBlockedDeg = 75;
/// A ride back along the front stops when a step would point more than this away from the material.
inline constexpr double kRideAwayDeg = 60;
/// Rides back shorter than kRideMinMm gain nothing; none goes beyond kRideMaxMm.
inline constexpr double kRideMinMm = 1.0;
inline constexpr double kRideMaxMm = 300.0;
/// A ride steps this many planning steps at a time (it cuts nothing at any of its positions; between
/// two of them 4 steps = D/10 apart, a cell within R of the move but of neither lies at most
/// (D/10)²/(8R) = D/400 beyond R of both, as air_ok allows).
inline constexpr int kRideStepSteps = 4;
/// A tool with no link out backtracks along its own path, trying a link every kBacktrackMm, at
/// most kBacktrackTries times.
inline constexpr double kBacktrackMm = 2.0;
inline constexpr int kBacktrackTries = 60;
/// Wall loops: a possible start every kWallStartMm of straight edge; the kWallStartTries nearest
/// starts are tried in turn.
inline constexpr double kWallStartMm = 5.0;
inline constexpr std::size_t kWallStartTries = 40;
/// Below this engagement target the passes also take the wall band (see mark_target()), degrees.
inline constexpr double kPassesTakeTheWallBandBelowDeg = 85;
/// Uncut material worth a pass, in cells of D/40 (less is raster noise); min_work_ is this area in
/// the raster's own cells.
inline constexpr double kMinWorkCellsD40 = 4;

/// v turned by a radians, counter-clockwise.
inline Vec2 rot(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

/// The planner's state while it plans one region: the raster, the walls, the lattice and the raw
/// chains. plan_adaptive calls the constructor (prepare), clear_area, cut_walls, then result.
class Planner {
public:
  Planner(const Region& region, const CutParams& cut, const AdaptiveParams& prm, double target_deg);

  /// Passes, rides and links (a retraction and a new entry where none is linkable) until no
  /// reachable position sees uncut target material (planner_adaptive.cpp).
  void clear_area();

  /// The wall pass: every loop of A_0 (outer loops counter-clockwise, island loops clockwise for
  /// climb; reversed for conventional), the nearest loop next, each from its vertex nearest the
  /// tool, reached with the tool down through cut area (a retraction only where no way is free).
  void cut_walls();

  /// The raw chains simplified into res's path (tol::adaptive_simplify_mm), with the statistics.
  PlanResult result(PlanResult res);

  AdaptiveStats stats_;

private:
  struct RawChain {
    std::vector<Vec2> pts;
    bool predrill = true;
    std::size_t turn_end = 0;  ///< pts[0] … pts[turn_end]: the turn round the entry's bore (Chain::entry_turn)
  };

  struct Entry_ {
    Vec2 p;
    bool entered = false;
  };

  // ---- the wall pass (adaptive_chains.cpp)
  /// Links the tool to the nearest start of a wall loop a link reaches (loop li, vertex vi): true;
  /// false (li, vi the nearest start) when none of the kWallStartTries nearest is reached.
  bool link_to_wall_loop(const std::vector<std::vector<Vec2>>& loops, std::size_t& li, std::size_t& vi);

  // ---- prepare (adaptive_prepare.cpp)
  /// Target cells (within R of an allowed raster centre), raster components of allowed centres,
  /// their entry points (largest distance to the material's edge), the lattice.
  void prepare();
  /// Raster cells where the tool centre may stand (the walls' clearance, exact near it).
  [[nodiscard]] std::vector<std::uint8_t> allowed_centres(const std::vector<double>& wall_d2) const;
  /// The passes' target: the uncut cells within reach of an allowed centre cell.
  void mark_target(const std::vector<std::uint8_t>& allowed);
  /// Per component of allowed centres, its entry: the cell farthest from the walls.
  void find_entries(const std::vector<std::uint8_t>& allowed, const std::vector<double>& wall_d2);
  /// The link lattice over the raster's box, nothing known of it yet.
  void make_lattice();

  // ---- the clearing loop (planner_adaptive.cpp)
  /// What follows a pass that left the tool at pos: the return stripe, a ride back, or a link to
  /// the nearest start. False when nothing is linkable from pos (the tool retracts).
  bool next_pass(Vec2& pos);
  /// Both ways: the pass blocked at a wall turns round and cuts the next stripe back. True when
  /// that stripe was worth it.
  bool turn_round(Vec2& pos);
  /// A ride back along the front, then a pass from its end (or a link from it to a start).
  bool ride_and_cut(Vec2& pos);
  /// A link to the nearest start and a pass from there (or the start marked dead).
  bool link_and_cut(Vec2& pos);
  /// Enters the next component not entered yet (helix at its entry point), or re-enters with a
  /// plunge at a cleared start that no link reaches. False when nothing is left.
  bool enter_next(std::optional<Vec2>& pos);
  /// The entry into component e: the helix's bore and its flat turn, then the first pass.
  void enter(Entry_& e, std::optional<Vec2>& pos);
  /// A plunge at a cleared lattice position with target material near that no link reached.
  bool reenter(std::optional<Vec2>& pos);

  // ---- step selection (adaptive_passes.cpp)
  /// A pass from `start` (the tool there), across the line to the material at `toward`; a start
  /// whose pass cuts next to nothing is not offered again. Returns where the tool is.
  Vec2 pass_from(const Vec2& start, const Vec2& toward);
  /// The first direction at a pass start: across the line to the nearest uncut material, so that
  /// the material is on the right (climb) or on the left (conventional).
  [[nodiscard]] Vec2 first_dir(const Vec2& start, const Vec2& toward) const;
  /// Fresh cells of a step to q, or +inf where the move is not allowed.
  [[nodiscard]] double cost(const Vec2& p, const Vec2& q) const;
  /// The tangent along the material sensed from p (the centroid of the uncut target cells within
  /// R + kSenseMm, or heading d when it lies at p), with the material on the right for side +1
  /// (climb), on the left for −1; nullopt when no target material is in range.
  [[nodiscard]] std::optional<Vec2> material_tangent(const Vec2& p, const Vec2& d, double side) const;
  /// The first of the probe directions rot(t0, −side·θ), θ = 90° (straight at the material), −90°
  /// (straight away), −120°, −150°, −180°, whose step cuts at most the target; nullopt when none.
  [[nodiscard]] std::optional<double> first_feasible(const Vec2& p, const Vec2& t0, double side) const;
  /// Whether cut_pass(p, d, first_wide = true) takes a first step.
  [[nodiscard]] bool can_start(const Vec2& p, const Vec2& d) const;
  /// One pass from p (already there, its disk cleared) heading about d. Returns the cells cut.
  double cut_pass(Vec2 p, Vec2 d, bool first_wide);

  // ---- rides (adaptive_rides.cpp)
  /// From p (the end of a pass), rides back along the front with the material on the other side
  /// than a cutting pass keeps it, cutting nothing. False when it is shorter than kRideMinMm.
  bool ride_back(const Vec2& p0, std::vector<Vec2>& way);
  /// The straight move a→b keeps the walls' margin and cuts nothing.
  [[nodiscard]] bool air_ok(const Vec2& a, const Vec2& b) const;
  /// A ride pulled taut: from each vertex the farthest later one that air_ok reaches.
  [[nodiscard]] std::vector<Vec2> taut_ride(const std::vector<Vec2>& way) const;
  /// Appends a tool-down move along `way` (from the chain's end) to the current chain.
  void append_link(const std::vector<Vec2>& way);

  // ---- links (adaptive_links.cpp)
  [[nodiscard]] Vec2 lattice_point(std::size_t k) const;
  [[nodiscard]] std::size_t lattice_index(const Vec2& p) const;
  /// Allowed for links (cached: walls do not move).
  bool lattice_allowed(std::size_t k);
  /// The tool's disk there is cleared (up to raster noise).
  [[nodiscard]] bool safe(const Vec2& p) const { return raster_.clear_within(p, R_); }
  /// The straight move a→b with the tool down: no wall, at most the target's cut per step.
  [[nodiscard]] bool link_ok(const Vec2& a, const Vec2& b) const;
  /// Dijkstra from `from` over safe, allowed lattice positions to the nearest one with uncut target
  /// material within reach; the way there (from first, the start last).
  /// With `goal`: the way to that point instead (the lattice position nearest it that a straight
  /// link reaches, then the goal).
  bool find_start(const Vec2& from, Vec2& start, Vec2& toward, std::vector<Vec2>& way, const Vec2* goal = nullptr);
  /// Cuts along `way` (from the tool's position) pulled taut. False (nothing appended) when a move
  /// between two lattice neighbours fails.
  bool link_along(const std::vector<Vec2>& way);
  /// Where no link leaves the tool's position: back along the chain's own path to a point from
  /// which a link reaches `goal`, then that link. False (nothing appended) when none does.
  bool backtrack_to(const Vec2& goal);
  /// Marks the straight move a→b cut, at the planning step.
  void mark_move(const Vec2& a, const Vec2& b);

  [[nodiscard]] Vec2 current_end() const { return chains_.back().pts.back(); }

  const Region& region_;
  CutParams cut_;
  double R_;
  bool climb_;
  bool both_;                  ///< AdaptiveParams::both_ways
  bool pass_climb_;            ///< the current pass's side (climb_ but for the return stripes of both ways)
  bool last_blocked_ = false;  ///< the last pass ended at a wall with material ahead
  Vec2 last_dir_{1, 0};        ///< its last heading
  double step_;
  Raster raster_;
  Clearance walls_;         ///< cutting moves: the contour pass's clearance
  Clearance exact_;         ///< links and simplified chords: the tool's clearance
  Clearance link_walls_;    ///< lattice positions
  double max_cells_ = 0;    ///< fresh cells allowed per step
  int min_work_ = 4;        ///< uncut cells worth a pass (kMinWorkCellsD40)
  double target_deg_ = 90;  ///< the engagement target, degrees
  double last_cells_ = 0;   ///< cells the last pass cut
  Vec2 last_heading_{1, 0};
  std::vector<Entry_> entries_;
  Vec2 lat_lo_;
  int lnx_ = 0, lny_ = 0;
  std::vector<signed char> lat_ok_;
  std::vector<std::uint8_t> dead_;
  std::vector<std::uint8_t> lat_safe_;  ///< lattice positions known allowed and cleared
  std::vector<RawChain> chains_;

  // Caches of link_ok: the uncut cells at a, while the raster is unchanged.
  mutable Vec2 fresh_at_{kInf, kInf};
  mutable std::uint64_t fresh_version_ = 0;
  mutable int fresh_a_ = 0;
  // Caches of cost: the position p's room to the walls, whether its disk is clear, its runs.
  mutable double p_pad_ = -1;
  mutable Raster::Runs p_runs_;
  mutable Vec2 room_at_{kInf, kInf};
  mutable double room_ = -1;
  mutable bool p_clear_ = false;
};

}  // namespace millnet::pocket::adaptive
