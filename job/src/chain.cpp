// A part's programs machined in order on one stock (chain.hpp).
#include "millnet/job/chain.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/rest.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <variant>

namespace millnet::job {

simulate::ZMap block_stock(const Design& design, const SimParams& sim, double top) {
  return simulate::ZMap::flat(design.grid, top, sim.max_bytes());
}

namespace {

/// Paints `stock`'s cells onto the raster `f` (part heights): a point takes them only when its
/// square (half a step each way) lies within the z-map's grid, each the highest of the cells whose
/// centres its square holds, or (a step finer than the cell) the cell it lies in. O(cells + points).
void paint_stock(ingest::HeightField& f, const simulate::ZMap& stock, const Frame& frame) {
  const simulate::GridSpec& g = stock.spec();
  const auto& h = stock.heights();
  const double x0 = f.x0, y0 = f.y0, step = f.step_x;
  const double gx0 = g.x0, gy0 = g.y0, gx1 = g.x0 + static_cast<double>(g.nx) * g.cell,
               gy1 = g.y0 + static_cast<double>(g.ny) * g.cell, half = 0.5 * step;
  auto on_grid = [&](int i, int j) {
    const double px = x0 + j * step, py = y0 + i * step;
    return px - half >= gx0 && px + half <= gx1 && py - half >= gy0 && py + half <= gy1;
  };
  std::vector<std::uint8_t> seen(f.z.size(), 0);
  for (std::size_t iy = 0; iy < g.ny; ++iy)  // O(cells): each cell into the point whose square holds it
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double j = std::round((g.x(ix) - x0) / step), i = std::round((g.y(iy) - y0) / step);
      if (j < 0 || i < 0 || j >= f.nx || i >= f.ny || !on_grid(static_cast<int>(i), static_cast<int>(j))) continue;
      const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(f.nx) + static_cast<std::size_t>(j);
      const double z = h[iy * g.nx + ix] - frame.z_shift();  // part frame
      f.z[k] = seen[k] != 0 ? std::max(f.z[k], z) : z;
      seen[k] = 1;
    }
  for (int i = 0; i < f.ny; ++i)  // O(points)
    for (int j = 0; j < f.nx; ++j) {
      const std::size_t k = static_cast<std::size_t>(i) * static_cast<std::size_t>(f.nx) + static_cast<std::size_t>(j);
      if (seen[k] != 0 || !on_grid(i, j)) continue;
      const auto cx = std::min(g.nx - 1, static_cast<std::size_t>((x0 + j * step - gx0) / g.cell));
      const auto cy = std::min(g.ny - 1, static_cast<std::size_t>((y0 + i * step - gy0) / g.cell));
      f.z[k] = h[cy * g.nx + cx] - frame.z_shift();
    }
}

}  // namespace

ingest::HeightField stock_top_field(const simulate::ZMap& stock, const Frame& frame, double x0, double y0, double x1,
                                    double y1, double step, const simulate::ZMap* surround) {
  if (!(step > 0) || !(x1 >= x0) || !(y1 >= y0)) throw Error("stock: the roughing's raster needs step > 0 over a box");
  ingest::HeightField f;
  f.x0 = x0, f.y0 = y0, f.step_x = step, f.step_y = step;
  f.nx = static_cast<int>(std::ceil((x1 - x0) / step)) + 1;
  f.ny = static_cast<int>(std::ceil((y1 - y0) / step)) + 1;
  const auto n = static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny);
  f.z.assign(n, frame.stock_top);  // off the stock's grids: the block
  f.hit.assign(n, 1);
  if (surround != nullptr) paint_stock(f, *surround, frame);  // the block's surround, coarse
  paint_stock(f, stock, frame);                               // the footprint, at the z-map's cell
  f.z_min = *std::min_element(f.z.begin(), f.z.end());
  f.z_max = *std::max_element(f.z.begin(), f.z.end());
  return f;
}

