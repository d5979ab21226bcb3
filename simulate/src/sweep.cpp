// The swept-cutter material removal: every move of a program becomes one or more swept primitives
// (a line segment of the tool tip, or a planar arc); each primitive lowers the cells under its XY
// shadow to the lower envelope of the cutter swept along it.
//
// Lower envelope at a cell p of a cutter whose tip moves c(t), t ∈ [0, 1]:
//     h(p) = min_t  c_z(t) + f(|p − c_xy(t)|)
// with f the cutter profile (convex, nondecreasing, +inf beyond R). Closed forms:
//  * ball, line: the swept solid is a capsule (sphere centres on a segment): min of the two end
//    spheres and of the lower surface of the tilted cylinder around the segment (when its contact
//    lies within the segment);
//  * flat, line: the disk covers p on an interval [t0, t1] of t (a quadratic), z is linear in t:
//    the lower end of that interval;
//  * bull, line: h(t) is convex on [t0, t1] (f convex nondecreasing, |p − c_xy(t)| convex), so a
//    golden-section search (64 steps, bracket shrunk by 0.618^64 ≈ 4e-14) plus the interval ends;
//  * any cutter, planar arc (constant Z): h = z + f(d) with d the XY distance from p to the arc,
//    exact (the nearest point of the arc is the radial projection when it lies in the sweep, else
//    an end point);
//  * helical arcs: chords with sagitta ≤ SweepOptions::helix_chord_tol_mm, each swept exactly.
//
// The passes (sweep_internal.hpp lists their files): moves → primitives and link caps; rows of
// each primitive bucketed into chunks of rows; the chunks swept in parallel, each cell seeing its
// primitives in program order; each move's depth of cut.
#include "sweep_internal.hpp"

#include "millnet/core/error.hpp"

#include <omp.h>

namespace millnet::simulate {

namespace sweep {

Profile make_profile(const tooling::Cutter& c) {
  c.check();
  Profile p;
  p.type = c.shape();
  p.R = c.diameter / 2;
  p.R2 = p.R * p.R;
  p.rc = c.profile_corner_radius();
  p.a = p.R - p.rc;
  if (p.type == tooling::CutterType::Drill) p.cone = c.point_height() / p.R;
  return p;
}

namespace {

constexpr std::size_t kChunkRows = 8;  // rows per parallel work unit
/// Primitives crossing a chunk from which its rows' bounds (RowTops) are worth reading its cells
/// for: a chunk of a Ø2 ball's finishing pass has hundreds, a single move's a handful.
constexpr std::size_t kTopsFrom = 64;

/// Per chunk of kChunkRows rows, the primitives whose shadow reaches it, in program order; sets
/// each primitive's rows (iy0, iy1). Primitives entirely off the grid are in no chunk.
std::vector<std::vector<std::uint32_t>> bucket_rows(std::vector<Seg>& segs, const GridSpec& spec) {
  const std::size_t nchunks = (spec.ny + kChunkRows - 1) / kChunkRows;
  std::vector<std::vector<std::uint32_t>> chunk_segs(nchunks);
  if (segs.size() >= std::numeric_limits<std::uint32_t>::max()) throw Error("simulate: too many swept primitives");
  for (std::size_t s = 0; s < segs.size(); ++s) {
    Seg& g = segs[s];
    std::size_t c0 = 0, c1 = 0, r0 = 0, r1 = 0;
    if (!cell_range(g.xlo, g.xhi, spec.x0, spec.cell, spec.nx, c0, c1)) continue;
    if (!cell_range(g.ylo, g.yhi, spec.y0, spec.cell, spec.ny, r0, r1)) continue;
    g.iy0 = r0;
    g.iy1 = r1;
    g.ix0 = c0;
    g.ix1 = c1;
    for (std::size_t c = r0 / kChunkRows; c <= r1 / kChunkRows; ++c)
      chunk_segs[c].push_back(static_cast<std::uint32_t>(s));
  }
  return chunk_segs;
}

/// Sweeps every chunk's primitives over its rows, the chunks in parallel (each cell belongs to one
/// chunk and sees its primitives in program order: bit-identical for any thread count). Sets `res`'s
/// largest height each item removed at one cell and its largest axial engagement (max over the
/// threads: exact), adds the cell evaluations and the rows the row bounds left. A chunk crossed by
/// kTopsFrom primitives or more is swept with its rows' bounds (SweepOptions::row_bounds).
void sweep_chunks(const std::vector<Seg>& segs, const std::vector<std::vector<std::uint32_t>>& chunk_segs,
                  const Profile& P, const GridSpec& spec, double* z, std::uint32_t* stamp, std::size_t nitems,
                  const SweepOptions& opt, SweepResult& res) {
  const int nthreads = opt.threads > 0 ? opt.threads : std::max(1, omp_get_max_threads());
  std::vector<std::vector<double>> thread_cut(static_cast<std::size_t>(nthreads)),
      thread_engage(static_cast<std::size_t>(nthreads));
  std::uint64_t cells = 0, bounded = 0;
  const auto nch = static_cast<std::ptrdiff_t>(chunk_segs.size());
#pragma omp parallel num_threads(nthreads) reduction(+ : cells, bounded)
  {
    auto& cut = thread_cut[static_cast<std::size_t>(omp_get_thread_num())];
    cut.assign(nitems, 0.0);
    auto& eng = thread_engage[static_cast<std::size_t>(omp_get_thread_num())];
    eng.assign(nitems, 0.0);
    RowTops tops;
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t ci = 0; ci < nch; ++ci) {
      const auto c = static_cast<std::size_t>(ci);
      const std::size_t row0 = c * kChunkRows, row1 = std::min(spec.ny, row0 + kChunkRows) - 1;
      // The rows' bounds cost a read of the chunk's cells: only for chunks many primitives cross.
      RowTops* rt = nullptr;
      if (opt.row_bounds && chunk_segs[c].size() >= kTopsFrom) {
        tops.fill(z, spec, row0, row1);
        rt = &tops;
      }
      for (const std::uint32_t si : chunk_segs[c]) {
        const Seg& g = segs[si];
        sweep_rows(g, P, spec, std::max(row0, g.iy0), std::min(row1, g.iy1), z, stamp, cut[g.item], eng[g.item], cells,
                   rt);
      }
    }
    bounded += tops.rows_left;
  }
  res.cells_visited += cells;
  res.rows_bounded += bounded;
  res.item_max_cut_mm.assign(nitems, 0);
  for (const auto& cut : thread_cut)
    for (std::size_t i = 0; i < cut.size(); ++i) res.item_max_cut_mm[i] = std::max(res.item_max_cut_mm[i], cut[i]);
  res.item_max_engage_mm.assign(nitems, 0);
  for (const auto& e : thread_engage)
    for (std::size_t i = 0; i < e.size(); ++i) res.item_max_engage_mm[i] = std::max(res.item_max_engage_mm[i], e[i]);
}

/// The largest cut per move kind and the rapids that cut, from the per-item depths of cut.
void charge_cuts(const gcode::Program& program, const SweepOptions& opt, SweepResult& res) {
  for (std::size_t i = 0; i < program.items.size(); ++i) {
    const auto* mv = std::get_if<gcode::Move>(&program.items[i]);
    if (!mv) continue;
    const std::uint8_t k = kind_of(mv->motion);
    const double c = res.item_max_cut_mm[i];
    if (c > res.max_cut_mm[k]) {
      res.max_cut_mm[k] = c;
      res.max_cut_item[k] = i;
    }
    if (k == kRapidKind && c > opt.cut_eps_mm) res.cutting_rapids.push_back(i);
  }
}

}  // namespace

}  // namespace sweep

