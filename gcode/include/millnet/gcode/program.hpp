#pragma once
// The program model every millnet G-code goes through (ARCHITECTURE.md, gcode/): planners and
// finishing strategies build a Program; the writer turns it into text for a dialect; the reader
// turns text back into a Program; the motion model times it. Nothing here knows about pockets,
// meshes or cutters.
//
// Frame and units: mm, mm/min, rpm; absolute coordinates; XY plane (G17); Z is the tool tip.
// Arcs lie in the XY plane (helical when Z changes) with an absolute centre.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace millnet::gcode {

using Point3 = std::array<double, 3>;

enum class Motion : std::uint8_t { Rapid, Line, ArcCW, ArcCCW };  ///< G0, G1, G2, G3

/// Which axes a block's position is known on (bit 0 = X, 1 = Y, 2 = Z): stated by it or by an
/// earlier block. A program's first rapid usually states only Z (the XY position before it is
/// unknown); the writer never writes an axis outside the mask.
enum AxisMask : std::uint8_t { kX = 1, kY = 2, kZ = 4, kXYZ = 7 };

struct Move {
  Motion motion = Motion::Rapid;
  Point3 to{};                     ///< absolute end point, mm (unstated axes: the previous value)
  std::array<double, 2> center{};  ///< arcs: absolute XY centre, mm
  double feed = 0;                 ///< mm/min for Line and arcs; 0 for Rapid
  std::uint8_t axes = kXYZ;        ///< AxisMask of the axes the block states
  std::uint8_t op = 0;             ///< operation index (0 = main; e.g. 1 = the pocket's pre-drilling)
  /// 81 / 83: one of the moves a drilling cycle (G81, G83) stands for (gcode/cycles.hpp): the
  /// writer writes such a hole as one cycle block on a dialect with canned cycles; 0: a plain move.
  std::uint8_t cycle = 0;
};

enum class SpindleDir : std::uint8_t { Off, CW, CCW };  ///< M5, M3, M4
struct Spindle {
  SpindleDir dir = SpindleDir::CW;
  double rpm = 0;  ///< S word (ignored for Off)
};
struct ToolChange {  ///< T<n> M6
  int number = 1;
  std::string description;  ///< written as a comment beside it
  int length_offset = 0;    ///< the H register of the dialect's G43 after it; 0 = the tool's number
};
struct Pause {  ///< M0 (M1 when optional)
  bool optional = false;
};
struct Comment {  ///< "(text)" on its own line; parentheses are replaced by [ ]
  std::string text;
};

using Item = std::variant<Move, Spindle, ToolChange, Pause, Comment>;

/// A program: header comments, then the preamble (G21 G90 G17 G94), then the items, then M30.
struct Program {
  std::vector<std::string> header;  ///< comment lines written before the preamble
  std::vector<Item> items;
  /// Reader only: the 1-based source line of each item (same size as items); empty when built.
  std::vector<std::size_t> source_line;
};

}  // namespace millnet::gcode
