#pragma once
// Program → G-code text for one controller dialect. One writer for every millnet program.
//
// Text layout (every dialect): the header as comment lines, the preamble, the items in order, the
// end code. Coordinates are absolute (G90) with `decimals` decimals (trailing zeros dropped, "-0"
// written as "0"); an axis is written when the block states it and its text differs from the
// previous one (arcs always state X and Y); arc centres as incremental I J (the default IJ mode of
// both dialects); F only when the feed changes (never on G0); S with no decimals.
//
// Dialect differences (what each controller accepts):
//   LinuxCNC  "T<n> M6" tool changes, M1 optional stop, long comments.
//   Fanuc     tape format ("%" … "%", O number), G54, G43 H tool length compensation after M6,
//             M8/M9 coolant, "X10." decimal points, 3 decimals, Z home by G91 G28 Z0. at the end.
//   GRBL 1.1  no M6 (error 20, "unsupported command"): a tool change is written as a comment
//             and M0 so the operator changes the tool by hand; M1 is parsed and ignored (no
//             pause), so an optional stop is written as M0; comments are kept short because
//             streaming senders count every character of a line against the 128-byte serial
//             buffer (GRBL strips comments itself, but only after receiving them).
#include "millnet/gcode/program.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::gcode {

enum class WorkOrigin : std::uint8_t { PartCorner, StockCorner, StockCentre };

/// The stock block around a part's footprint [x0, x1] × [y0, y1] (issue 38; /rough/margin_mm,
/// /rough/stock_offsets_mm, /rough/stock_size_mm): one margin on every side, or an offset per side,
/// or a block of a given size centred on the footprint.
struct StockBlock {
  double margin_mm = 0;
  std::optional<std::array<double, 4>> offsets_mm;  ///< x−, x+, y−, y+ (≥ 0)
  std::optional<std::array<double, 2>> size_mm;     ///< X, Y: the block, centred on the footprint
  /// The offsets of the block's sides from a footprint of `width` × `depth` (x−, x+, y−, y+). Throws
  /// millnet::Error when the size is smaller than the footprint (naming /rough/stock_size_mm).
  [[nodiscard]] std::array<double, 4> sides(double width, double depth) const;
};

struct Dialect {
  std::string name = "linuxcnc";
  int decimals = 4;       ///< coordinate decimals (both controllers accept 3–8)
  int feed_decimals = 1;  ///< F decimals
  std::string preamble = "G21 G90 G17 G94";
  std::string end = "M30";
  bool tool_change_m6 = true;         ///< false: "(tool change: T<n> …)" + M0
  bool optional_stop_m1 = true;       ///< false: an optional stop is written as M0
  std::size_t max_comment_chars = 0;  ///< longer comment text is cut (0: no limit)
  std::string start;                  ///< lines before the program ("%" for tape-format controls)
  int program_number = 0;             ///< > 0: an "O<nnnn>" line first (Fanuc program number)
  /// Every number of an axis, centre or feed with a decimal point ("X10." not "X10": a Fanuc
  /// control reads "X10" as 10 least increments, 0.01 mm).
  bool decimal_point = false;
  std::string coolant_on;   ///< after each spindle start ("M8"; empty: none)
  std::string coolant_off;  ///< before each spindle stop ("M9")
  /// After each tool change, tool length compensation "G43 H<tool>" on the first move (with its Z).
  bool tool_length_offset = false;
  /// Drilling cycles (moves marked Move::cycle, gcode/cycles.hpp) as canned cycle blocks: "G98 G81
  /// X Y Z R F" (G83 with Q), the next holes of a series by their X Y, then G80. False: the moves
  /// themselves (GRBL 1.1 has no canned cycles).
  bool canned_cycles = true;
  /// Inch output (G20): coordinates, arc offsets and feeds (in/min) divided by 25.4. Programs stay
  /// millimetres inside millnet; the reader converts G20 back.
  bool inch = false;
  /// Where the work origin (G54's X0 Y0) lies (/machine/work_origin): at the part footprint's
  /// lower-left corner (millnet's own frame), the stock's lower-left corner, or the stock's centre.
  WorkOrigin origin_at = WorkOrigin::PartCorner;
  StockBlock stock;  ///< the stock around each part's footprint (where its corner and centre are)
  /// The work origin in millnet's frame, mm (set per part by placed()): X Y are written as x − origin
  /// and shifted back when a program is read back (written(), shift()).
  std::array<double, 2> origin{0, 0};
  bool origin_placed = false;  ///< placed() ran (a pocket's program keeps its own frame)
};

