// A part's job: operations, their tools, one program (operations.hpp).
#include "millnet/job/operations.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/cycles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <variant>

namespace millnet::job {
namespace {

bool drill_move(const gcode::Item& item) {
  const auto* m = std::get_if<gcode::Move>(&item);
  return m != nullptr && m->op == 1;
}
bool is_move(const gcode::Item& item) { return std::holds_alternative<gcode::Move>(item); }

/// A hole deeper than this many drill diameters is peck-drilled (G83), one diameter per peck: the
/// shop rule for chip evacuation of a twist drill.
constexpr double kPeckDepthDiameters = 3.0;

/// Tools are the same tool when their library ids match (inline tools: their shape).
bool same_tool(const tooling::Tool& a, const tooling::Tool& b) {
  if (!a.id.empty() || !b.id.empty()) return a.id == b.id;
  return a.type == b.type && a.diameter_mm == b.diameter_mm && a.corner_radius_mm == b.corner_radius_mm;
}

bool reaches(const tooling::Tool& t, double depth_mm) { return t.stickout_mm <= 0 || t.stickout_mm >= depth_mm; }

/// "1.500": a length in a message, mm to the micrometre.
std::string mm3(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.3f", v);
  return b;
}

}  // namespace

bool predrills(const gcode::Program& rough) { return std::any_of(rough.items.begin(), rough.items.end(), drill_move); }

std::vector<Operation> roughing_operations(const gcode::Program& rough, const tooling::Tool& mill,
                                           const tooling::Tool* drill, const DrillCut& cut) {
  const auto first = std::find_if(rough.items.begin(), rough.items.end(), drill_move);
  if (first == rough.items.end()) return {{"roughing", mill, rough}};
  if (drill == nullptr) throw Error("job: the roughing program pre-drills its entries and no drill was given");
  const auto last = std::find_if(rough.items.rbegin(), rough.items.rend(), drill_move).base();  // one past
  // The drilling block: the comments and spindle items just before its first move and those just
  // after its last (the "load a drill" comment, its spindle, the pause for the end mill).
  auto begin = first;
  while (begin != rough.items.begin() && !is_move(*(begin - 1))) --begin;
  auto end = last;
  while (end != rough.items.end() && !is_move(*end) && !std::holds_alternative<gcode::Pause>(*end)) ++end;
  if (end != rough.items.end() && std::holds_alternative<gcode::Pause>(*end)) ++end;  // the pause goes too

  Operation drilling{"drilling", *drill, {}};
  drilling.program.header = {"pre-drilled entries of the roughing: " + drill->label()};
  drilling.program.items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, cut.rpm});
  // Each plunge of the roughing's pre-drilling is a hole: a drilling cycle (gcode/cycles.hpp) from
  // the plane the plunge starts at, retracting to the height it rose to; pecks of one diameter where
  // the hole is deeper than kPeckDepthDiameters diameters. The first hole is reached by a plain rapid.
  gcode::Point3 pos{};
  std::uint8_t known = 0;
  const gcode::Move* prev = nullptr;
  for (auto it = first; it != last; ++it) {  // O(items)
    if (const auto* c = std::get_if<gcode::Comment>(&*it); c != nullptr && c->text == "pre-drill") {
      drilling.program.items.emplace_back(*c);
      continue;
    }
    const auto* m = std::get_if<gcode::Move>(&*it);
    if (m == nullptr) continue;  // the drill block's own spindle and comments
    if (m->motion != gcode::Motion::Line) {
      prev = m;
      continue;
    }
    const auto next = std::find_if(it + 1, last, is_move);
    const auto* up = next == last ? nullptr : std::get_if<gcode::Move>(&*next);
    gcode::DrillHole h;
    h.x = m->to[0], h.y = m->to[1], h.bottom_z = m->to[2];
    h.r_z = prev != nullptr ? std::max(prev->to[2], h.bottom_z) : h.bottom_z;
    h.peck_mm = h.r_z - h.bottom_z > kPeckDepthDiameters * drill->diameter_mm ? drill->diameter_mm : 0;
    h.feed = cut.feed_mm_min;
    const double clear = up != nullptr ? std::max(up->to[2], h.r_z) : h.r_z;
    if (known != gcode::kXYZ) {
      gcode::Move reach;
      reach.to = {h.x, h.y, clear};
      drilling.program.items.emplace_back(reach);
      pos = reach.to, known = gcode::kXYZ;
    }
    for (const gcode::Move& d : gcode::drill_cycle_moves(pos, known, h, clear)) {  // O(pecks)
      pos = d.to;
      drilling.program.items.emplace_back(d);
    }
  }
  drilling.program.items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, cut.rpm});

  Operation roughing{"roughing", mill, {}};
  roughing.program.header = rough.header;
  roughing.program.items.assign(rough.items.begin(), begin);
  roughing.program.items.insert(roughing.program.items.end(), end, rough.items.end());
  return {drilling, roughing};
}

