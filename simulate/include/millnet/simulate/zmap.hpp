#pragma once
// Z-map virtual machining (ARCHITECTURE.md, simulate/): a regular XY grid of heights that a
// cutter, swept along every move of a gcode::Program, lowers to the lower envelope of the swept
// cutter; then the machined surface is scored against the design surface (deviation, gouge,
// remaining material, scallop, roughness).
//
// Grid: cell (ix, iy), ix in [0, nx) along X (columns), iy in [0, ny) along Y (rows), stored row by
// row (index iy * nx + ix). (x0, y0) is the lower-left CORNER of the grid; each cell is sampled at
// its centre (x0 + (ix + ½)·cell, y0 + (iy + ½)·cell). Heights in mm, same frame as the program
// (Z = tool tip, see gcode/program.hpp).
//
// Cutters: tooling::Cutter (flat, ball, bull, drill; vertical axis, CL = tip), checked by its own
// check(); the simulator evaluates the profile in its kernels by the cutter's shape(): the cutter
// is a solid of revolution, infinitely long above its profile f(r), r ≤ R:
//   flat f = 0;  ball f = R − √(R² − r²);  bull f = 0 for r ≤ R − rc, rc − √(rc² − (r − R + rc)²) beyond;
//   drill f = r / tan(point angle / 2).
#include "millnet/core/budget.hpp"
#include "millnet/tooling/cutter.hpp"
#include "millnet/gcode/program.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace millnet::simulate {

/// The regular grid shared by a z-map and the design surface it is compared with.
struct GridSpec {
  double x0 = 0;  ///< lower-left corner, mm
  double y0 = 0;
  double cell = 0.02;  ///< cell edge, mm (> 0)
  std::size_t nx = 0;  ///< columns (X)
  std::size_t ny = 0;  ///< rows (Y)

  [[nodiscard]] std::size_t cells() const { return nx * ny; }
  [[nodiscard]] double x(std::size_t ix) const { return x0 + (static_cast<double>(ix) + 0.5) * cell; }
  [[nodiscard]] double y(std::size_t iy) const { return y0 + (static_cast<double>(iy) + 0.5) * cell; }
  /// Throws millnet::Error unless the cell is finite and > 0, nx, ny ≥ 1 and the corner finite.
  void check() const;
};

/// Default memory limit of one z-map (heights + move stamps): 2 GiB.
inline constexpr std::size_t kZMapMaxBytes = std::size_t{2} << 30;

/// The cost of a z-map over `spec` (issue 12): its cells, with ZMap::bytes_needed plus
/// `extra_bytes_per_cell` of per-cell data its caller keeps beside it (design heights, metrics).
/// Memory-only (core/budget.hpp): a cell costs a few bytes and constant time. Check it with
/// millnet::check_work before ZMap::flat / from_heights, which keep their own max_bytes backstop.
[[nodiscard]] WorkEstimate zmap_work(const GridSpec& spec, double extra_bytes_per_cell = 0);

/// Where a cell's height comes from: the pass (one machine() call) and the program item.
struct MoveRef {
  std::size_t pass = 0;  ///< 0-based index of the machine() call on this z-map
  std::size_t item = 0;  ///< index into that program's items
  std::size_t line = 0;  ///< 1-based G-code source line when the reader filled it, else 0
};

/// Heights over a GridSpec plus, per cell, a stamp of the move that last lowered it.
class ZMap {
public:
  /// Bytes a z-map of `spec` needs (8 per height + 4 per stamp).
  [[nodiscard]] static std::size_t bytes_needed(const GridSpec& spec);
  /// Flat stock at height `top`. Throws millnet::Error when bytes_needed(spec) > max_bytes.
  [[nodiscard]] static ZMap flat(const GridSpec& spec, double top, std::size_t max_bytes = kZMapMaxBytes);
  /// Stock from a height field (row-major, spec.cells() values) raised by `offset` (an allowance);
  /// NaN heights (no surface) become `nan_fill`. Throws on a size mismatch or above the limit.
  [[nodiscard]] static ZMap from_heights(const GridSpec& spec, const std::vector<double>& heights, double offset = 0,
                                         double nan_fill = 0, std::size_t max_bytes = kZMapMaxBytes);
  /// The same z-map in the memory of `reuse`, a z-map no longer needed (any grid): its pages are
  /// not allocated and faulted in again (a part's strategies are machined one after another on
  /// stocks of one grid).
  [[nodiscard]] static ZMap from_heights(const GridSpec& spec, const std::vector<double>& heights, double offset,
                                         double nan_fill, std::size_t max_bytes, ZMap&& reuse);
  // A previous simulation is simply a ZMap: copy it (or keep machining the same object).

