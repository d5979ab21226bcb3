#pragma once
// The frame every program of a part shares (ARCHITECTURE.md, Formats: X/Y origin at the lower-left
// corner of the footprint, Z 0 at the stock top, Z the tool tip), and the holder check. This is the
// one place that says where Z 0 is: roughing, finishing, the simulation chain and the previews take
// it from here.
//
// Part frame: a prepared mesh (ingest::load_prepared: mm, up +Z, footprint lower-left at x = y = 0,
// lowest point z = 0). The stock top lies top_allowance above the part's highest point; a program's
// Z is part z − stock_top.
//
//   const job::Frame f = job::frame_of(mesh, 1.0);       // Z 0 = part top + 1 mm
//   params.z_shift = f.z_shift();                         // finishing: CL z → program Z
//   job::check_reach(tool, label, f.depth_below_top(z_lowest), "the part");
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/tooling/cutter.hpp"

#include <string>
#include <string_view>

namespace millnet::job {

struct Frame {
  double part_top = 0;       ///< highest point of the part, part frame, mm
  double part_bottom = 0;    ///< lowest point (0 for a prepared mesh)
  double top_allowance = 0;  ///< stock above the part's highest point, mm (/rough/top_allowance_mm)
  double stock_top = 0;      ///< part_top + top_allowance: Z 0 of every program, part frame
  double width = 0;          ///< footprint: x in [0, width] (the mesh's largest x)
  double depth = 0;          ///< footprint: y in [0, depth]

  /// Program Z = part z + z_shift().
  [[nodiscard]] double z_shift() const { return -stock_top; }
  /// How far below the stock top a point at part height `z` lies, mm.
  [[nodiscard]] double depth_below_top(double z) const { return stock_top - z; }
  /// The part's lowest point in the program frame (the stock's floor in the previews).
  [[nodiscard]] double program_bottom() const { return part_bottom - stock_top; }
  /// "frame: Z 0 = stock top = part top + 1.000 mm" (the programs' header comment).
  [[nodiscard]] std::string header() const;
  /// The dialect with the work origin placed on this part's stock (gcode::placed over the footprint).
  [[nodiscard]] gcode::Dialect post(const gcode::Dialect& dialect) const {
    return gcode::placed(dialect, 0, 0, width, depth);
  }
};

/// The frame of a prepared mesh with `top_allowance_mm` of stock above it. Throws millnet::Error
/// for an empty mesh or an allowance that is not finite and ≥ 0.
[[nodiscard]] Frame frame_of(const ingest::Mesh& mesh, double top_allowance_mm);

/// The holder check: a tool whose stick-out (Cutter::reach_mm) is stated must reach `depth_mm`
/// below the stock top, or its holder would hit the stock. `what` names what reaches that deep ("the
/// part", "the pocket"). Throws millnet::Error "<label>: <what> reaches D mm below the stock top,
/// beyond the tool's stick-out S mm by E mm: the holder would hit the stock". No check when the
/// reach is 0 (not stated).
void check_reach(const tooling::Cutter& cutter, std::string_view label, double depth_mm, std::string_view what);

}  // namespace millnet::job