Operation facing_operation(const tooling::Tool& mill, const FacingSpec& s) {
  const double d = mill.diameter_mm, r = d / 2;
  if (!(s.blank_top > 0) || !(s.blank_top < s.safe_z))
    throw Error("facing: the blank's top (Z" + mm3(s.blank_top) +
                ") must lie above the stock top Z 0 and below the safe height Z" + mm3(s.safe_z));
  if (!(s.stepover_mm > 0) || s.stepover_mm > d)
    throw Error("facing: the stepover " + mm3(s.stepover_mm) + " mm is not in (0, " + mm3(d) +
                "] mm (the tool's diameter)");
  if (!(s.x1 > s.x0) || !(s.y1 > s.y0)) throw Error("facing: the stock rectangle is empty");
  // Passes along the longer side: u along a pass, v across; (u, v) → (x, y) swapped when the stock is
  // deeper than wide.
  const bool along_x = s.x1 - s.x0 >= s.y1 - s.y0;
  const double u0 = (along_x ? s.x0 : s.y0) - r - kFacingRunOutMm, u1 = (along_x ? s.x1 : s.y1) + r + kFacingRunOutMm;
  const double edge = 0.1 * r;  // the outer passes' overhang past the stock's sides
  const double v_lo = (along_x ? s.y0 : s.x0) + r - edge, v_hi = (along_x ? s.y1 : s.x1) - r + edge;
  const int passes = v_hi > v_lo ? static_cast<int>(std::ceil((v_hi - v_lo) / s.stepover_mm - 1e-9)) + 1 : 1;
  const double v_step = passes > 1 ? (v_hi - v_lo) / (passes - 1) : 0;
  const double v_first = passes > 1 ? v_lo : 0.5 * ((along_x ? s.y0 : s.x0) + (along_x ? s.y1 : s.x1));
  const int levels =
      s.max_depth_mm > 0 ? std::max(1, static_cast<int>(std::ceil(s.blank_top / s.max_depth_mm - 1e-9))) : 1;

  Operation op{"facing", mill, {}};
  op.program.header = {"facing the sawn blank: its top Z" + mm3(s.blank_top) + " down to the stock top Z0 in " +
                       std::to_string(levels) + " level(s) of " + std::to_string(passes) + " passes"};
  auto at = [&](double u, double v, double z) -> gcode::Point3 {
    return along_x ? gcode::Point3{u, v, z} : gcode::Point3{v, u, z};
  };
  auto move = [&](gcode::Motion m, const gcode::Point3& to, double feed) {
    gcode::Move mv;
    mv.motion = m, mv.to = to, mv.feed = feed;
    op.program.items.emplace_back(mv);
  };
  gcode::Move up;  // from the tool change: up to the safe height first, then across to the stock
  up.to = {0, 0, s.safe_z}, up.axes = gcode::kZ;
  op.program.items.emplace_back(up);
  op.program.items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, s.rpm});
  for (int k = 1; k <= levels; ++k) {  // O(levels · passes)
    const double z = k == levels ? 0.0 : s.blank_top * (1.0 - static_cast<double>(k) / levels);
    gcode::Point3 start = at(u0, v_first, s.safe_z);
    move(gcode::Motion::Rapid, start, 0);
    start[2] = std::min(s.safe_z, z + kFacingFeedHeightMm);
    move(gcode::Motion::Rapid, start, 0);
    move(gcode::Motion::Line, at(u0, v_first, z), s.plunge_feed_mm_min);
    for (int p = 0; p < passes; ++p) {
      const double v = v_first + p * v_step;
      const bool forward = p % 2 == 0;
      if (p > 0) move(gcode::Motion::Line, at(forward ? u0 : u1, v, z), s.feed_mm_min);  // the step, off the stock
      move(gcode::Motion::Line, at(forward ? u1 : u0, v, z), s.feed_mm_min);
    }
    const auto* last = std::get_if<gcode::Move>(&op.program.items.back());
    move(gcode::Motion::Rapid, {last->to[0], last->to[1], s.safe_z}, 0);
  }
  op.program.items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, s.rpm});
  return op;
}

