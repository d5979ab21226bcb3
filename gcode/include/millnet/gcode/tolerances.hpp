#pragma once
// Named tolerances of the gcode module: the motion-time model and the in-stock figures (stats.hpp).
// Lengths in mm, angles in radians. (The reader's own are in reader.cpp.)
namespace millnet::gcode::tol {

/// Arcs are timed as chords deviating at most this much from the arc (GRBL's default
/// arc_tolerance); stats.hpp names it kArcChordToleranceMm.
inline constexpr double arc_chord_mm = 0.002;

/// A move (or arc chord) shorter than this is no planner block: zero-length moves are skipped.
inline constexpr double zero_length_mm = 1e-9;

/// Two tool heights closer than this are the same height (retracts to clearance, descending
/// entries, lateral cuts of the in-stock figures).
inline constexpr double same_z_mm = 1e-9;

/// An arc whose end lies at most this angle past its start (rad) is a full circle.
inline constexpr double full_circle_rad = 1e-12;

/// GRBL's thresholds on cos θ, θ the angle between the reversed incoming direction and the
/// outgoing one: above this a joint is a reversal (the machine stops), below its negative it is
/// straight on (no slow-down).
inline constexpr double straight_cos = 0.999999;

}  // namespace millnet::gcode::tol
