// Pass 1 of the sweep: a program's moves become swept primitives (lines of the tool tip, planar
// arcs, the chords of helical arcs), and each joint's cutter is handed to one of the two
// primitives that meet there (link caps).
#include "sweep_internal.hpp"

#include "millnet/core/error.hpp"

#include <string>

namespace millnet::simulate::sweep {

namespace {

Seg make_line(const gcode::Point3& s, const gcode::Point3& e, double R) {
  Seg g;
  g.type = SegType::Line;
  g.ax = s[0];
  g.ay = s[1];
  g.az = s[2];
  g.bx = e[0];
  g.by = e[1];
  g.bz = e[2];
  g.dx = e[0] - s[0];
  g.dy = e[1] - s[1];
  g.dz = e[2] - s[2];
  g.L2 = g.dx * g.dx + g.dy * g.dy;
  g.L = std::sqrt(g.L2);
  if (g.L > tol::xy_length_mm) {
    g.ux = g.dx / g.L;
    g.uy = g.dy / g.L;
    g.m = g.dz / g.L;
    g.sq1m = std::sqrt(1 + g.m * g.m);
    g.inv1m2 = 1 / (1 + g.m * g.m);
  }
  g.zmin = std::min(g.az, g.bz);
  g.xlo = std::min(g.ax, g.bx) - R;
  g.xhi = std::max(g.ax, g.bx) + R;
  g.ylo = std::min(g.ay, g.by) - R;
  g.yhi = std::max(g.ay, g.by) + R;
  return g;
}

std::string where(const gcode::Program& p, std::size_t item) {
  if (item < p.source_line.size() && p.source_line[item] > 0) return "line " + std::to_string(p.source_line[item]);
  return "item " + std::to_string(item);
}

/// The circle of an arc move from a known start: centre, radius, start angle, sweep (rad, > 0),
/// direction (+1 CCW), and the Z change.
struct Circle {
  double cx = 0, cy = 0, rho0 = 0, th0 = 0, sweep = 0, dir = 1, dz = 0;
};

Circle circle_of(const gcode::Move& mv, const gcode::Point3& start, const gcode::Point3& end,
                 const gcode::Program& program, std::size_t it) {
  if (!std::isfinite(mv.center[0]) || !std::isfinite(mv.center[1]))
    throw Error("simulate: non-finite arc centre at " + where(program, it));
  Circle c;
  c.cx = mv.center[0];
  c.cy = mv.center[1];
  c.rho0 = std::hypot(start[0] - c.cx, start[1] - c.cy);
  if (c.rho0 < tol::min_arc_radius_mm) throw Error("simulate: arc of zero radius at " + where(program, it));
  c.dir = mv.motion == gcode::Motion::ArcCCW ? 1.0 : -1.0;
  c.th0 = std::atan2(start[1] - c.cy, start[0] - c.cx);
  const double th1 = std::atan2(end[1] - c.cy, end[0] - c.cx);
  c.sweep = wrap(c.dir * (th1 - c.th0));
  if (c.sweep < tol::full_circle_rad) c.sweep = kTwoPi;  // same start and end: a full circle
  c.dz = end[2] - start[2];
  return c;
}

/// A planar arc swept exactly; its shadow's box holds the end points and the axis extremes inside
/// the sweep, widened by R.
Seg planar_arc(const gcode::Point3& start, const gcode::Point3& end, const Circle& c, double R) {
  Seg g;
  g.type = SegType::Arc;
  g.ax = start[0];
  g.ay = start[1];
  g.az = start[2];
  g.bx = end[0];
  g.by = end[1];
  g.bz = start[2];
  g.cx = c.cx;
  g.cy = c.cy;
  g.rho0 = c.rho0;
  g.th0 = c.th0;
  g.sweep = c.sweep;
  g.dir = c.dir;
  g.zmin = start[2];
  double xlo = std::min(start[0], end[0]), xhi = std::max(start[0], end[0]);
  double ylo = std::min(start[1], end[1]), yhi = std::max(start[1], end[1]);
  for (int q = 0; q < 4; ++q) {
    const double phi = q * std::numbers::pi / 2;
    if (!in_sweep(g, phi)) continue;
    const double x = c.cx + c.rho0 * std::cos(phi), y = c.cy + c.rho0 * std::sin(phi);
    xlo = std::min(xlo, x);
    xhi = std::max(xhi, x);
    ylo = std::min(ylo, y);
    yhi = std::max(yhi, y);
  }
  g.xlo = xlo - R;
  g.xhi = xhi + R;
  g.ylo = ylo - R;
  g.yhi = yhi + R;
  return g;
}

/// A helical arc as chords of sagitta ≤ the helix chord tolerance (at most the radius).
template <class Add>
void helix_chords(const gcode::Point3& start, const gcode::Point3& end, const Circle& c, double chord_tol, double R,
                  Add add) {
  const double tol = std::min(chord_tol, c.rho0);
  const double max_step = 2 * std::acos(1 - tol / c.rho0);
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(c.sweep / max_step)));
  gcode::Point3 a = start;
  for (std::size_t k = 1; k <= n; ++k) {
    gcode::Point3 b = end;
    if (k < n) {
      const double f = static_cast<double>(k) / static_cast<double>(n);
      const double th = c.th0 + c.dir * c.sweep * f;
      b = {c.cx + c.rho0 * std::cos(th), c.cy + c.rho0 * std::sin(th), start[2] + c.dz * f};
    }
    add(make_line(a, b, R));
    a = b;
  }
}