const tooling::Tool* drill_for(const std::vector<tooling::Tool>& library, const tooling::Tool& mill, double depth_mm) {
  const tooling::Tool* best = nullptr;
  for (const tooling::Tool& t : library) {  // O(tools)
    if (t.type != tooling::ToolType::Drill || t.diameter_mm > mill.diameter_mm ||
        t.diameter_mm < mill.diameter_mm / 2 || !reaches(t, depth_mm) ||
        (t.flute_length_mm > 0 && t.flute_length_mm < depth_mm))
      continue;
    if (best == nullptr || t.diameter_mm > best->diameter_mm ||
        (t.diameter_mm == best->diameter_mm && t.stickout_mm < best->stickout_mm))
      best = &t;
  }
  return best;
}

const tooling::Tool* tool_that_reaches(const std::vector<tooling::Tool>& library, const tooling::Tool& configured,
                                       double depth_mm) {
  if (reaches(configured, depth_mm)) return &configured;
  const tooling::Tool* best = nullptr;
  for (const tooling::Tool& t : library)  // O(tools)
    if (t.type == configured.type && t.diameter_mm == configured.diameter_mm &&
        t.cutter().profile_corner_radius() == configured.cutter().profile_corner_radius() &&
        t.flutes == configured.flutes && t.material == configured.material && t.stickout_mm > 0 &&
        t.stickout_mm >= depth_mm && (best == nullptr || t.stickout_mm < best->stickout_mm))
      best = &t;
  return best;
}

const tooling::Tool* longest_of_shape(const std::vector<tooling::Tool>& library, tooling::ToolType type,
                                      double diameter_mm, double corner_radius_mm) {
  const tooling::Tool* best = nullptr;
  for (const tooling::Tool& t : library)  // O(tools)
    if (t.type == type && std::abs(t.diameter_mm - diameter_mm) <= 1e-9 &&
        std::abs(t.corner_radius_mm - corner_radius_mm) <= 1e-9 && t.stickout_mm > 0 &&
        (best == nullptr || t.stickout_mm > best->stickout_mm))
      best = &t;
  return best;
}

const tooling::Tool* semi_finishing_tool(const std::vector<tooling::Tool>& library, const tooling::Tool& finisher,
                                         const tooling::Tool& rough, double depth_of_cut_mm, double depth_mm) {
  const tooling::Tool* best = nullptr;
  for (const tooling::Tool& t : library) {  // O(tools)
    if (t.type != tooling::ToolType::Ball || t.diameter_mm <= finisher.diameter_mm ||
        t.diameter_mm > rough.diameter_mm || !reaches(t, depth_mm) ||
        (t.flute_length_mm > 0 && t.flute_length_mm < depth_of_cut_mm))
      continue;
    if (best == nullptr || t.diameter_mm < best->diameter_mm ||
        (t.diameter_mm == best->diameter_mm && t.stickout_mm < best->stickout_mm))
      best = &t;
  }
  return best;
}

std::vector<const tooling::Tool*> semi_finishing_tools(const std::vector<tooling::Tool>& library,
                                                       const tooling::Tool& finisher, const tooling::Tool& rough,
                                                       double depth_mm) {
  std::vector<const tooling::Tool*> out;
  for (const tooling::Tool& t : library)  // O(tools)
    if (t.type == tooling::ToolType::Ball && t.diameter_mm > finisher.diameter_mm &&
        t.diameter_mm <= rough.diameter_mm && reaches(t, depth_mm))
      out.push_back(&t);
  std::stable_sort(out.begin(), out.end(), [](const tooling::Tool* a, const tooling::Tool* b) {
    return a->diameter_mm != b->diameter_mm ? a->diameter_mm < b->diameter_mm : a->stickout_mm < b->stickout_mm;
  });
  return out;
}

double scallop_step(double radius, double scallop_mm) {
  const double h = std::min(scallop_mm, radius);
  return 2 * std::sqrt(std::max(0.0, 2 * radius * h - h * h));
}

std::vector<Operation> numbered(std::vector<Operation> ops) {
  int next = 0;
  for (const Operation& op : ops) next = std::max({next, op.tool.number, op.tool.length_offset});
  for (std::size_t i = 0; i < ops.size(); ++i) {
    if (ops[i].tool.number > 0) continue;
    int n = 0;
    for (std::size_t j = 0; j < i; ++j)
      if (same_tool(ops[j].tool, ops[i].tool)) n = ops[j].tool.number;
    ops[i].tool.number = n > 0 ? n : ++next;
  }
  return ops;
}

std::vector<tooling::Tool> tools_of(const std::vector<Operation>& ops) {
  std::vector<tooling::Tool> tools;
  for (const Operation& op : ops)
    if (std::none_of(tools.begin(), tools.end(), [&](const auto& t) { return t.number == op.tool.number; }))
      tools.push_back(op.tool);
  return tools;
}