simulate::ZMap block_surround(const Frame& frame, const std::array<double, 4>& sides, double top,
                              const SimParams& sim) {
  const double c = kSurroundCellMm;
  const double bx0 = -sides[0], bx1 = frame.width + sides[1], by0 = -sides[2], by1 = frame.depth + sides[3];
  simulate::GridSpec g;
  g.cell = c;
  g.x0 = bx0 - c, g.y0 = by0 - c;
  g.nx = static_cast<std::size_t>(std::ceil((bx1 - bx0) / c)) + 2;
  g.ny = static_cast<std::size_t>(std::ceil((by1 - by0) / c)) + 2;
  g.check();
  std::vector<double> h(g.cells());
  const double none = frame.program_bottom() - 1.0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)  // O(surround cells)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double x = g.x(ix), y = g.y(iy);
      h[iy * g.nx + ix] = x >= bx0 && x <= bx1 && y >= by0 && y <= by1 ? top : none;
    }
  return simulate::ZMap::from_heights(g, h, 0.0, 0.0, sim.max_bytes());
}

void machine_surround(simulate::ZMap& surround, const std::vector<ChainStep>& steps) {
  for (const ChainStep& s : steps) (void)simulate::machine(surround, *s.program, s.cutter);  // O(moves · cells)
}

void uncovered_to(ingest::HeightField& top, double none) {
  for (std::size_t k = 0; k < top.z.size(); ++k)  // O(points)
    if (top.hit[k] == 0) top.z[k] = none;
  top.z_min = std::min(top.z_min, none);
}

simulate::ZMap stock_from_raster(const ingest::HeightField& top, const Design& design, const Frame& frame,
                                 const SimParams& sim) {
  const simulate::GridSpec& g = design.grid;
  if (top.z.size() != g.cells() || top.hit.size() != g.cells())
    throw Error("stock: the stock's raster has " + std::to_string(top.z.size()) + " points, the part's grid " +
                std::to_string(g.cells()) + " cells");
  std::vector<double> h(g.cells());
  for (std::size_t c = 0; c < h.size(); ++c)  // O(cells)
    h[c] = top.hit[c] ? top.z[c] + frame.z_shift() : frame.program_bottom();
  return simulate::ZMap::from_heights(g, h, 0.0, 0.0, sim.max_bytes());
}

StockDeparture stock_departure(const simulate::ZMap& stock, const Design& design) {
  const simulate::GridSpec& g = stock.spec();
  StockDeparture d;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {  // O(cells)
      const double h = stock.at(ix, iy), design_h = design.heights[iy * g.nx + ix];
      if (h > d.above_top_mm) d.above_top_mm = h, d.above_at = {g.x(ix), g.y(iy)};
      if (!std::isnan(design_h) && design_h - h > d.below_design_mm)
        d.below_design_mm = design_h - h, d.below_at = {g.x(ix), g.y(iy)};
    }
  return d;
}

/// The most stock above the design and where. O(cells).
void left_above(const simulate::ZMap& stock, const Design& design, StepResult& st) {
  const simulate::GridSpec& g = stock.spec();
  st.max_left_mm = 0;
  for (std::size_t iy = 0; iy < g.ny; ++iy)
    for (std::size_t ix = 0; ix < g.nx; ++ix) {
      const double d = design.heights[iy * g.nx + ix];
      if (std::isnan(d)) continue;
      const double left = stock.at(ix, iy) - d;
      if (left > st.max_left_mm) {
        st.max_left_mm = left;
        st.max_left_at = {g.x(ix), g.y(iy)};
      }
    }
}

StepResult left_above(const simulate::ZMap& stock, const Design& design) {
  StepResult st;
  left_above(stock, design, st);
  return st;
}

