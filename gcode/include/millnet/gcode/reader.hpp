#pragma once
// G-code text → Program: the subset millnet writes and what users hand-edit in it.
//
// Accepted: G0 G1 G2 G3 (modal motion), G17, G20 / G21 (inch values are converted to mm), G90 /
// G91 (X Y Z absolute / incremental; I J are always incremental from the arc's start), G94;
// words X Y Z I J R (arcs by radius: R > 0 the shorter arc, R < 0 the longer one) F S T N;
// M0 M1 (Pause), M2 M30 (end: later lines are not read), M3 M4 M5 (Spindle), M6 (ToolChange with
// the last T; a comment on the same line becomes its description); comments in ( ) and after ;,
// blank lines and lines holding only "%". Comment-only lines before the first line with words
// become Program::header; later ones Comment items, as do comments beside other words.
// What the Fanuc-style dialect adds (writer.hpp) is read and makes no item: an O program number
// alone on the first line with words; G40, G49, G54, G80 (motion cancelled: axis words need a
// new motion code); G43 with its H offset number; M8 M9 (coolant); G28 only as "G91 G28" with
// zero increments (straight to the machine's home: those axes are unknown afterwards).
// Drilling cycles (issue 40), G90 only: G81 (drill) and G83 (peck drill, Q per peck) with modal Z
// (bottom), R (feed plane) and Q, G98 / G99 (return to the Z before the series / to R; G98 when
// neither is given), G80 ending them; each block becomes the moves LinuxCNC makes of it
// (gcode/cycles.hpp, Move::cycle set; tests/gcode/test_cycles.cpp holds them equal to rs274's),
// refused as LinuxCNC refuses them (R below Z, G83 without Q > 0, no feed) and bounded (10,000
// pecks a block). G82, G73 and the other canned cycles are not read.
// Anything else (another G or M code, another letter, a repeated word, a feed move with no
// feed, an arc whose radius cannot reach its end) throws millnet::Error "<source>:<line>: …"
// naming the word.
//
// What LinuxCNC's interpreter refuses is refused too (issue 42; src/emc/rs274ngc of LinuxCNC):
//  * two codes of one modal group on a line (G0 G1, G90 G91, M3 M5, M0 M30: "Two G-codes used
//    from same modal group"), a comment inside a comment ("Nested comment found");
//  * an arc by centre (I J) whose radius at the start or the end is below 0.00005 in ("Zero-radius
//    arc"), or whose end is not on its circle: the radii at start and end may differ by at most
//    0.02828 mm (0.002828 in under G20), or by up to 100 times that when it is at most 0.1 % of
//    the radius ("Radius to end of arc differs from radius to start");
// and, beyond LinuxCNC, what no machine can do: an X Y Z position (after G20 and G91 are applied)
// or an arc's centre farther than kMaxCoordinateMm from the origin, a tool number outside
// 0…99999, a number that does not fit a double. Since every position and centre lies within the
// bound, an arc's radius is below 2√2 · kMaxCoordinateMm and the chords its users cut it into
// are bounded per arc (gcode/bounds.hpp counts them for a whole program before they are made).
// Messages quote at most 40 characters of a bad word or comment, control bytes as \xNN.
//
// Within a line the words act in the RS-274 order: modes and F S T, tool change, spindle, motion,
// pause, end. The programme's preamble and end code make no items, so write → read → write
// gives the same text.
#include "millnet/gcode/program.hpp"

#include <string_view>

namespace millnet::gcode {

/// The travel bound, mm: no position or arc centre of a program read lies farther from the origin
/// along any axis (100 m; a machine's travel is a few metres at most).
inline constexpr double kMaxCoordinateMm = 1e5;

[[nodiscard]] Program read(std::string_view text, std::string_view source_name);

}  // namespace millnet::gcode