double deepest_z(const gcode::Program& program) {
  double z = 0;
  for (const gcode::Item& i : program.items)
    if (const auto* m = std::get_if<gcode::Move>(&i)) z = std::min(z, m->to[2]);
  return z;
}

namespace {
void append_operation(gcode::Program& out, const Operation& op) {
  if (op.tool.number <= 0)
    throw Error("job: operation '" + op.name + "' has a tool without a number (" + op.tool.label() + ")");
  out.items.emplace_back(gcode::ToolChange{op.tool.number, op.tool.label(), op.tool.length_offset_register()});
  for (const std::string& h : op.program.header) out.items.emplace_back(gcode::Comment{h});
  out.items.insert(out.items.end(), op.program.items.begin(), op.program.items.end());
}
}  // namespace

gcode::Program operation_program(const Operation& op, std::vector<std::string> header) {
  gcode::Program p;
  p.header = std::move(header);
  append_operation(p, op);
  return p;
}

gcode::Program job_program(const std::vector<Operation>& ops, std::vector<std::string> header) {
  gcode::Program p;
  p.header = std::move(header);
  for (std::size_t i = 0; i < ops.size(); ++i) {  // O(items)
    p.items.emplace_back(gcode::Comment{"operation " + std::to_string(i + 1) + " of " + std::to_string(ops.size()) +
                                        ": " + ops[i].name});
    append_operation(p, ops[i]);
  }
  return p;
}

std::vector<ToolRun> split_at_tool_changes(const gcode::Program& program) {
  std::vector<ToolRun> runs;
  const bool lines = program.source_line.size() == program.items.size();
  for (std::size_t i = 0; i < program.items.size(); ++i) {  // O(items)
    if (const auto* tc = std::get_if<gcode::ToolChange>(&program.items[i])) {
      runs.push_back({tc->number, {}});
    } else if (runs.empty()) {
      runs.push_back({0, {}});
    }
    gcode::Program& p = runs.back().program;
    p.items.push_back(program.items[i]);
    if (lines) p.source_line.push_back(program.source_line[i]);
  }
  // Comments before the first tool change (the first operation's name) are no run of their own.
  if (runs.size() > 1 && runs.front().tool_number == 0 &&
      std::none_of(runs.front().program.items.begin(), runs.front().program.items.end(), is_move))
    runs.erase(runs.begin());
  if (!runs.empty()) runs.front().program.header = program.header;
  return runs;
}

