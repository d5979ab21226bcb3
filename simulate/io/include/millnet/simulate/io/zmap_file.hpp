#pragma once
// The z-map file: a machined stock saved by `millnet simulate --save-stock` and read back as the
// stock of a later simulation (`--stock FILE.zmap`), so that a roughing and a finishing program
// can be simulated in separate runs.
//
// Format (one owner: this adapter):
//   line 1   "millnet-zmap 1"
//   line 2   one JSON object: {"x0": mm, "y0": mm, "cell": mm, "nx": int, "ny": int,
//            "heights": "float64le"}   (the GridSpec, zmap.hpp)
//   then     exactly nx·ny IEEE-754 doubles, little-endian, row by row (index iy·nx + ix), the
//            heights in the program frame (mm). Nothing follows.
// Move stamps are not saved: a stock read back has no move history (every stamp 0), so material
// that only an earlier run cut counts as uncut, not as scallop, until a program of this run cuts it.
#include "millnet/simulate/zmap.hpp"

#include <filesystem>

namespace millnet::simulate::io {

/// Writes the heights and the grid of `zmap` to `path` atomically. Throws millnet::Error.
void write_zmap(const std::filesystem::path& path, const ZMap& zmap);

/// Reads a z-map file. Checks the header, the grid (GridSpec::check, max_bytes) and the file size
/// BEFORE allocating, and every height (finite). Errors name the file and what was expected.
[[nodiscard]] ZMap read_zmap(const std::filesystem::path& path, std::size_t max_bytes = kZMapMaxBytes);

}  // namespace millnet::simulate::io
