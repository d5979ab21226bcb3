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
// Anything else (another G or M code, another letter, a repeated word, a feed move with no
// feed, an arc whose radius cannot reach its end) throws millnet::Error "<source>:<line>: …"
// naming the word.
//
// Within a line the words act in the RS-274 order: modes and F S T, tool change, spindle, motion,
// pause, end. The programme's preamble and end code make no items, so write → read → write
// gives the same text.
#include "millnet/gcode/program.hpp"

#include <string_view>

namespace millnet::gcode {

[[nodiscard]] Program read(std::string_view text, std::string_view source_name);

}  // namespace millnet::gcode