HolderClearance holder_clearance(const gcode::Program& program, const tooling::Tool& tool,
                                 const simulate::GridSpec& grid, const std::vector<double>& design, double coarse_mm,
                                 double step_mm) {
  HolderClearance hc;
  // The part max-pooled onto coarse cells (−inf where no part), then dilated by the holder's radius
  // plus a coarse cell's diagonal (a point anywhere in its cell, a part point anywhere in its own):
  // conservative, it may report the holder nearer than it is by up to that diagonal sideways.
  const double w = grid.cell * static_cast<double>(grid.nx), h = grid.cell * static_cast<double>(grid.ny);
  const auto cx = static_cast<std::size_t>(std::ceil(w / coarse_mm)),
             cy = static_cast<std::size_t>(std::ceil(h / coarse_mm));
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  if (cx == 0 || cy == 0 || design.size() != grid.cells()) return hc;  // no part to clear
  std::vector<double> pooled(cx * cy, kNone);
  for (std::size_t iy = 0; iy < grid.ny; ++iy)  // O(cells)
    for (std::size_t ix = 0; ix < grid.nx; ++ix) {
      const double z = design[iy * grid.nx + ix];
      if (std::isnan(z)) continue;
      const auto px = std::min(cx - 1, static_cast<std::size_t>((grid.x(ix) - grid.x0) / coarse_mm));
      const auto py = std::min(cy - 1, static_cast<std::size_t>((grid.y(iy) - grid.y0) / coarse_mm));
      pooled[py * cx + px] = std::max(pooled[py * cx + px], z);
    }
  const double radius = std::max(tool.holder_diameter_mm, tool.diameter_mm) / 2 + coarse_mm * std::numbers::sqrt2;
  const auto k = static_cast<std::ptrdiff_t>(std::ceil(radius / coarse_mm));
  std::vector<double> dilated(cx * cy, kNone);
  for (std::size_t py = 0; py < cy; ++py)  // O(coarse cells × disk)
    for (std::size_t px = 0; px < cx; ++px) {
      double m = kNone;
      for (std::ptrdiff_t dy = -k; dy <= k; ++dy)
        for (std::ptrdiff_t dx = -k; dx <= k; ++dx) {
          const auto qx = static_cast<std::ptrdiff_t>(px) + dx, qy = static_cast<std::ptrdiff_t>(py) + dy;
          if (qx < 0 || qy < 0 || qx >= static_cast<std::ptrdiff_t>(cx) || qy >= static_cast<std::ptrdiff_t>(cy))
            continue;
          if (std::hypot(static_cast<double>(dx), static_cast<double>(dy)) * coarse_mm > radius) continue;
          m = std::max(m, pooled[static_cast<std::size_t>(qy) * cx + static_cast<std::size_t>(qx)]);
        }
      dilated[py * cx + px] = m;
    }
  auto part_under = [&](double x, double y) {
    const double fx = std::floor((x - grid.x0) / coarse_mm), fy = std::floor((y - grid.y0) / coarse_mm);
    const double px = std::clamp(fx, 0.0, static_cast<double>(cx - 1)),
                 py = std::clamp(fy, 0.0, static_cast<double>(cy - 1));
    // Off the grid by more than the radius: nothing of the part under the holder.
    if (std::abs(fx - px) * coarse_mm > radius || std::abs(fy - py) * coarse_mm > radius) return kNone;
    return dilated[static_cast<std::size_t>(py) * cx + static_cast<std::size_t>(px)];
  };
  hc.deepest_tip_z = std::numeric_limits<double>::infinity();
  hc.reach_needed_mm = kNone;
  auto sample = [&](const gcode::Point3& p) {
    hc.deepest_tip_z = std::min(hc.deepest_tip_z, p[2]);
    const double top = part_under(p[0], p[1]);
    if (top == kNone) return;
    if (top - p[2] > hc.reach_needed_mm) {
      hc.reach_needed_mm = top - p[2];
      hc.worst = p;
    }
  };
  gcode::Point3 pos{std::nan(""), std::nan(""), std::nan("")};
  for (const gcode::Item& item : program.items) {  // O(moves × length / step)
    const auto* m = std::get_if<gcode::Move>(&item);
    if (m == nullptr) continue;
    gcode::Point3 end = pos;
    for (std::size_t a = 0; a < 3; ++a)
      if (m->axes & (1U << a)) end[a] = m->to[a];
    if (std::isnan(end[0]) || std::isnan(end[1]) || std::isnan(end[2])) {
      pos = end;
      continue;
    }
    if (!std::isnan(pos[0]) && !std::isnan(pos[1]) && !std::isnan(pos[2])) {
      const bool arc = m->motion == gcode::Motion::ArcCW || m->motion == gcode::Motion::ArcCCW;
      double a0 = 0, sweep = 0, r = 0;
      if (arc) {
        r = std::hypot(pos[0] - m->center[0], pos[1] - m->center[1]);
        a0 = std::atan2(pos[1] - m->center[1], pos[0] - m->center[0]);
        const double a1 = std::atan2(end[1] - m->center[1], end[0] - m->center[0]);
        sweep = m->motion == gcode::Motion::ArcCCW ? a1 - a0 : a0 - a1;
        while (sweep <= 1e-12) sweep += 2 * std::numbers::pi;  // a full circle when the ends meet
      }
      const double len = arc ? r * sweep : std::hypot(end[0] - pos[0], end[1] - pos[1]);
      const auto n = static_cast<std::size_t>(std::ceil(len / step_mm));
      for (std::size_t s = 1; s < n; ++s) {
        const double f = static_cast<double>(s) / static_cast<double>(n);
        if (arc) {
          const double a = a0 + (m->motion == gcode::Motion::ArcCCW ? 1 : -1) * sweep * f;
          sample({m->center[0] + r * std::cos(a), m->center[1] + r * std::sin(a), pos[2] + (end[2] - pos[2]) * f});
        } else {
          sample({pos[0] + (end[0] - pos[0]) * f, pos[1] + (end[1] - pos[1]) * f, pos[2] + (end[2] - pos[2]) * f});
        }
      }
    }
    sample(end);
    pos = end;
  }
  if (hc.reach_needed_mm == kNone) hc.reach_needed_mm = 0;
  if (!std::isfinite(hc.deepest_tip_z)) hc.deepest_tip_z = 0;
  hc.checked = tool.stickout_mm > 0 && tool.holder_diameter_mm > 0;
  hc.min_clearance_mm = tool.stickout_mm - hc.reach_needed_mm;
  return hc;
}

}  // namespace millnet::job
