// The stock a job starts from (job_stock.hpp).
#include "job_stock.hpp"

#include "finish_job.hpp"
#include "text.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/job/chain.hpp"

#include <array>
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
simulate::ZMap stock_from_mesh(const std::string& file, const StockSource& src, const job::Design& design,
                               const job::SimParams& sim) {
  ingest::PrepareOptions raw = src.prep;
  raw.recentre = false;
  const Eigen::Vector3d shift = ingest::bounds(ingest::load_prepared(src.part_file, raw)).min;
  ingest::Mesh stock = ingest::load_prepared(file, raw);
  stock.V.rowwise() -= shift.transpose();
  const simulate::GridSpec& g = design.grid;
  return job::stock_from_raster(
      ingest::rasterize_top_cells(stock, g.x(0), g.y(0), g.cell, static_cast<int>(g.nx), static_cast<int>(g.ny)),
      design, src.frame, sim);
}

}  // namespace

/// The stock the job starts from: the block (footprint + margin up to Z 0), a z-map saved by
/// `simulate --save-stock` on this part's grid (issue 38: a stock as a model; a job's real
/// history), or a stock mesh (a casting, a plate sawn to size). A stock that does not hold the
/// design (below it by more than the tolerance) or rises above Z 0 (the stock top every rapid and
/// clearance plane is set from) is refused, naming the place (job::stock_departure).
simulate::ZMap starting_stock(const std::optional<std::string>& file, const StockSource& src, const job::Design& design,
                              const job::SimParams& sim) {
  if (!file) return job::block_stock(design, sim);
  simulate::ZMap z = fs::path(*file).extension() == ".zmap" ? stock_from_file(*file, design.grid)
                                                            : stock_from_mesh(*file, src, design, sim);
  const job::StockDeparture d = job::stock_departure(z, design);
  const auto where = [](const std::array<double, 2>& at) {
    return "X" + fixed(at[0], 2) + " Y" + fixed(at[1], 2) + " (part frame)";
  };
  if (d.below_design_mm > kStockToleranceMm)
    throw file_error(*file, "the stock lies " + fixed(d.below_design_mm, 3) + " mm below the design at " +
                                where(d.below_at) + ": not a stock this part can be machined from");
  if (d.above_top_mm > kStockToleranceMm)
    throw file_error(*file, "the stock rises " + fixed(d.above_top_mm, 3) +
                                " mm above Z 0, the stock top the job's rapids and clearance planes are set from, at " +
                                where(d.above_at) + ": raise /rough/top_allowance_mm by that much");
  return z;
}

}  // namespace millnet::app
