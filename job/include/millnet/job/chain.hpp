#pragma once
// A part's programs machined one after the other on one stock (roughing, then finishing, then rest
// machining: each meets what the ones before it left), and the surface measured with the last
// tool. What `millnet simulate` and the rough + finish chain of `millnet run` report.
#include "millnet/finish/rest.hpp"
#include "millnet/gcode/program.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/job/finishing.hpp"
#include "millnet/job/operations.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/simulate/zmap.hpp"
#include "millnet/tooling/cutter.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace millnet::job {

/// One program of a chain, as the controller gets it (read from its file, or gcode::written), and
/// the tool that runs it.
struct ChainStep {
  const gcode::Program* program = nullptr;
  tooling::Cutter cutter;
};

/// The operations as chain steps (each its program and its tool's cutter), in order; they point
/// into `ops`.
[[nodiscard]] std::vector<ChainStep> chain_steps(const std::vector<Operation>& ops);

/// One move of a program as the chain machined it (StepResult::moves, when asked): where the air
/// lies, move by move. `kind`: a rapid; a feed move whose cutter never reaches the z-map (not
/// measured); a feed move that lowered some cell by kAirCutMm or more (cut); or one that did not
/// (air: what air_feed_mm sums).
struct MoveRecord {
  enum class Kind : std::uint8_t { Rapid, Outside, Cut, Air };
  std::size_t item = 0;  ///< its index in the program's items
  std::size_t line = 0;  ///< its G-code line (0 when the program was built, not read)
  gcode::Motion motion = gcode::Motion::Rapid;
  gcode::Point3 to{};    ///< its end point (program frame)
  double length_mm = 0;  ///< 3D length (arcs along the arc)
  double cut_mm = 0;     ///< the most it lowered any cell (SweepResult::item_max_cut_mm)
  Kind kind = Kind::Rapid;
};
[[nodiscard]] const char* kind_name(MoveRecord::Kind k);

/// What one program of the chain did.
struct StepResult {
  gcode::ProgramStats stats;  ///< lengths and times (the /machine motion model)
  double max_depth_of_cut_mm =
      0;  ///< deepest cut of any of its moves: the axial engagement (SweepResult::item_max_engage_mm)
  std::size_t cutting_rapids = 0;  ///< its rapids that removed material
  /// Where that deepest cut was: the move's G-code line (0 when the program was built, not read)
  /// and its end point (program frame).
  std::size_t max_cut_line = 0;
  gcode::Point3 max_cut_at{};
  /// After it: the most stock above the design (cells where the design is), mm, and where (XY);
  /// what the next tool meets at worst.
  double max_left_mm = 0;
  std::array<double, 2> max_left_at{};
  /// Feed moves (G1/G2/G3) over the z-map and those of them that removed less than kAirCutMm
  /// anywhere, 3D length: air_cut_share = air_feed_mm / feed_mm (cutting air: what rest machining
  /// must not do). Feed moves whose cutter never reaches the z-map's area (a roughing's passes
  /// round the part in the stock's margin) are outside_feed_mm: not measured, neither cut nor air.
  double feed_mm = 0, air_feed_mm = 0, outside_feed_mm = 0;
  /// The air in runs (consecutive air feed moves between cutting moves, rapids or moves off the
  /// z-map) longer than the cutter's diameter: the air a CAM system trims. A shorter run bridges a
  /// gap in patchy rest along a pass, which no one lifts for (a lift and a re-entry take longer).
  double air_run_feed_mm = 0;
  /// Move by move (rapids and feeds, in program order), when the caller asked for them.
  std::vector<MoveRecord> moves;
  [[nodiscard]] double air_cut_share() const { return feed_mm > 0 ? air_feed_mm / feed_mm : 0.0; }
  [[nodiscard]] double air_run_share() const { return feed_mm > 0 ? air_run_feed_mm / feed_mm : 0.0; }
};

/// A feed move that lowers no cell by more than this removes nothing (mm).
inline constexpr double kAirCutMm = 0.001;

struct ChainResult {
  std::vector<StepResult> steps;     ///< per program, in order
  simulate::SurfaceMetrics metrics;  ///< the surface after the last, scored with its tool
  /// Rest machining (issue 41): when the last tool is smaller than the one before it, the XY area
  /// of the surface carrying more than sim.rest_threshold_mm of material (along the normal:
  /// simulate::area_above_mm2) before and after the last program. The ideal after is what the last
  /// tool cannot reach (finish::unreachable_area_mm2, from the mesh: the caller's yardstick).
  bool rest_step = false;
  tooling::Cutter rest_reference;
  double rest_area_before_mm2 = 0, rest_area_after_mm2 = 0;
  /// The cells over the threshold before the last program (simulate::cells_above), for the
  /// caller's split by what each tool can reach.
  std::vector<std::uint8_t> rest_above_before;
};