/// The end of a move from `pos`: the axes it states, the others where they were. Throws on a
/// stated non-finite coordinate.
gcode::Point3 end_of(const gcode::Move& mv, const gcode::Point3& pos, const gcode::Program& program, std::size_t it) {
  gcode::Point3 end = pos;
  for (int k = 0; k < 3; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    if (mv.axes & (1u << k)) {
      if (!std::isfinite(mv.to[ku])) throw Error("simulate: non-finite coordinate at " + where(program, it));
      end[ku] = mv.to[ku];
    }
  }
  return end;
}

bool known(const gcode::Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

}  // namespace

std::vector<Seg> primitives(const gcode::Program& program, const Profile& P, const SweepOptions& opt,
                            std::uint32_t first_serial, std::vector<std::array<double, 3>>& across, SweepResult& res) {
  std::vector<Seg> segs;
  gcode::Point3 pos = opt.start;
  for (std::size_t it = 0; it < program.items.size(); ++it) {
    const auto* mv = std::get_if<gcode::Move>(&program.items[it]);
    if (!mv) continue;
    const gcode::Point3 end = end_of(*mv, pos, program, it);
    const std::uint8_t kind = kind_of(mv->motion);
    (kind == kRapidKind ? res.rapid_moves : res.feed_moves) += 1;
    const std::uint32_t serial = first_serial + static_cast<std::uint32_t>(it);
    if (!known(end)) {  // sweeps nothing
      pos = end;
      continue;
    }
    const bool from_known = known(pos);
    const gcode::Point3 start = from_known ? pos : end;  // unknown start: the tool is placed at the end
    auto add = [&](Seg g) {
      g.kind = kind;
      g.item = it;
      g.serial = serial;
      segs.push_back(g);
    };
    if (kind != kArcKind || !from_known) {
      const Seg g = make_line(start, end, P.R);
      add(g);
      const double len = std::sqrt(g.L2 + g.dz * g.dz);
      (kind == kRapidKind ? res.rapid_length_mm : res.feed_length_mm) += len;
      if (g.L > tol::across_length_mm) across[it] = {-g.uy, g.ux, 0};
    } else {
      const Circle c = circle_of(*mv, start, end, program, it);
      res.feed_length_mm += std::hypot(c.rho0 * c.sweep, c.dz);
      across[it] = {c.cx, c.cy, 1};
      if (std::abs(c.dz) <= tol::planar_arc_dz_mm)
        add(planar_arc(start, end, c, P.R));
      else
        helix_chords(start, end, c, opt.helix_chord_tol_mm, P.R, add);
    }
    pos = end;
  }
  return segs;
}

// At a joint where primitive A ends exactly where B starts (both feeds or both rapids), the
// sphere (cutter) at the joint is applied by one of them only, and the other skips the half of
// its end disk that lies outside its band. Exact: behind the start of a line that does not
// descend (dz ≥ 0) the distance and the height both grow with t, so the minimum there is at the
// joint; likewise beyond the end of a line that does not ascend. Only the visited cells shrink
// (by up to πR²/2 per primitive, a lot for the short chords of a finishing path).
void link_caps(std::vector<Seg>& segs) {
  for (std::size_t i = 0; i + 1 < segs.size(); ++i) {
    Seg& a = segs[i];
    Seg& b = segs[i + 1];
    if ((a.kind == kRapidKind) != (b.kind == kRapidKind)) continue;
    if (a.bx != b.ax || a.by != b.ay || a.bz != b.az) continue;
    if (b.type == SegType::Line && b.L > tol::xy_length_mm && b.dz >= 0) {
      b.skip_start = true;
    } else if (a.type == SegType::Line && a.L > tol::xy_length_mm && a.dz <= 0 &&
               (b.type == SegType::Arc || b.L > tol::xy_length_mm)) {
      // (never onto a vertical move: a retract would then be charged with the joint's cut)
      a.skip_end = true;
    }
  }
}

}  // namespace millnet::simulate::sweep
