#pragma once
// Pocket files (adapter millnet::pocket_io): pocket JSON (ARCHITECTURE.md) and ASCII DXF (R12 and
// 2000+). The region comes back validated and normalized (boundary CCW, islands CW).
//   JSON: {"units":"mm","boundary":[[x,y,bulge],…],"islands":[[[x,y,bulge],…],…], optional numbers
//          "tool_diameter","stepover","depth","safe_z","step_down","stock_to_leave","feed_slot",
//          "feed_half","feed_plunge","spindle_rpm"} and free text "note", "name", "comment", "format";
//          [x, y] without bulge means a line; any other key is an error naming it (the numbers'
//          ranges are the config's /pocket/… ones, checked by the app).
//   DXF:  ENTITIES LWPOLYLINE (bulges, closed flag 70&1), POLYLINE/VERTEX/SEQEND, LINE, ARC, CIRCLE;
//          loose and open pieces are chained into closed loops when their ends lie within
//          tol::chain_join_mm; the loop enclosing the others is the boundary, loops inside it
//          islands. Loops inside islands and several separate outlines are errors (for now).
#include "millnet/pocket/geometry.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::pocket {

struct PocketFile {
  Region region;
  std::vector<std::string> notes;  ///< what normalization / chaining changed
  std::optional<double> tool_diameter, stepover, depth, safe_z, step_down, stock_to_leave;
  std::optional<double> feed_slot, feed_half, feed_plunge, spindle_rpm;
};

/// Reads a .json or .dxf pocket (by extension, case-insensitive). Throws millnet::Error naming the
/// file and the key / line / entity at fault.
[[nodiscard]] PocketFile read_pocket(const std::filesystem::path& path);
[[nodiscard]] PocketFile parse_pocket_json(const std::string& text, const std::string& source);
[[nodiscard]] PocketFile parse_pocket_dxf(const std::string& text, const std::string& source);

/// Writes a region as pocket JSON (atomically), bulges included.
void write_pocket_json(const std::filesystem::path& path, const Region& region);

}  // namespace millnet::pocket