double profile_height(const tooling::Cutter& cutter, double r) {
  const sweep::Profile p = sweep::make_profile(cutter);
  if (!(r >= 0)) r = std::abs(r);
  if (r > p.R) return sweep::kInf;
  return p.f(r);
}

class Sweeper {
public:
  static SweepResult run(ZMap& zm, const gcode::Program& program, const tooling::Cutter& cutter,
                         const SweepOptions& opt);

private:
  static ZMap::Pass open_pass(const ZMap& zm, const gcode::Program& program, const SweepOptions& opt);
};

// The checks before anything changes, and the new pass's record (its move stamps and across-feed
// directions).
ZMap::Pass Sweeper::open_pass(const ZMap& zm, const gcode::Program& program, const SweepOptions& opt) {
  if (!(opt.helix_chord_tol_mm > 0)) throw Error("simulate: helix chord tolerance must be > 0 mm");
  const std::size_t nitems = program.items.size();
  if (static_cast<std::uint64_t>(zm.next_serial_) + nitems >= std::numeric_limits<std::uint32_t>::max())
    throw Error("simulate: too many moves on one z-map (move stamps overflow 32 bits)");
  ZMap::Pass pass;
  pass.first_serial = zm.next_serial_;
  pass.items = nitems;
  pass.source_line = program.source_line;
  pass.across.assign(nitems, {0, 0, -1});
  return pass;
}

SweepResult Sweeper::run(ZMap& zm, const gcode::Program& program, const tooling::Cutter& cutter,
                         const SweepOptions& opt) {
  using namespace sweep;
  const Profile P = make_profile(cutter);
  ZMap::Pass pass = open_pass(zm, program, opt);
  SweepResult res;
  res.pass = zm.passes_.size();

  // 1. Moves → primitives; each joint's cutter swept once.
  std::vector<Seg> segs = primitives(program, P, opt, pass.first_serial, pass.across, res);
  link_caps(segs);
  res.segments = segs.size();
  zm.passes_.push_back(std::move(pass));
  zm.next_serial_ += static_cast<std::uint32_t>(program.items.size());

  // 2. Rows of each primitive and the per-chunk lists (in program order).
  const auto chunk_segs = bucket_rows(segs, zm.spec_);

  // 3. Sweep, parallel over row chunks; 4. each move's depth of cut.
  sweep_chunks(segs, chunk_segs, P, zm.spec_, zm.z_.data(), zm.stamp_.data(), program.items.size(), opt, res);
  charge_cuts(program, opt, res);
  return res;
}

SweepResult machine(ZMap& zmap, const gcode::Program& program, const tooling::Cutter& cutter,
                    const SweepOptions& options) {
  return Sweeper::run(zmap, program, cutter, options);
}

}  // namespace millnet::simulate