/// The dialect with its origin placed for a part whose footprint is [x0, x1] × [y0, y1] (millnet's
/// frame): origin_at's point of the stock (d.stock around the footprint). A header line names it.
[[nodiscard]] Dialect placed(Dialect d, double x0, double y0, double x1, double y1);
/// "part footprint's lower-left corner", "stock's lower-left corner", "stock's centre".
[[nodiscard]] std::string to_string(WorkOrigin w);
/// Moves every move (end points and arc centres) by (dx, dy): a program read in a work frame back
/// into millnet's.
void shift(Program& program, double dx, double dy);

/// The dialect writing inches (an inch shop's job, /machine/program_units): G20 in place of G21 in
/// the preamble, one more decimal on coordinates and feeds (0.0001 in is 0.00254 mm, a Fanuc inch
/// control's least increment), a header line saying so.
[[nodiscard]] Dialect in_inches(Dialect d);

[[nodiscard]] Dialect linuxcnc(int decimals = 4);
[[nodiscard]] Dialect grbl(int decimals = 4);
/// Fanuc-style (Fanuc 0i/30i, Haas and most industrial controls): "%" and an O number, a safety
/// line (G21 G90 G17 G94 G40 G80: not G49, so that a program without a tool change keeps the length
/// offset the operator set) and work offset G54, "T<n> M6" then G43 H<n> on the first
/// move, flood coolant M8/M9 with the spindle, a decimal point on every coordinate, at most 3
/// decimals (the controls' least increment, 0.001 mm), and the end "G91 G28 Z0." (Z home) "G90 M30 %".
[[nodiscard]] Dialect fanuc(int decimals = 3);

/// The registry of dialects (the posts a machine profile may name, /machine/post and --post): one
/// entry per controller, in the order the CLI lists them. A new dialect is one entry here (and its
/// factory beside linuxcnc() and grbl()); the config schema's enum is checked against it by a test.
struct DialectEntry {
  std::string_view name;     ///< "linuxcnc"
  std::string_view summary;  ///< one line for --help and docs
  Dialect (*make)(int decimals);
};
[[nodiscard]] const std::vector<DialectEntry>& dialects();
/// The registry's names, in its order.
[[nodiscard]] std::vector<std::string> dialect_names();
/// The dialect of a registry name; throws millnet::Error naming the accepted values.
[[nodiscard]] Dialect dialect_named(std::string_view name, int decimals = 4);

/// The program's text. Throws millnet::Error on a non-finite coordinate or feed, or decimals
/// outside [3, 8].
[[nodiscard]] std::string write(const Program& program, const Dialect& dialect);

/// A program as the controller gets it: its text in a dialect, and that text read back (gcode::read),
/// so that coordinates carry the dialect's rounding and every item its source line. What the
/// simulator machines and the previews draw, without a round trip through the file system.
struct Written {
  std::string text;
  Program program;
};
[[nodiscard]] Written written(const Program& program, const Dialect& dialect, std::string_view source_name);

/// written() to a file, atomically (core's write_file_atomic: nothing half-written): the one place
/// a program becomes a file. Returns what was written (source name: the path).
Written write_program(const std::filesystem::path& path, const Program& program, const Dialect& dialect);

/// Number text as the writer prints it: `decimals` decimals, trailing zeros dropped, "-0" → "0".
[[nodiscard]] std::string format_number(double v, int decimals);

}  // namespace millnet::gcode
