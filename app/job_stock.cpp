// The stock a job starts from (job_stock.hpp).
#include "job_stock.hpp"

#include "finish_job.hpp"
#include "text.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/job/chain.hpp"
#include "millnet/job/operations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

namespace millnet::app {

namespace {

/// A given stock may lie this far below the design or above Z 0 (a z-map saved after a finishing
/// carries its cusps and the simulation's rounding), mm.
constexpr double kStockToleranceMm = 0.01;

/// A stock mesh (any mesh or CAD file millnet reads) in the part file's own coordinates: read with
/// the part's units and up axis and moved as the part is (its footprint's corner and lowest point
/// to 0), its top rasterized on the part's grid, each cell the highest of the mesh over it (a
/// conservative stock: no material missed between raster points; job::stock_from_raster).
ingest::Mesh stock_mesh(const std::string& file, const StockSource& src) {
  ingest::PrepareOptions raw = src.prep;
  raw.recentre = false;
  const Eigen::Vector3d shift = ingest::bounds(ingest::load_prepared(src.part_file, raw)).min;
  ingest::Mesh stock = ingest::load_prepared(file, raw);
  stock.V.rowwise() -= shift.transpose();
  return stock;
}

simulate::ZMap stock_from_mesh(const ingest::Mesh& stock, const StockSource& src, const job::Design& design,
                               const job::SimParams& sim) {
  const simulate::GridSpec& g = design.grid;
  return job::stock_from_raster(
      ingest::rasterize_top_cells(stock, g.x(0), g.y(0), g.cell, static_cast<int>(g.nx), static_cast<int>(g.ny)),
      design, src.frame, sim);
}

}  // namespace

std::optional<GivenStock> read_stock(const std::optional<std::string>& file, const StockSource& src) {
  if (!file) return std::nullopt;
  GivenStock g{*file, std::nullopt};
  if (fs::path(*file).extension() != ".zmap") g.mesh = stock_mesh(*file, src);
  return g;
}

namespace {

/// A given stock that does not hold the design (below it by more than the tolerance) or rises above
/// Z 0 is refused, naming the file and the place (job::stock_departure).
void check_departure(const simulate::ZMap& z, const std::string& file, const job::Design& design) {
  const job::StockDeparture d = job::stock_departure(z, design);
  const auto where = [](const std::array<double, 2>& at) {
    return "X" + fixed(at[0], 2) + " Y" + fixed(at[1], 2) + " (part frame)";
  };
  if (d.below_design_mm > kStockToleranceMm)
    throw file_error(file, "the stock lies " + fixed(d.below_design_mm, 3) + " mm below the design at " +
                               where(d.below_at) + ": not a stock this part can be machined from");
  if (d.above_top_mm > kStockToleranceMm)
    throw file_error(file, "the stock rises " + fixed(d.above_top_mm, 3) +
                               " mm above Z 0, the stock top the job's rapids and clearance planes are set from, at " +
                               where(d.above_at) + ": raise /rough/top_allowance_mm by that much");
}

}  // namespace

simulate::ZMap starting_stock(const GivenStock* given, const StockSource& src, const job::Design& design,
                              const job::SimParams& sim, double blank_top) {
  if (given == nullptr) return job::block_stock(design, sim, blank_top);
  simulate::ZMap z =
      given->mesh ? stock_from_mesh(*given->mesh, src, design, sim) : stock_from_file(given->file, design.grid);
  check_departure(z, given->file, design);
  return z;
}

std::shared_ptr<const ingest::HeightField> roughing_stock(const GivenStock* given, const StockSource& src,
                                                          const ingest::Mesh& part, const rough::Params& rp,
                                                          const job::SimParams& sim) {
  if (given == nullptr) return nullptr;
  const job::Design design = job::design_surface(part, src.frame, sim);
  // The roughing's slicing raster (rough_mesh: the footprint + the block's margins, raster_mm apart).
  const ingest::Box3 box = ingest::bounds(part);
  const std::array<double, 4> m = rp.stock.sides(box.max.x() - box.min.x(), box.max.y() - box.min.y());
  const double x0 = box.min.x() - m[0], y0 = box.min.y() - m[2], x1 = box.max.x() + m[1], y1 = box.max.y() + m[3];
  if (!given->mesh) {  // a z-map covers the part's footprint; beyond it its surround, or the block
    const simulate::io::SavedStock saved = saved_stock_from_file(given->file, design.grid);
    check_departure(saved.zmap, given->file, design);
    return std::make_shared<const ingest::HeightField>(job::stock_top_field(
        saved.zmap, src.frame, x0, y0, x1, y1, rp.raster_mm, saved.surround ? &*saved.surround : nullptr));
  }
  check_departure(stock_from_mesh(*given->mesh, src, design, sim), given->file, design);
  // A stock mesh everywhere: its top over each raster point's cell, none where it is not.
  const int nx = static_cast<int>(std::ceil((x1 - x0) / rp.raster_mm)) + 1;
  const int ny = static_cast<int>(std::ceil((y1 - y0) / rp.raster_mm)) + 1;
  ingest::HeightField top = ingest::rasterize_top_cells(*given->mesh, x0, y0, rp.raster_mm, nx, ny);
  const double none = box.min.z() - rp.cut.stock_to_leave - 1.0;  // below every level
  job::uncovered_to(top, none);
  return std::make_shared<const ingest::HeightField>(std::move(top));
}

namespace {

/// A facing pass's radial engagement, in tool diameters (a face milled with an end mill: 3/4 of it).
constexpr double kFacingStepover = 0.75;

/// How deep one facing level goes: the roughing's step-down, within the end mill's flutes.
double facing_level_mm(const rough::Params& rp, const tooling::Tool& mill) {
  return mill.flute_length_mm > 0 ? std::min(rp.cut.step_down, mill.flute_length_mm) : rp.cut.step_down;
}

}  // namespace

/// The sawn blank's top above Z 0 (/rough/stock_squared false: /rough/facing_mm), 0 for a pre-squared
/// block. Refused with a given stock (machined as it is) or at or above the rapids' height.
double sawn_blank_top(const Json& config, const rough::Params& rp, const std::optional<std::string>& stock) {
  if (config["rough"]["stock_squared"].get<bool>()) return 0;
  const double top = config["rough"]["facing_mm"].get<double>();
  if (stock)
    throw Error(*stock +
                ": --stock is the stock the job starts from, machined as it is; /rough/stock_squared false "
                "asks for the block with a sawn top: give one of them");
  if (!(top < rp.cut.safe_z - job::kFacingFeedHeightMm))
    throw Error("/rough/facing_mm " + format_double(top) + " leaves the sawn blank's top within " +
                format_double(job::kFacingFeedHeightMm) + " mm of the safe height /pocket/safe_z " +
                format_double(rp.cut.safe_z) + ": the rapids would run into it; raise /pocket/safe_z");
  return top;
}

/// The facing of a sawn blank over the roughing's stock rectangle, with the roughing's end mill and
/// cutting data (job::facing_operation).
job::FacingSpec facing_spec(const rough::Result& rough, const rough::Params& rp, const tooling::Tool& mill,
                            double blank_top) {
  job::FacingSpec f;
  f.x0 = rough.stock_x0, f.y0 = rough.stock_y0, f.x1 = rough.stock_x1, f.y1 = rough.stock_y1;
  f.blank_top = blank_top;
  f.max_depth_mm = facing_level_mm(rp, mill);
  f.stepover_mm = kFacingStepover * mill.diameter_mm;
  f.safe_z = rp.cut.safe_z;
  f.rpm = rp.cut.spindle_rpm, f.feed_mm_min = rp.cut.feed_half, f.plunge_feed_mm_min = rp.cut.feed_plunge;
  return f;
}

}  // namespace millnet::app