/// A block up to Z `top` over the design's grid (the raw stock of a part roughed from a block: Z 0,
/// or a sawn blank's top above it).
[[nodiscard]] simulate::ZMap block_stock(const Design& design, const SimParams& sim, double top = 0.0);

/// The cell of the block's surround (a saved stock's coarse map of the whole block), mm: the
/// roughing's default slicing raster (/rough/raster_mm).
inline constexpr double kSurroundCellMm = 0.25;

/// The block's surround (issue 38): the stock over the whole block — the part's footprint grown by
/// the block's `sides` (x−, x+, y−, y+, gcode::StockBlock::sides) — at kSurroundCellMm, up to Z
/// `top`, on a grid reaching one cell past the block where no stock is (the part's bottom − 1 mm:
/// below every level), so that the raster points on the block's edge see only what is there. What
/// a z-map over the footprint does not hold; saved with it (simulate --save-stock) for a job that
/// starts from it (stock_top_field). O(surround cells).
[[nodiscard]] simulate::ZMap block_surround(const Frame& frame, const std::array<double, 4>& sides, double top,
                                            const SimParams& sim);

/// The chain's programs machined on the surround, in order (simulate::machine with each step's
/// cutter). O(moves · swept surround cells).
void machine_surround(simulate::ZMap& surround, const std::vector<ChainStep>& steps);

/// A stock from the raster of a stock mesh's top on the design's grid (ingest::rasterize_top_cells
/// at the grid's cell centres, part frame): program heights z + frame.z_shift(); a cell the mesh
/// does not cover holds no material (the part's bottom, frame.program_bottom()). O(cells).
[[nodiscard]] simulate::ZMap stock_from_raster(const ingest::HeightField& top, const Design& design, const Frame& frame,
                                               const SimParams& sim);

/// A given stock's top for the roughing to plan from (rough::Params::stock_top): raster points
/// x0 + j·step, y0 + i·step up to x1, y1 (part frame), each the highest of the stock's cells within
/// half a step of it (no material missed between points), part heights. The z-map covers the
/// part's footprint; beyond it a point takes the `surround`'s cells the same way (the block's
/// stock saved with it, simulate/io/zmap_file.hpp), and off both grids keeps the block's top
/// (frame.stock_top). O(cells + surround cells + points).
[[nodiscard]] ingest::HeightField stock_top_field(const simulate::ZMap& stock, const Frame& frame, double x0, double y0,
                                                  double x1, double y1, double step,
                                                  const simulate::ZMap* surround = nullptr);

/// A stock mesh's raster as a stock top: each point the mesh does not cover (hit 0) set to `none`
/// (below every level: no material there). O(points).
void uncovered_to(ingest::HeightField& top, double none);

/// How far a given stock departs from one a job can start from: the most it lies below the design
/// (it does not hold the part there) and the most it rises above Z 0 (the stock top the rapids and
/// clearance planes are set from), each with its cell's centre (XY, part frame). O(cells).
struct StockDeparture {
  double below_design_mm = 0, above_top_mm = 0;
  std::array<double, 2> below_at{}, above_at{};
};
[[nodiscard]] StockDeparture stock_departure(const simulate::ZMap& stock, const Design& design);

/// The most a stock stands above the design, and where (StepResult::max_left_mm, max_left_at; the
/// rest zero): what an operation meets when nothing was machined before it. O(cells).
void left_above(const simulate::ZMap& stock, const Design& design, StepResult& st);
[[nodiscard]] StepResult left_above(const simulate::ZMap& stock, const Design& design);

/// Machines the steps in order on `stock` (left machined), each measured: its lengths and times,
/// its deepest cut and where, its cutting rapids and the stock it leaves above the design.
/// O(steps × (moves + cells swept + cells)).
/// `record_moves`: each step's StepResult::moves too (O(moves) memory).
[[nodiscard]] std::vector<StepResult> machine_steps(simulate::ZMap& stock, const Design& design,
                                                    const std::vector<ChainStep>& steps,
                                                    const gcode::MotionModel& machine, bool record_moves = false);

