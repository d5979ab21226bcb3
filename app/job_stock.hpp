#pragma once
// The stock a job starts from (issue 38: a stock as a model the job reads): the block, a saved
// z-map or a stock mesh, checked to be one the part can be machined from.
#include "json_settings.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/job/finishing.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/job/operations.hpp"
#include "millnet/rough/rough.hpp"
#include "millnet/simulate/zmap.hpp"

#include <memory>
#include <optional>
#include <string>

namespace millnet::app {

/// Where a stock mesh is put: the part file it belongs to, read as the part was, and its frame.
struct StockSource {
  std::string part_file;
  ingest::PrepareOptions prep;
  job::Frame frame;
};

/// A stock given by --stock FILE, read once: a stock mesh in the part frame (read with the part's
/// units and up axis and moved as the part is), or a z-map saved by `simulate --save-stock`, read
/// where it is used (8 B a cell: not kept beside the finishing's memory budget).
struct GivenStock {
  std::string file;
  std::optional<ingest::Mesh> mesh;  ///< a stock mesh; empty for FILE.zmap
};
[[nodiscard]] std::optional<GivenStock> read_stock(const std::optional<std::string>& file, const StockSource& src);

/// The stock the job starts from: the block (footprint + margin up to Z `blank_top`: 0, or a sawn
/// blank's top that a facing operation takes down to 0), a z-map saved by `simulate --save-stock`
/// on this part's grid (issue 38: a stock as a model; a job's real history), or a stock mesh (a
/// casting, a plate sawn to size). A stock that does not hold the design (below it by more than the
/// tolerance) or rises above Z 0 (the stock top every rapid and clearance plane is set from) is
/// refused, naming the place (job::stock_departure).
[[nodiscard]] simulate::ZMap starting_stock(const GivenStock* given, const StockSource& src, const job::Design& design,
                                            const job::SimParams& sim, double blank_top = 0.0);

/// A given stock, checked before anything is planned (starting_stock on the part's design surface:
/// a bad stock is refused before the minutes of roughing, finishing and simulation it would feed),
/// as the top the roughing plans from (rough::Params::stock_top: its levels clear only where the
/// stock still holds material), over the roughing's stock rectangle at its raster. Null for the block.
[[nodiscard]] std::shared_ptr<const ingest::HeightField> roughing_stock(const GivenStock* given, const StockSource& src,
                                                                        const ingest::Mesh& part,
                                                                        const rough::Params& rp,
                                                                        const job::SimParams& sim);

/// A sawn blank (/rough/stock_squared false): its top above Z 0 (/rough/facing_mm), 0 for a
/// pre-squared block. Refused with a given stock (machined as it is) or within the feed height of
/// the rapids' safe height (/pocket/safe_z).
[[nodiscard]] double sawn_blank_top(const Json& config, const rough::Params& rp,
                                    const std::optional<std::string>& stock);

/// The facing of a sawn blank whose top is `blank_top` over the roughing's stock rectangle, with the
/// roughing's end mill and cutting data: passes 3/4 D apart, levels of the step-down within the
/// flutes (job::facing_operation).
[[nodiscard]] job::FacingSpec facing_spec(const rough::Result& rough, const rough::Params& rp,
                                          const tooling::Tool& mill, double blank_top);

}  // namespace millnet::app