  [[nodiscard]] const GridSpec& spec() const { return spec_; }
  [[nodiscard]] const std::vector<double>& heights() const { return z_; }
  [[nodiscard]] std::vector<double>& heights() { return z_; }
  [[nodiscard]] double at(std::size_t ix, std::size_t iy) const { return z_[iy * spec_.nx + ix]; }
  /// Stamps: 0 = never lowered by a move; otherwise a global move serial (see origin()).
  [[nodiscard]] const std::vector<std::uint32_t>& stamps() const { return stamp_; }
  /// The move that last lowered cell `index`; false when no move did.
  [[nodiscard]] bool origin(std::size_t index, MoveRef& out) const;
  [[nodiscard]] std::size_t passes() const { return passes_.size(); }
  /// Unit across-feed direction of the move that last lowered cell `index` at (x, y); false when
  /// no move did or the move has no XY direction (a plunge).
  [[nodiscard]] bool across_feed(std::size_t index, double x, double y, double& nx, double& ny) const;

private:
  friend class Sweeper;
  struct Pass {
    std::uint32_t first_serial = 1;  ///< stamp of item 0
    std::size_t items = 0;
    std::vector<std::size_t> source_line;  ///< copy of Program::source_line (may be empty)
    /// Per item, the across-feed direction for roughness profiles: lines (nx, ny, 0) unit;
    /// arcs (cx, cy, 1): radial from the centre; other items (0, 0, -1).
    std::vector<std::array<double, 3>> across;
  };
  GridSpec spec_;
  std::vector<double> z_;
  std::vector<std::uint32_t> stamp_;
  std::vector<Pass> passes_;
  std::uint32_t next_serial_ = 1;
};

struct SweepOptions {
  /// Helical arcs (G2/G3 whose Z changes) are split into chords whose sagitta is at most this
  /// (mm). Planar arcs and lines are swept exactly (closed forms, no sampling).
  double helix_chord_tol_mm = 1e-4;
  /// A move "cuts" when it lowers some cell by more than this (mm); used for cutting rapids.
  double cut_eps_mm = 1e-6;
  /// Known tool position before the first move; NaN axes are unknown. A move whose start is not
  /// fully known sweeps only its end point (the tool is placed there); a move whose end is not
  /// fully known sweeps nothing.
  gcode::Point3 start{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::quiet_NaN()};
  int threads = 0;  ///< OpenMP threads; 0 = the OpenMP default
  /// Bound each block of a row's heights while sweeping, so that a ball line leaves at once the
  /// rows it cannot lower (speed only: the heights, stamps and cuts are the same bits without).
  bool row_bounds = true;
};

enum MoveKind : std::uint8_t { kRapidKind = 0, kLineKind = 1, kArcKind = 2 };

struct SweepResult {
  std::size_t pass = 0;         ///< index of this machine() call on the z-map
  std::size_t feed_moves = 0;   ///< G1/G2/G3 items
  std::size_t rapid_moves = 0;  ///< G0 items
  std::size_t segments = 0;     ///< swept primitives (helices count their chords)
  double feed_length_mm = 0;    ///< 3D path length of G1/G2/G3
  double rapid_length_mm = 0;
  /// Rapids that lowered some cell by more than cut_eps_mm (item indices, ascending).
  std::vector<std::size_t> cutting_rapids;
  /// Largest depth of cut (height removed at one cell by one move) per MoveKind, mm.
  std::array<double, 3> max_cut_mm{};
  /// Item of that largest cut per MoveKind (SIZE_MAX when the kind never cut).
  std::array<std::size_t, 3> max_cut_item{SIZE_MAX, SIZE_MAX, SIZE_MAX};
  std::vector<double> item_max_cut_mm;  ///< per program item (0 for non-moves)
  /// Axial engagement per program item, mm: at each cell a move cuts, the height of the stock above
  /// the tip where the cutter first reaches that cell (its disk first covers it: the flutes' side
  /// meets that wall of material at once), never more than the height removed there and never less
  /// than that height up to the cutter's radius (a plunge's cut is the tip's). What a tool's flutes
  /// must take: a move along a wall's skin from its top down removes the skin's whole height at
  /// each cell (item_max_cut_mm) but meets it a little at a time. Line moves with an XY direction
  /// of a ball or flat cutter are refined; other moves report the height removed.
  std::vector<double> item_max_engage_mm;
  std::uint64_t cells_visited = 0;  ///< cell evaluations (for the benchmark's cells × moves)
  /// Rows of ball lines left at once by the row bounds (SweepOptions::row_bounds).
  std::uint64_t rows_bounded = 0;
};