namespace {

/// The 3D length of every program item that is a feed move (0 for the rest), from the previous
/// position (unknown before the first: 0). Arcs: radius × swept angle in XY with their Z travel.
std::vector<double> feed_lengths(const gcode::Program& program) {
  std::vector<double> out(program.items.size(), 0.0);
  std::optional<gcode::Point3> at;
  for (std::size_t i = 0; i < program.items.size(); ++i) {  // O(items)
    const auto* m = std::get_if<gcode::Move>(&program.items[i]);
    if (m == nullptr) continue;
    if (at && m->motion != gcode::Motion::Rapid) {
      const double dz = m->to[2] - (*at)[2];
      if (m->motion == gcode::Motion::Line) {
        out[i] = std::hypot(m->to[0] - (*at)[0], m->to[1] - (*at)[1], dz);
      } else {
        const double r = std::hypot((*at)[0] - m->center[0], (*at)[1] - m->center[1]);
        const double a0 = std::atan2((*at)[1] - m->center[1], (*at)[0] - m->center[0]);
        const double a1 = std::atan2(m->to[1] - m->center[1], m->to[0] - m->center[0]);
        double sweep = m->motion == gcode::Motion::ArcCCW ? a1 - a0 : a0 - a1;
        while (sweep <= 1e-12) sweep += 2 * std::numbers::pi;  // a full circle when the ends meet
        out[i] = std::hypot(r * sweep, dz);
      }
    }
    at = m->to;
  }
  return out;
}

/// Per program item: 1 when it is a feed move whose swept band (its XY box — an arc's whole
/// circle — grown by the cutter's radius) reaches the z-map's area, 0 otherwise. A move entirely
/// outside (the roughing's passes round the part in the stock's margin, beyond the design's grid)
/// cuts what the z-map does not hold: its material is not measured, so it is neither cutting nor
/// air. O(items).
std::vector<std::uint8_t> feeds_over_grid(const gcode::Program& program, const simulate::GridSpec& g, double radius) {
  std::vector<std::uint8_t> out(program.items.size(), 0);
  const double gx1 = g.x0 + static_cast<double>(g.nx) * g.cell, gy1 = g.y0 + static_cast<double>(g.ny) * g.cell;
  std::optional<gcode::Point3> at;
  for (std::size_t i = 0; i < program.items.size(); ++i) {  // O(items)
    const auto* m = std::get_if<gcode::Move>(&program.items[i]);
    if (m == nullptr) continue;
    if (at && m->motion != gcode::Motion::Rapid) {
      double x0 = std::min((*at)[0], m->to[0]), x1 = std::max((*at)[0], m->to[0]);
      double y0 = std::min((*at)[1], m->to[1]), y1 = std::max((*at)[1], m->to[1]);
      if (m->motion != gcode::Motion::Line) {
        const double r = std::hypot((*at)[0] - m->center[0], (*at)[1] - m->center[1]);
        x0 = std::min(x0, m->center[0] - r), x1 = std::max(x1, m->center[0] + r);
        y0 = std::min(y0, m->center[1] - r), y1 = std::max(y1, m->center[1] + r);
      }
      out[i] = x1 + radius >= g.x0 && x0 - radius <= gx1 && y1 + radius >= g.y0 && y0 - radius <= gy1 ? 1 : 0;
    }
    at = m->to;
  }
  return out;
}

}  // namespace

std::vector<ChainStep> chain_steps(const std::vector<Operation>& ops) {
  std::vector<ChainStep> out;
  out.reserve(ops.size());
  for (const Operation& op : ops) out.push_back({&op.program, op.tool.cutter()});
  return out;
}

const char* kind_name(MoveRecord::Kind k) {
  switch (k) {
    case MoveRecord::Kind::Rapid: return "rapid";
    case MoveRecord::Kind::Outside: return "outside";
    case MoveRecord::Kind::Cut: return "cut";
    case MoveRecord::Kind::Air: return "air";
  }
  return "?";
}

std::string moves_csv(const std::vector<StepResult>& steps, const std::vector<std::string>& programs,
                      const std::array<double, 2>& origin) {
  static constexpr std::array<const char*, 4> kMotion{"G0", "G1", "G2", "G3"};
  std::string out = "program,line,motion,x,y,z,length_mm,cut_mm,kind\n";
  char row[160];
  for (std::size_t k = 0; k < steps.size(); ++k) {  // O(moves)
    const std::string& name = k < programs.size() ? programs[k] : std::to_string(k + 1);
    for (const MoveRecord& m : steps[k].moves) {
      const int n = std::snprintf(row, sizeof row, ",%zu,%s,%.4f,%.4f,%.4f,%.6f,%.6f,%s\n", m.line,
                                  kMotion.at(static_cast<std::size_t>(m.motion)), m.to[0] - origin[0],
                                  m.to[1] - origin[1], m.to[2], m.length_mm, m.cut_mm, kind_name(m.kind));
      out += name;
      out.append(row, static_cast<std::size_t>(std::min<int>(n, static_cast<int>(sizeof row) - 1)));
    }
  }
  return out;
}