/// The steps' recorded moves as CSV (simulate --moves): a header, then one row per move in program
/// order — `program` (programs[step], the file's name), `line` (its G-code line; 0 for a built
/// program), `motion` (G0 G1 G2 G3), its end point `x y z` in the program's own work frame (XY
/// less `origin`, the post's work origin in millnet's frame; Z as written), `length_mm`,
/// `cut_mm` and `kind` (rapid, outside, cut, air: MoveRecord). The air rows' lengths of a step sum
/// to its air_feed_mm. O(moves).
[[nodiscard]] std::string moves_csv(const std::vector<StepResult>& steps, const std::vector<std::string>& programs,
                                    const std::array<double, 2>& origin);

/// Machines the steps in order on `stock` (left machined) and scores the surface against the
/// design (allowance 0: the finished part) with the last step's cutter (none: all material left
/// counts as uncut). With `score_rest`, a last step with a smaller tool than the one before, that
/// one not a flat end mill (a roughing tool: roughing then finishing is not rest machining), is
/// scored as rest machining too (ChainResult::rest_*: the area over the rest threshold before and
/// after it, O(cells) each). O(steps × (moves + cells swept) + cells).
[[nodiscard]] ChainResult machine_chain(simulate::ZMap& stock, const Design& design,
                                        const std::vector<ChainStep>& steps, const gcode::MotionModel& machine,
                                        const SimParams& sim, bool score_rest = false, bool record_moves = false);

/// A rest step's material over the threshold split by what each tool can reach (issue 41), both
/// found exactly from the mesh (finish::unreachable_regions: a point-like probe's rest behind the
/// tool; for the reference a z-map cell takes the answer of the test's nearest node). The rest is the material over
/// the threshold where the reference (r.rest_reference) cannot reach: before (r.rest_above_before)
/// and after the rest program (`stock`); what the rest tool cannot reach either (the ideal after);
/// rest left where the rest tool reaches (missed), with its vertical excess per cell (NaN elsewhere).
/// `mesh` in the part frame, whose XY is the z-map's (program Z = part z + `mesh_z_shift`). Rest on
/// design below `floor_z` (the z-map's frame: the stock top less the rest tool's stick-out) is
/// beyond its reach, counted apart from the missed (beyond_reach_mm2). Whether the rest tool
/// reaches a cell of rest left after it: its nearest node's answer where that node's eight
/// neighbours agree it cannot, else the exact test at the cell's own design point (bands narrower
/// than the nodes are apart: beside the creases of a steep faceted wall). O(cells) + the two tests
/// + the exact test at those cells.
/// A missed cell is confirmed by the programs themselves (`steps`, the programs that cut `stock`):
/// missed only where none of them brought its tool within the threshold of the cell's design point
/// (simulate::nearest_approach, the same 3D distance the reach test asks of the rest tool's best
/// placement). On a steep wall a z-map cell's vertical excess times the cosine of the grid's slope
/// overstates the material a tool left within hundredths of a millimetre of the point (s4: 2.7 of
/// 4.3 mm² of the z-map's missed rest lay within the threshold of the rest program's tool).
/// missed_zmap_mm2: the z-map's figure before that check. O(missed cells · moves near each).
struct RestSplit {
  double before_mm2 = 0, after_mm2 = 0, unreachable_mm2 = 0, reference_unreachable_mm2 = 0, missed_mm2 = 0;
  double beyond_reach_mm2 = 0, missed_zmap_mm2 = 0;
  std::vector<double> missed;
};
[[nodiscard]] RestSplit split_rest(const ingest::Mesh& mesh, const Design& design, const simulate::ZMap& stock,
                                   const ChainResult& r, const std::vector<ChainStep>& steps,
                                   const tooling::Cutter& tool, double threshold_mm, double floor_z,
                                   double mesh_z_shift);

/// The rest a rest program is planned against, measured as split_rest judges it (issue 41): for
/// each cell of `stock` whose material over `design` exceeds `threshold_mm` (simulate::cells_above),
/// the nearest approach of `steps` (the programs that cut `stock`) to the cell's design point goes
/// into rest.exact_mm and that point's height (the z-map's frame) into rest.exact_z; NaN elsewhere,
/// and where no tool came within four thresholds (the z-map's reading stands there). `rest`: the
/// same stock as finish::RestStock (its grid the z-map's). Program by program, each binned by its
/// own tool; points in parallel (any thread count). O(programs · rest cells · moves near each).
void measure_rest_exactly(finish::RestStock& rest, const simulate::ZMap& stock, const Design& design,
                          const std::vector<ChainStep>& steps, double threshold_mm);

}  // namespace millnet::job