/// Lowers every cell of `zmap` to the lower envelope of `cutter` swept along every move of
/// `program` (feeds AND rapids) and stamps each lowered cell with its move. Only the cells of each
/// move's swept band are visited (per row, the exact X interval of the band's XY shadow). Parallel
/// over rows with OpenMP; bit-identical results for any thread count (each cell sees the moves in
/// program order). Exact for lines (ball, flat: closed forms; bull: golden-section search of the
/// convex height along the move) and planar arcs (all cutters, closed form); helical arcs follow
/// chords within helix_chord_tol_mm. The cutter at the joint of two consecutive moves of the same
/// kind (feed/feed or rapid/rapid) is swept by one of them only, so a cell cut there is charged
/// (stamp, depth of cut) to either. Throws millnet::Error on a bad cutter, on a non-finite
/// coordinate or when the z-map's move stamps would overflow.
SweepResult machine(ZMap& zmap, const gcode::Program& program, const tooling::Cutter& cutter,
                    const SweepOptions& options = {});

/// The cutter profile f(r) used by the sweep (+inf beyond the radius), for tests and callers.
[[nodiscard]] double profile_height(const tooling::Cutter& cutter, double r);

// ---------------------------------------------------------------------------------------------
// Metrics against the design surface.
//
// Roughness: Ra per cell, the arithmetic mean deviation of the PROFILE of e = machined − design
// from its least-squares mean line, over one ISO 4288 sampling length (default 0.8 mm) centred at
// the cell and laid ACROSS the feed direction of the move that last cut the cell. The profile is
// sampled at the cell centres along the grid axis closest to the across-feed direction, over a
// length of sampling_length / cos(angle between that axis and the across-feed direction), so
// that it spans one sampling length measured across the feed (Ra of a periodic scallop profile
// does not change when the profile is stretched along its axis). Cells never cut use a profile
// along Y. Cells whose design height is NaN are not part of the surface; profile samples there
// are skipped, and a cell with fewer than 3 samples has no Ra.

/// The rest-material test's answers (MetricsOptions::reach_every, SurfaceMetrics::rest_area_mm2)
/// kept between the metrics of several programs machined with one cutter on one design: the test
/// asks whether the cutter can touch the design at a cell at all, which depends on the design, the
/// cutter, the grid, the block size and the tolerance only, never on the program. A part's five
/// strategies then test each block once instead of five times (the test was 56 % of
/// `finish --strategy all --simulate` with a Ø6 ball). The answers are the ones the test gives, so
/// the figures are the same bytes with or without a memo.
/// Contract: one memo serves one design (heights and judged surface); the caller that owns the
/// design owns its memo (job::Design). A call with another grid, cutter, block size or tolerance
/// starts it afresh. Not for concurrent surface_metrics calls.
class ReachMemo {
public:
  /// Per block of reach_every × reach_every cells (numbered row by row, ⌈nx / reach_every⌉ per row;
  /// each block is always probed at the same cell): 0 not tested yet, 1 reachable, 2 rest material;
  /// emptied first when any of the keys differ from the last call's.
  std::vector<std::uint8_t>& answers(const GridSpec& grid, const tooling::Cutter& cutter, std::size_t reach_every,
                                     double tolerance_mm);

private:
  GridSpec grid_;
  tooling::Cutter cutter_;
  std::size_t reach_every_ = 0;
  double tolerance_mm_ = 0;
  std::vector<std::uint8_t> answers_;
};