std::vector<StepResult> machine_steps(simulate::ZMap& stock, const Design& design, const std::vector<ChainStep>& steps,
                                      const gcode::MotionModel& machine, bool record_moves) {
  std::vector<StepResult> out;
  for (const ChainStep& s : steps) {  // O(steps)
    const simulate::SweepResult sw = simulate::machine(stock, *s.program, s.cutter);
    StepResult st;
    st.stats = gcode::stats(*s.program, machine);
    // The depth of cut the flutes take: the axial engagement (simulate::SweepResult), where it is largest.
    const auto deepest = std::max_element(sw.item_max_engage_mm.begin(), sw.item_max_engage_mm.end());
    st.max_depth_of_cut_mm = deepest == sw.item_max_engage_mm.end() ? 0.0 : *deepest;
    const auto item = static_cast<std::size_t>(deepest - sw.item_max_engage_mm.begin());
    if (st.max_depth_of_cut_mm > 0 && item < s.program->items.size()) {
      if (const auto* m = std::get_if<gcode::Move>(&s.program->items[item])) st.max_cut_at = m->to;
      if (item < s.program->source_line.size()) st.max_cut_line = s.program->source_line[item];
    }
    st.cutting_rapids = sw.cutting_rapids.size();
    const std::vector<double> len = feed_lengths(*s.program);
    const std::vector<std::uint8_t> over = feeds_over_grid(*s.program, stock.spec(), s.cutter.radius());
    // Air runs: consecutive air feed moves, closed by a cutting move, a rapid or a move off the z-map.
    const double bridge = 2 * s.cutter.radius();
    double run = 0;
    const auto close_run = [&] {
      if (run > bridge) st.air_run_feed_mm += run;
      run = 0;
    };
    for (std::size_t i = 0; i < len.size(); ++i) {  // O(items)
      const auto* m = std::get_if<gcode::Move>(&s.program->items[i]);
      if (m == nullptr) continue;
      const double cut = i < sw.item_max_cut_mm.size() ? sw.item_max_cut_mm[i] : 0.0;
      MoveRecord::Kind kind = MoveRecord::Kind::Cut;
      if (m->motion == gcode::Motion::Rapid) {
        kind = MoveRecord::Kind::Rapid;
        close_run();
      } else if (!over[i]) {
        kind = MoveRecord::Kind::Outside;
        st.outside_feed_mm += len[i];
        close_run();
      } else {
        st.feed_mm += len[i];
        if (cut < kAirCutMm) {  // (a move of no length that cuts nothing is air too: it adds 0 mm)
          kind = MoveRecord::Kind::Air;
          st.air_feed_mm += len[i];
          run += len[i];
        } else if (len[i] > 0) {
          close_run();
        }
      }
      if (record_moves) {  // a rapid's length straight from where the one before ended
        const double length = kind != MoveRecord::Kind::Rapid ? len[i]
                              : st.moves.empty()
                                  ? 0.0
                                  : std::hypot(m->to[0] - st.moves.back().to[0], m->to[1] - st.moves.back().to[1],
                                               m->to[2] - st.moves.back().to[2]);
        st.moves.push_back({i, i < s.program->source_line.size() ? s.program->source_line[i] : 0, m->motion, m->to,
                            length, cut, kind});
      }
    }
    close_run();
    left_above(stock, design, st);
    out.push_back(st);
  }
  return out;
}

