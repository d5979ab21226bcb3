#pragma once
// Program → lengths and machining times: from the feeds alone, and from machine dynamics with a
// GRBL-style planner (constant acceleration, junction deviation, look-ahead over the whole
// program).
//
// Kinematic model: every line (and every chord of an arc, see kArcChordToleranceMm) is a block
// with a trapezoidal speed profile: it accelerates and decelerates at acceleration_mm_s2 and
// cruises at its nominal speed (the feed, capped at max_feed_mm_min; rapids at rapid_mm_min).
// The speed through the joint of two blocks is at most √(a·δ·s/(1−s)), s = sin(θ/2), θ the angle
// between the reversed incoming direction and the outgoing one (GRBL's junction deviation δ):
// straight on (θ = 180°) does not slow down, a reversal (θ = 0) stops. A backward pass from the
// final stop and a forward pass from the initial stop make every entry speed reachable within
// its neighbours' lengths. The machine also stops at spindle changes, tool changes and pauses
// (GRBL synchronises its buffer on them). Travel along an axis before the program first states
// it is not counted (the start position is unknown).
#include "millnet/gcode/program.hpp"
#include "millnet/gcode/tolerances.hpp"

#include <cstddef>

namespace millnet::gcode {

/// Arcs are timed as chords deviating at most this much from the arc (GRBL's default arc_tolerance).
inline constexpr double kArcChordToleranceMm = tol::arc_chord_mm;

struct MotionModel {
  double rapid_mm_min = 5000;
  double max_feed_mm_min = 5000;
  double acceleration_mm_s2 = 500;
  double junction_deviation_mm = 0.01;
};

/// The frame of the in-stock figures (Shin & Suh's comparison of roughing programs): Z 0 is the
/// stock top; the tool starts at clearance height above X 0 Y 0; a milling move (Move::op 0) that
/// rapids up to clearance_z_mm after cutting and enters again is a retraction.
struct StockFrame {
  double clearance_z_mm = 5;       ///< the program's retract height (safe Z), mm
  double rapid_mm_min = 5000;      ///< rapid rate of the time_at_feeds figures
  double nominal_feed_mm_min = 0;  ///< f₂: the feed of a feed move without one, and of every lateral
                                   ///< milling cut in time_constant_feed_min (0: those take their own)
};

/// A program's figures. Lengths are 3D path lengths unless named xy_ (projected on the XY plane).
struct ProgramStats {
  double cut_length_mm = 0;       ///< 3D path length of feed moves (G1 G2 G3)
  double rapid_length_mm = 0;     ///< 3D path length of rapids (G0)
  double plunge_length_mm = 0;    ///< downward Z travel of feed moves
  double feed_time_min = 0;       ///< Σ length / feed (rapids at rapid_mm_min, feeds capped at max_feed_mm_min)
  double kinematic_time_min = 0;  ///< with acceleration and junction speeds (the planner above)
  std::size_t blocks = 0;         ///< planner blocks (lines + arc chords, zero-length moves skipped)

  // In the stock frame (StockFrame), from the tool's start above X 0 Y 0:
  double xy_cut_length_mm = 0;        ///< XY length of feed moves reaching below Z 0 (milling and drilling)
  double xy_rapid_length_mm = 0;      ///< XY length of rapids
  std::size_t retractions = 0;        ///< milling retractions to clearance followed by another entry
  std::size_t entries = 0;            ///< milling entries: descending feed moves right after a rapid
  double time_at_feeds_min = 0;       ///< Σ 3D length / feed, rapids at StockFrame::rapid_mm_min, no acceleration
  double time_constant_feed_min = 0;  ///< the same with every lateral milling cut at the nominal feed
};

/// Throws millnet::Error when a model value is not > 0 (junction deviation ≥ 0) or a feed move has
/// no feed (and the frame has no nominal feed for it).
[[nodiscard]] ProgramStats stats(const Program& program, const MotionModel& model, const StockFrame& frame = {});

/// Time (s) of one block of length `len` (mm) entered at v_in, left at v_out, cruising at most at
/// v_nom (mm/s), accelerating at `a` (mm/s²); v_in, v_out ≤ v_nom and reachable from each other.
[[nodiscard]] double trapezoid_time_s(double len, double v_in, double v_out, double v_nom, double a);

/// Largest speed (mm/s) through a joint from unit direction u to unit direction v.
[[nodiscard]] double junction_speed(const Point3& u, const Point3& v, double acceleration_mm_s2,
                                    double junction_deviation_mm);

}  // namespace millnet::gcode
