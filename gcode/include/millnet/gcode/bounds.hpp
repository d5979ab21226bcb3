#pragma once
// The work a program read from outside will cause, counted before it is spent (issue 42 §5). The
// reader bounds every position and arc centre (reader.hpp: kMaxCoordinateMm), so each arc's chords
// are finite; a program of many arcs can still ask for more chords than a run allows: its users cut
// arcs into chords — the timing model (stats.hpp: chords of sagitta kArcChordToleranceMm, every arc),
// the simulator (simulate::SweepOptions::helix_chord_tol_mm, helical arcs only; planar arcs are
// swept whole) and the 3D preview (report::PreviewLimits::arc_step_deg, every arc) — and these
// estimates count them with the same sizing, one WorkEstimate per user, for millnet::check_work.
#include "millnet/core/budget.hpp"
#include "millnet/gcode/program.hpp"

#include <string_view>
#include <vector>

namespace millnet::gcode {

/// Where a program read from a file goes, and the chord sizing of each user (their defaults).
struct ProgramUse {
  /// Machined on a z-map (helices in chords of helix_sagitta_mm) and timed (stats()).
  bool simulate = true;
  double helix_sagitta_mm = 1e-4;  ///< simulate::SweepOptions::helix_chord_tol_mm
  bool preview = true;             ///< drawn on a 3D page
  double preview_step_deg = 6;     ///< report::PreviewLimits::arc_step_deg (at least 0.5)
};

/// Chords of an arc of `radius_mm` over `sweep_rad` (> 0) when each may deviate at most sagitta_mm
/// from it (2·acos(1 − s/r) per chord; the whole sweep in one when r ≤ s). At least 1.
[[nodiscard]] double arc_chords(double radius_mm, double sweep_rad, double sagitta_mm);

/// Per user of `use`: the blocks, primitives or points a program becomes (moves plus the extra
/// chords of its arcs), with the memory each holds, named after `source`. O(moves).
[[nodiscard]] std::vector<WorkEstimate> program_work(const Program& program, std::string_view source,
                                                     const ProgramUse& use = {});

/// read() of a program from outside, checked before it is used: its lines within limits (before
/// reading), at least one move ("nothing to simulate"), and program_work within limits. Throws
/// millnet::Error naming `source` (check_work's one line after it).
[[nodiscard]] Program read_checked(std::string_view text, std::string_view source, const WorkLimits& limits,
                                   const ProgramUse& use = {});

}  // namespace millnet::gcode