struct MetricsOptions {
  double allowance_mm = 0;          ///< stock the operation should leave on the design
  double tolerance_mm = 0.002;      ///< gouge / remaining-material tolerance
  double sampling_length_mm = 0.8;  ///< ISO 4288 sampling length for Ra
  /// Ra bin edges, µm, ascending; bin k = [edge k, edge k+1) (values below edge 0 count in bin 0),
  /// the last bin is open (≥ the last edge). Median and p90 are nearest-rank percentiles.
  std::vector<double> ra_bins_um{0, 0.4, 0.8, 1.6, 3.2, 6.3, 12.5, 25};
  bool ra_map = true;  ///< compute the per-cell Ra map (and its statistics)
  /// Ra is evaluated at every ra_every-th cell in X and in Y (cells with ix % k = iy % k = k / 2;
  /// the others stay NaN in ra_um and do not count in the statistics). 1 = every cell. The
  /// profiles still use every cell; a stride only thins where they are centred (Ra changes over
  /// a sampling length, 0.8 mm, so a 0.1 mm lattice of centres loses nothing a histogram shows).
  std::size_t ra_every = 1;
  int threads = 0;  ///< OpenMP threads for the Ra map; 0 = the default
  /// The cutter of the last program: with it, the material left above the design is split into
  /// scallop, rest material and uncut (see SurfaceMetrics). Without it, all of it counts as uncut
  /// and scallop_max_mm is max(e − allowance) over the cells some move lowered.
  std::optional<tooling::Cutter> cutter;
  /// The rest-material test runs once per block of reach_every × reach_every cells (≥ 1) that
  /// holds material left, at the block's cell with a design height nearest its centre (the same cell
  /// whatever the program: rest material is the same for every strategy); every cell left in the
  /// block takes that answer. The test samples the design under the cutter at the same stride.
  std::size_t reach_every = 5;
  /// The scallop test's walks across the feed take their cells from a table of offsets per
  /// direction (the same cells, bit for bit); false: each step computes its cell from its
  /// coordinates, as before 2026-12-07 (the oracle the tests hold the tables to).
  bool walk_tables = true;
  /// The rest test's answers shared by the programs scored on one design (null: none kept).
  std::shared_ptr<ReachMemo> reach_memo;
  /// The surface specification (issue 37 §2): a cell is in spec when some move machined it and the
  /// material it keeps over the design, along the normal ((e − allowance)·cos(slope)), is at most
  /// spec_limit_mm (the spec's scallop + form tolerance). NaN: no specification, nothing measured.
  double spec_limit_mm = std::numeric_limits<double>::quiet_NaN();
  /// The Ra target, µm, of ra_target_share (the paper's quality aim read as a share). NaN: none.
  double ra_target_um = std::numeric_limits<double>::quiet_NaN();
  /// The surface an operation is judged on (a machining boundary, issue 38): when not empty (one
  /// per cell), cells with 0 count only for the gouge (a cut into the design anywhere is one);
  /// the surface cells, remaining material, scallop, specification and Ra are those with 1.
  std::vector<std::uint8_t> judged;
};

