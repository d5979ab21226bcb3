#pragma once
// The pocket's program (a gcode::Program: the text of a dialect is written at the edge, by
// gcode::write_program): G0/G1/G2/G3 with feeds, spindle on and off, parameters as header comments.
// No canned cycles, no tool-length or work offsets. Pocket top Z = 0, floor Z = −depth.
//
// Every level is planned on its own (issue 5 passes a different region and plan per Z level):
//   levels are machined in the given order (top-down); between chains the tool retracts to safe Z,
//   rapids above the next start, rapids down to approach_mm above the level's material top, then
//   plunges (predrilled hole / already-cut point) or enters by helix / ramp (fed straight down to
//   ramp_clearance_mm above the material, descending from there at entry_angle_deg): entry "helix" falls
//   back to a ramp along the chain's first segment, "ramp" to a helix; a plain plunge into uncut
//   material (with a WARNING comment) only where neither fits. A helix starts on its circle so that
//   its descent ends at the chain's first point, where its flat turn at the floor closes and the
//   chain begins (after the chain's own turn round the bore, Chain::entry_turn, if it has one).
#include "millnet/gcode/program.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/pocket/toolpath.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace millnet::pocket {

struct LevelPlan {
  double z = 0;                ///< cutting Z of this level (< 0)
  double top_z = 0;            ///< material top above this level (the previous level's z, 0 for the first)
  Region region;               ///< the level's region (for helix clipping); may differ per level
  Path2D path;                 ///< chains with feeds assigned (0 ⇒ cut.feed_half)
  std::vector<Vec2> predrill;  ///< entry points needing a pre-drilled hole at this level
};

/// How the tool enters uncut material: a pre-drilled hole (drilled first, op 1 of the program),
/// a helix, or a zigzag ramp (both fall back to a plain plunge where they do not fit).
enum class Entry : std::uint8_t { Predrill, Helix, Ramp };

/// "predrill" | "helix" | "ramp"; throws millnet::Error naming the accepted values.
[[nodiscard]] Entry parse_entry(std::string_view name);
[[nodiscard]] std::string_view to_string(Entry e);

struct GcodeParams {
  CutParams cut;
  Entry entry = Entry::Predrill;
  std::string program_name;
  std::vector<std::string> comments;
  double approach_mm = 1.0;      ///< rapid down to this height above the material, then feed
  double entry_angle_deg = 3.0;  ///< helix / ramp descent angle
  /// A helix or ramp starts this high above the level's material top (fed straight down to from
  /// approach height at the plunge feed): the ramp is spent in material, not in air.
  double ramp_clearance_mm = 0.2;
  int decimals = 4;  ///< coordinate decimals (LinuxCNC and GRBL accept 4–6)
};

/// The helix build_program makes to enter a chain at p (Entry::Helix): its centre and radius rh,
/// chosen so that the whole helix of tool centres keeps `clear`'s clearance (radius ≤ 0.45·D,
/// shrunk and turned round p until it fits). It clears a disk of radius rh + D/2 round the centre.
/// Empty when none fits (build_program then ramps or plunges).
[[nodiscard]] std::optional<std::pair<Vec2, double>> entry_helix(const Clearance& clear, const Vec2& p, double D);

/// The program (header, levels expanded, entries resolved): moves with op = 1 for the
/// pre-drilling, comments as Comment items, spindle and the drill-to-end-mill pause as items.
/// Throws millnet::Error on bad parameters (level z ≥ top_z, non-positive feeds…).
[[nodiscard]] gcode::Program build_program(const std::vector<LevelPlan>& levels, const GcodeParams& params);

/// The frame of a pocket program's in-stock figures (gcode::ProgramStats' xy_ lengths, retractions,
/// entries and the feed-map / constant-feed times): safe Z, rapid rate and f₂ of `cut`.
[[nodiscard]] gcode::StockFrame stock_frame(const CutParams& cut);

/// Most Z levels of one program (a pocket or a roughing run).
inline constexpr std::int64_t kMaxLevels = 10000;

/// ceil(depth / step_down) (at least 1), counted in 64 bits and bounded before any level is
/// planned: throws millnet::Error "depth D mm at step-down S mm makes N Z levels; at most 10000"
/// above kMaxLevels, and for a depth or step-down that is not finite and > 0 (issue 15:
/// `--step-down 1e-9` overflowed an int into "levels 1" and one plunge to the floor).
[[nodiscard]] std::int64_t level_count(double depth, double step_down);

/// Evenly split step-downs: depth/level_count(depth, step_down) per level, returns the level Zs
/// (< 0, top-down). Throws as level_count().
[[nodiscard]] std::vector<double> level_zs(double depth, double step_down);

}  // namespace millnet::pocket