ChainResult machine_chain(simulate::ZMap& stock, const Design& design, const std::vector<ChainStep>& steps,
                          const gcode::MotionModel& machine, const SimParams& sim, bool score_rest, bool record_moves) {
  ChainResult r;
  // The exact gouge check's programs per z-map pass: none for the passes of a stock read back.
  std::vector<simulate::PassTool> passes(stock.passes());
  for (const ChainStep& s : steps) passes.push_back({s.program, s.cutter});
  // A rest step: the last tool smaller than the one before; the reference's rest before it.
  if (score_rest && steps.size() >= 2 && steps.back().cutter.radius() < steps[steps.size() - 2].cutter.radius() &&
      steps[steps.size() - 2].cutter.shape() != tooling::CutterType::Flat) {
    r.rest_step = true;
    r.rest_reference = steps[steps.size() - 2].cutter;
    const std::vector<ChainStep> before(steps.begin(), steps.end() - 1);
    r.steps = machine_steps(stock, design, before, machine, record_moves);
    r.rest_above_before = simulate::cells_above(stock, design.heights, sim.rest_threshold_mm);
    r.rest_area_before_mm2 =
        static_cast<double>(std::count(r.rest_above_before.begin(), r.rest_above_before.end(), 1)) * stock.spec().cell *
        stock.spec().cell;
    const std::vector<ChainStep> last{steps.back()};
    r.steps.push_back(machine_steps(stock, design, last, machine, record_moves).front());
    r.rest_area_after_mm2 = simulate::area_above_mm2(stock, design.heights, sim.rest_threshold_mm);
  } else {
    r.steps = machine_steps(stock, design, steps, machine, record_moves);
  }
  simulate::MetricsOptions mo;
  if (!steps.empty()) {
    mo = sim.metrics_options(steps.back().cutter);  // scallop and rest of the last tool
  } else {
    mo = sim.metrics_options(tooling::Cutter::ball(2));
    mo.cutter.reset();
  }
  r.metrics = simulate::surface_metrics(stock, design.heights, mo);
  if (design.solid)
    simulate::confirm_gouges(r.metrics, stock, design.heights, *design.solid, passes, sim.gouge_options());
  return r;
}

RestSplit split_rest(const ingest::Mesh& mesh, const Design& design, const simulate::ZMap& stock, const ChainResult& r,
                     const std::vector<ChainStep>& steps, const tooling::Cutter& tool, double threshold_mm,
                     double floor_z, double mesh_z_shift) {
  const finish::RestRegions ref = finish::unreachable_regions(mesh, r.rest_reference, threshold_mm);
  const finish::RestRegions own = finish::unreachable_regions(mesh, tool, threshold_mm);
  const simulate::GridSpec& g = design.grid;
  auto node = [&g](const finish::RestRegions& u, std::size_t i) {
    return std::pair{std::lround((g.y(i / g.nx) - u.y0) / u.cell), std::lround((g.x(i % g.nx) - u.x0) / u.cell)};
  };
  auto on = [](const finish::RestRegions& u, long bi, long bj) {
    return bi >= 0 && bj >= 0 && bi < u.ny && bj < u.nx && u.mask[static_cast<std::size_t>(bi * u.nx + bj)] != 0;
  };
  auto in = [&](const finish::RestRegions& u, std::size_t i) {
    const auto [bi, bj] = node(u, i);
    return on(u, bi, bj);
  };
  const std::vector<std::uint8_t> above = simulate::cells_above(stock, design.heights, threshold_mm);
  RestSplit out;
  out.missed.assign(g.cells(), std::numeric_limits<double>::quiet_NaN());
  std::size_t before = 0, after = 0, miss = 0, deep = 0;
  std::vector<std::size_t> left;                 // rest after the program, where the reference cannot reach
  for (std::size_t i = 0; i < g.cells(); ++i) {  // O(cells)
    const bool was = i < r.rest_above_before.size() && r.rest_above_before[i] != 0;
    if ((!was && above[i] == 0) || !in(ref, i)) continue;
    before += was ? 1 : 0;
    if (above[i] == 0) continue;
    ++after;
    left.push_back(i);
  }
  // Whether the rest tool reaches a cell: the test's nodes decide where the nearest and its eight
  // neighbours all say it cannot; elsewhere (a region's edge, and bands narrower than the nodes
  // are apart: beside a concave crease between two facets of a steep wall the tool stays off the
  // design by more than the threshold for ~0.1 mm across it, a few hundredths in XY) the cell's
  // own design point is tested exactly — its distance to the tool's nearest placement
  // (RestRegions::material). Cells in parallel, each on its own: any thread count.
  std::vector<std::uint8_t> reaches(left.size(), 0);
  const auto n_left = static_cast<std::ptrdiff_t>(left.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t k = 0; k < n_left; ++k) {  // O(left cells · the test's search)
    const std::size_t i = left[static_cast<std::size_t>(k)];
    const auto [bi, bj] = node(own, i);
    bool all = true;
    for (long di = -1; di <= 1 && all; ++di)
      for (long dj = -1; dj <= 1 && all; ++dj) all = on(own, bi + di, bj + dj);
    if (all) continue;
    const Eigen::Vector3d p(g.x(i % g.nx), g.y(i / g.nx), design.heights[i] - mesh_z_shift);
    reaches[static_cast<std::size_t>(k)] = own.material(p, Eigen::Vector3d::UnitZ()) <= threshold_mm ? 1 : 0;
  }
  std::vector<std::size_t> within;                 // left where the rest tool reaches, within its stick-out
  for (std::size_t k = 0; k < left.size(); ++k) {  // O(left cells)
    const std::size_t i = left[k];
    if (!reaches[k]) continue;
    if (design.heights[i] < floor_z) {
      ++deep;
      continue;
    }
    within.push_back(i);
  }
  // The z-map's missed cells confirmed by the programs: the nearest approach of their tools to
  // the cell's design point (program frame) beyond the threshold.
  std::vector<simulate::PassTool> programs;
  for (const ChainStep& s : steps) programs.push_back({s.program, s.cutter});
  std::vector<gcode::Point3> points;
  for (const std::size_t i : within) points.push_back({g.x(i % g.nx), g.y(i / g.nx), design.heights[i]});
  const std::vector<double> approach =
      simulate::nearest_approach(programs, points, std::max(0.5, 4 * threshold_mm), simulate::ExactGougeOptions{});
  for (std::size_t k = 0; k < within.size(); ++k) {  // O(missed cells)
    if (!(approach[k] > threshold_mm)) continue;
    out.missed[within[k]] = stock.heights()[within[k]] - design.heights[within[k]];
    ++miss;
  }
  out.missed_zmap_mm2 = static_cast<double>(within.size()) * g.cell * g.cell;
  out.beyond_reach_mm2 = static_cast<double>(deep) * g.cell * g.cell;
  const double cell_area = g.cell * g.cell;
  out.before_mm2 = static_cast<double>(before) * cell_area;
  out.after_mm2 = static_cast<double>(after) * cell_area;
  out.missed_mm2 = static_cast<double>(miss) * cell_area;
  out.unreachable_mm2 = own.rest_axis_area_mm2;
  out.reference_unreachable_mm2 = ref.rest_axis_area_mm2;
  return out;
}

