// What a program read from outside will cost its users (see bounds.hpp).
#include "millnet/gcode/bounds.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/gcode/stats.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <variant>

namespace millnet::gcode {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
/// Bytes each item holds: a planner block of stats() (length, direction, speed, flag, entry speed),
/// a swept primitive of the simulator (measured: 2.4 GB for 5·10⁶ helix chords), a point of the
/// preview (position, kind, feed, line), a program item read (the variant and its source line).
constexpr double kBlockBytes = 64;
constexpr double kSweepPrimitiveBytes = 480;
constexpr double kPreviewPointBytes = 64;
constexpr double kLineBytes = 128;

}  // namespace

double arc_chords(double radius_mm, double sweep_rad, double sagitta_mm) {
  const double step = radius_mm > sagitta_mm ? 2 * std::acos(1 - sagitta_mm / radius_mm) : sweep_rad;
  return std::max(1.0, std::ceil(sweep_rad / step));
}

std::vector<WorkEstimate> program_work(const Program& program, std::string_view source, const ProgramUse& use) {
  double moves = 0, timing = 0, sweep = 0, preview = 0;
  const double step = std::max(use.preview_step_deg, 0.5) * std::numbers::pi / 180;
  Point3 pos{0, 0, 0};
  std::uint8_t known = 0;
  for (const Item& item : program.items) {  // O(moves)
    const Move* m = std::get_if<Move>(&item);
    if (m == nullptr) continue;
    ++moves;
    Point3 from = pos;
    for (std::size_t a = 0; a < 3; ++a)
      if ((known & (1U << a)) == 0) from[a] = m->to[a];
    const bool from_xy = (known & (kX | kY)) == (kX | kY);
    known |= m->axes;
    pos = m->to;
    if (m->motion != Motion::ArcCW && m->motion != Motion::ArcCCW) {
      const double dx = m->to[0] - from[0], dy = m->to[1] - from[1], dz = m->to[2] - from[2];
      if (std::sqrt(dx * dx + dy * dy + dz * dz) >= 1e-9) ++timing;  // stats() skips zero-length blocks
      ++sweep, ++preview;
      continue;
    }
    const bool ccw = m->motion == Motion::ArcCCW;
    const double cx = m->center[0], cy = m->center[1];
    const double r = std::hypot(from[0] - cx, from[1] - cy);
    const double a0 = std::atan2(from[1] - cy, from[0] - cx), a1 = std::atan2(m->to[1] - cy, m->to[0] - cx);
    // The sweep as stats() and the simulator take it: (0, 2π], equal ends a full circle.
    double s = std::fmod(ccw ? a1 - a0 : a0 - a1, kTwoPi);
    if (s < 0) s += kTwoPi;
    if (s <= 1e-12) s = kTwoPi;
    timing += arc_chords(r, s, kArcChordToleranceMm);
    const bool helix = std::abs(m->to[2] - from[2]) > 1e-12;
    if (helix && from_xy && r >= 1e-9) {  // the simulator's helix: chords of sagitta min(tol, r)
      const double tol = std::min(use.helix_sagitta_mm, r);
      sweep += std::max(1.0, std::ceil(s / (2 * std::acos(1 - tol / r))));
    } else {
      ++sweep;
    }
    preview += std::max(1.0, std::ceil(s / step));
  }
  const std::string name(source);
  std::vector<WorkEstimate> out;
  if (use.simulate) {
    out.push_back(
        {name + ": its moves, arcs in chords of " + format_size(kArcChordToleranceMm) + " mm for the motion-time model",
         timing, "planner blocks", timing * kBlockBytes});
    out.push_back({name + ": its moves, helices in chords of " + format_size(use.helix_sagitta_mm) +
                       " mm for the z-map simulator",
                   sweep, "swept primitives", sweep * kSweepPrimitiveBytes});
  }
  if (use.preview)
    out.push_back({name + ": its moves, arcs in steps of " + format_size(std::max(use.preview_step_deg, 0.5)) +
                       "° for the 3D preview",
                   preview, "path points", preview * kPreviewPointBytes});
  (void)moves;
  return out;
}

Program read_checked(std::string_view text, std::string_view source, const WorkLimits& limits, const ProgramUse& use) {
  const double lines = static_cast<double>(std::count(text.begin(), text.end(), '\n')) + 1;
  check_work({std::string(source) + ": " + format_count(lines) + " lines of G-code", lines, "program items",
              lines * kLineBytes},
             limits);
  Program p = read(text, source);
  const bool moves =
      std::any_of(p.items.begin(), p.items.end(), [](const Item& i) { return std::holds_alternative<Move>(i); });
  if (!moves)
    throw Error(std::string(source) + ": no motion (no G0, G1, G2 or G3 move): nothing to " +
                (use.simulate ? "simulate" : "show"));
  for (const WorkEstimate& e : program_work(p, source, use)) check_work(e, limits);
  return p;
}

}  // namespace millnet::gcode
