#pragma once
// The z-map file: a machined stock saved by `millnet simulate --save-stock` and read back as the
// stock of a later simulation (`--stock FILE.zmap`), so that a roughing and a finishing program
// can be simulated in separate runs.
//
// Format (one owner: this adapter):
//   line 1   "millnet-zmap 1" ("millnet-zmap 2" with a surround)
//   line 2   one JSON object: {"x0": mm, "y0": mm, "cell": mm, "nx": int, "ny": int,
//            "heights": "float64le"}   (the GridSpec, zmap.hpp); version 2 adds
//            "surround": {"x0", "y0", "cell", "nx", "ny"}, the surround's grid
//   then     exactly nx·ny IEEE-754 doubles, little-endian, row by row (index iy·nx + ix), the
//            heights in the program frame (mm); version 2: then the surround's heights the same way.
//            Nothing follows.
// The surround (issue 38): the stock over the whole block — the part's footprint and the margins
// around it, which the z-map (over the footprint) does not hold — at a coarse cell, machined by the
// same programs; a job that starts from the saved stock plans its roughing from it beyond the
// footprint instead of assuming the block there.
// Move stamps are not saved: a stock read back has no move history (every stamp 0), so material
// that only an earlier run cut counts as uncut, not as scallop, until a program of this run cuts it.
#include "millnet/simulate/zmap.hpp"

#include <filesystem>
#include <optional>

namespace millnet::simulate::io {

/// Writes the heights and the grid of `zmap` (and `surround`'s when given: version 2) to `path`
/// atomically. Throws millnet::Error.
void write_zmap(const std::filesystem::path& path, const ZMap& zmap, const ZMap* surround = nullptr);

/// A saved stock: the z-map and, when the file has one, the block's surround.
struct SavedStock {
  ZMap zmap;
  std::optional<ZMap> surround;
};

/// Reads a z-map file (version 1 or 2). Checks the header, the grids (GridSpec::check, max_bytes
/// each) and the file size BEFORE allocating, and every height (finite). Errors name the file and
/// what was expected.
[[nodiscard]] SavedStock read_saved_stock(const std::filesystem::path& path, std::size_t max_bytes = kZMapMaxBytes);

/// read_saved_stock's z-map alone.
[[nodiscard]] ZMap read_zmap(const std::filesystem::path& path, std::size_t max_bytes = kZMapMaxBytes);

}  // namespace millnet::simulate::io