void measure_rest_exactly(finish::RestStock& rest, const simulate::ZMap& stock, const Design& design,
                          const std::vector<ChainStep>& steps, double threshold_mm) {
  const simulate::GridSpec& g = stock.spec();
  if (design.heights.size() != g.cells() || rest.z.size() != g.cells())
    throw Error("job: the rest's exact measure needs the z-map's grid (" + std::to_string(g.cells()) +
                " cells; the design has " + std::to_string(design.heights.size()) + ", the stock " +
                std::to_string(rest.z.size()) + ")");
  const std::vector<std::uint8_t> above = simulate::cells_above(stock, design.heights, threshold_mm);
  std::vector<std::size_t> cells;
  std::vector<gcode::Point3> points;
  for (std::size_t i = 0; i < g.cells(); ++i)  // O(cells)
    if (above[i] != 0) {
      cells.push_back(i);
      points.push_back({g.x(i % g.nx), g.y(i / g.nx), design.heights[i]});
    }
  // Program by program, each binned by its own tool (one call for all bins every move by the
  // widest: the Ø10 roughing's 5 mm made each cell meet every finishing move within 5 mm of it).
  const double reach = 4 * threshold_mm;
  std::vector<double> approach(points.size(), reach);
  for (const ChainStep& s : steps) {  // O(programs · rest cells · moves near each)
    const std::vector<double> mine =
        simulate::nearest_approach({{s.program, s.cutter}}, points, reach, simulate::ExactGougeOptions{});
    for (std::size_t k = 0; k < points.size(); ++k) approach[k] = std::min(approach[k], mine[k]);
  }
  rest.exact_mm.assign(g.cells(), std::numeric_limits<float>::quiet_NaN());
  rest.exact_z.assign(g.cells(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < cells.size(); ++k) {  // O(rest cells)
    if (!(approach[k] < reach)) continue;
    rest.exact_mm[cells[k]] = static_cast<float>(approach[k]);
    rest.exact_z[cells[k]] = design.heights[cells[k]];
  }
}

}  // namespace millnet::job
