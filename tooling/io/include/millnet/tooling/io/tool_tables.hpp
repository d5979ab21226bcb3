#pragma once
// Tool tables of the systems shops already use, read into tooling::Tool and written back (issue 40):
//
//   LinuxCNC tool.tbl    lines "T1 P1 D6 Z+0 ;comment": words T P (integers), X Y Z A B C U V W D I J
//                        (reals), Q (integer), each a letter and its number, separated by blanks;
//                        ';' starts the comment; a line starting with ';' is ignored (LinuxCNC docs
//                        gcode/tool-compensation "Tool Table Format", src/emc/tooldata/tooldata_common.cc).
//                        Machine units, no tool type: the type, corner radius, flutes and tool material
//                        are taken from the comment when it names them ("ball", "bull r1", "drill",
//                        "3F", "hss"), else flat, 2 flutes, carbide (each assumption in the notes).
//   FreeCAD ToolBit      .fctb JSON {"version": 2, "name", "shape": "endmill.fcstd" | "ballend" |
//                        "bullnose" | "torus" | "drill" …, "parameter": {"Diameter": "6.00 mm", …},
//                        "attribute": {"Material": "Carbide", …}} and the library .fctl
//                        {"tools": [{"nr": 1, "path": "6mm_Endmill.fctb"}, …]} whose nr is the tool number
//                        (FreeCAD src/Mod/CAM/Tools/Bit, Tools/Library, Path/Tool/toolbit).
//   Fusion 360 library   JSON {"data": [{"type": "flat end mill" | "ball end mill" | "bull nose end mill" |
//                        "drill" | …, "unit": "millimeters" | "inches", "geometry": {"DC", "RE", "NOF",
//                        "LCF", "LB", "SIG", …}, "post-process": {"number", "length-offset"}, "holder":
//                        {"segments": [{"height", "lower-diameter", "upper-diameter"}]}, "BMC", …}]}.
//
// Every reader returns the tools (checked with Tool::check, ids made from the file's names, unique)
// and notes saying what it assumed; bad input throws millnet::Error in one line naming the file and
// the line (LinuxCNC) or the JSON pointer and key (FreeCAD, Fusion). Lengths are mm in the result.
// JSON parsing stays inside this adapter.
#include "millnet/tooling/cutting.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::tooling::io {

/// Largest tool-table file read, bytes (a shop's table of 10,000 tools is well under 4 MB).
inline constexpr std::size_t kMaxToolFileBytes = std::size_t{8} << 20;
/// Most tools one import holds.
inline constexpr std::size_t kMaxImportedTools = 10000;
/// Longest line LinuxCNC reads from a tool table (CANON_TOOL_ENTRY_LEN 256, with its newline).
inline constexpr std::size_t kLinuxCncMaxLine = 255;
/// Longest comment LinuxCNC keeps (CANON_TOOL_COMMENT_SIZE 40, with its terminating zero).
inline constexpr std::size_t kLinuxCncMaxComment = 39;
/// Highest pocket number of a LinuxCNC tool changer (CANON_POCKETS_MAX 1001; P0 is the spindle).
inline constexpr int kLinuxCncMaxPocket = 1000;

/// What an import read: the tools in the file's order, and one line per assumption made.
struct ToolImport {
  std::vector<Tool> tools;
  std::vector<std::string> notes;
};

enum class ToolFormat { LinuxCnc, FreeCad, Fusion };
enum class LengthUnit { Mm, Inch };

/// "linuxcnc" | "freecad" | "fusion"; throws millnet::Error naming the accepted values.
[[nodiscard]] ToolFormat parse_tool_format(const std::string& s);

/// A LinuxCNC tool table (`source` names it in errors and notes). The table is in machine units:
/// `units` says which (mm unless the machine is set up in inches).
[[nodiscard]] ToolImport read_linuxcnc_tool_table(std::string_view text, const std::string& source,
                                                  LengthUnit units = LengthUnit::Mm);

/// One FreeCAD ToolBit (.fctb). Its tool has no number (a bit's number is its library's).
/// A shape millnet does not model (v-bit, chamfer, probe, …) is an error here.
[[nodiscard]] ToolImport read_freecad_toolbit(std::string_view text, const std::string& source);

/// A bit file a FreeCAD library names: its text and the name errors give it.
struct BitFile {
  std::string text, source;
};
/// Reads the bit a library entry's "path" names (throws millnet::Error when it cannot).
using BitLoader = std::function<BitFile(const std::string& path)>;
/// A FreeCAD tool library (.fctl): each entry's bit read through `load`, numbered by its "nr";
/// bits of shapes millnet does not model are left out (in the notes).
[[nodiscard]] ToolImport read_freecad_library(std::string_view text, const std::string& source, const BitLoader& load);

/// A Fusion 360 tool library export. Entries that are not flat, ball, bull-nose end mills or drills
/// (holders, chamfer mills, probes, …) are left out (in the notes); inches are converted to mm.
[[nodiscard]] ToolImport read_fusion_library(std::string_view text, const std::string& source);

/// Reads a tool file of `format` from disk, bounded by kMaxToolFileBytes. FreeCAD: a .fctl file is a
/// library whose bits are read relative to it (then from ../Bit/, FreeCAD's own layout), any other
/// file one bit. `units` applies to LinuxCNC tables only.
[[nodiscard]] ToolImport import_tool_file(const std::filesystem::path& path, ToolFormat format,
                                          LengthUnit units = LengthUnit::Mm);

/// A LinuxCNC tool table: the text and what it could not hold (notes).
struct ToolTableText {
  std::string text;
  std::vector<std::string> notes;
};

/// The LinuxCNC tool table of `tools`, mm: a ';' header line, then one line per tool sorted by number,
/// "T<n> P<n> D<diameter> Z0 ;<id>: <type> [r<corner>] <flutes>F [hss]" (words separated by
/// single spaces) — P = T (a tool's pocket on a random tool changer is the machine's to track), Z0
/// (the length offset is measured at the machine), the comment within LinuxCNC's 39 characters (the
/// id shortened if need be, in the notes) and naming what read_linuxcnc_tool_table reads back: type,
/// corner radius, flutes, tool material. Throws millnet::Error naming the tools when one has no
/// number (tools are refused, not numbered), two share one, a number exceeds kLinuxCncMaxPocket, or
/// `tools` is empty. Holder, stick-out, flute length and point angle are not in a LinuxCNC table; a
/// length offset other than the tool's number cannot be either (in the notes).
[[nodiscard]] ToolTableText linuxcnc_tool_table(const std::vector<Tool>& tools);

}  // namespace millnet::tooling::io