struct SurfaceMetrics {
  std::size_t surface_cells = 0;  ///< cells with a design height
  double min_e_mm = 0;            ///< min(machined − design)
  double max_e_mm = 0;
  /// Deepest cut below the design measured along the surface normal: max(0, −min e·cos(slope)),
  /// the slope from the design's central differences (on flat ground, −min e).
  double max_gouge_mm = 0;
  bool gouged = false;                ///< max_gouge_mm > tolerance
  std::size_t gouge_cell = SIZE_MAX;  ///< the deepest gouge's cell
  bool gouge_has_move = false;
  MoveRef gouge_move;        ///< the move that cut the deepest gouge
  MoveRef first_gouge_move;  ///< the earliest move (pass, item) that left a gouged cell
  /// The exact check (confirm_gouges in exact_gouge.hpp), when it ran: the gouge figures above are
  /// then the confirmed ones (a z-map gouge the check refutes is an artefact of the cells, never a
  /// gouge), and these keep what the z-map alone said and what became of it.
  bool gouge_checked = false;
  double zmap_max_gouge_mm = 0;          ///< the z-map's own deepest gouge (along the normal)
  std::size_t zmap_gouge_places = 0;     ///< moves that left a z-map gouge cell (one place each)
  std::size_t gouge_places_checked = 0;  ///< of those, checked exactly (the deepest, bounded)
  std::size_t gouge_places_refuted = 0;  ///< checked and found clear: z-map artefacts
  double gouge_x_mm = 0;                 ///< confirmed gouge: the tool tip's XY where it is deepest
  double gouge_y_mm = 0;
  /// Per z-map pass (one program each), the deepest gouge of the cells it last lowered, mm ≥ 0:
  /// the exact check's deepest penetration of its checked places (a refuted artefact reads as its
  /// real penetration, ≤ tolerance), the z-map's along the normal where none was checked. Filled by
  /// confirm_gouges (empty when it did not run).
  std::vector<double> pass_max_gouge_mm;
  /// Remaining material: the area with (e − allowance)·cos(slope) > tolerance (measured along the
  /// surface normal, like the gouge: on an 87° wall a vertical e overstates it 19×). With options.cutter it is split
  /// into three parts, each cell in exactly one:
  ///  - rest: the cutter cannot touch the design there without cutting into it elsewhere by more
  ///    than the tolerance (a concave corner tighter than the cutter): no program with this
  ///    cutter can clear it — the same for every strategy;
  ///  - scallop: the cutter can reach it, and walking across the feed of the move that last cut
  ///    it, the surface is cut to the design (within the tolerance) on both sides within the
  ///    cutter's radius: a cusp between neighbouring passes;
  ///  - uncut: the rest of it — reachable material that the program left.
  /// Without options.cutter, uncut = remaining and the other two are 0.
  double remaining_area_mm2 = 0;
  double uncut_area_mm2 = 0;
  double scallop_area_mm2 = 0;
  double rest_area_mm2 = 0;
  /// With options.cutter: max((e − allowance)·cos(slope)) over the scallop cells (0 when there is
  /// none): the height of the cusps between passes along the normal, not of material the passes
  /// never met. Without it: the same max over the surface cells that some move lowered.
  double scallop_max_mm = 0;
  std::vector<float> ra_um;             ///< per cell, µm; NaN off the surface (empty if !ra_map)
  std::vector<double> ra_bin_edges_um;  ///< copy of the edges
  /// Share per bin (edges.size() bins) of the surface's sampled cells: the cells with an Ra and
  /// the not-machined ones (ra_not_machined_share), which together make 1.
  std::vector<double> ra_share;
  std::size_t ra_cells = 0;  ///< cells with an Ra (machined cells of the ra_every lattice)
  /// Cells of the ra_every lattice on the surface that no move lowered (stamp 0): left at the
  /// stock. They have no Ra — never Ra 0 — and no part in ra_mean/median/p90 (issue 37 §1).
  std::size_t not_machined_cells = 0;
  double ra_not_machined_share = 0;  ///< not_machined_cells / (ra_cells + not_machined_cells)
  double ra_mean_um = 0;
  double ra_median_um = 0;
  double ra_p90_um = 0;
  /// Share of the sampled surface (cells with an Ra and not-machined ones) with Ra ≤ the options'
  /// ra_target_um: not-machined surface counts as outside. NaN without a target.
  double ra_target_share = std::numeric_limits<double>::quiet_NaN();
  /// The surface specification (options' spec_limit_mm), when one was given. The surface it is
  /// judged over is the one the cutter can machine: every surface cell but the rest material (no
  /// program with this cutter can reach it; without options.cutter, every surface cell). Each of
  /// those cells is in spec, over the limit (machined, more material left than the spec allows:
  /// cusps too high, uncut) or not machined (no move lowered it), exactly one of the three.
  bool spec_measured = false;
  std::size_t spec_cells = 0;  ///< the surface judged (cells)
  std::size_t in_spec_cells = 0;
  std::size_t over_spec_cells = 0;
  std::size_t spec_not_machined_cells = 0;
  double spec_share = 0;                  ///< in_spec_cells / spec_cells (0 when there is none)
  double over_spec_max_mm = 0;            ///< the most material left over the design among the over-limit cells
  std::size_t over_spec_cell = SIZE_MAX;  ///< where (the first such cell in row order on a tie)
};

/// The deviation map e = machined − design per cell (NaN where the design is NaN), for heat maps.
/// Throws millnet::Error on a size mismatch.
[[nodiscard]] std::vector<double> deviation(const ZMap& machined, const std::vector<double>& design);

/// The XY area (mm²) of the surface cells (design not NaN) carrying more than `thickness_mm` of
/// material over the design along the normal ((machined − design)·cos(slope), the measure of the
/// metrics below): what a rest program should leave only where its tool cannot reach. Only the
/// cells with `only` ≠ 0 when it is not empty. O(cells). Throws millnet::Error on a size mismatch.
[[nodiscard]] double area_above_mm2(const ZMap& machined, const std::vector<double>& design, double thickness_mm,
                                    const std::vector<std::uint8_t>& only = {});
/// Per cell, 1 where area_above_mm2 counts it (with no `only`), else 0. O(cells).
[[nodiscard]] std::vector<std::uint8_t> cells_above(const ZMap& machined, const std::vector<double>& design,
                                                    double thickness_mm);

/// `design` is the part's top surface at the z-map's cells (row-major, spec.cells() values, NaN
/// where there is no surface). Throws millnet::Error on a size mismatch or bad options.
[[nodiscard]] SurfaceMetrics surface_metrics(const ZMap& machined, const std::vector<double>& design,
                                             const MetricsOptions& options = {});

}  // namespace millnet::simulate
