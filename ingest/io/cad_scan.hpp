#pragma once
// A structural pre-scan of STEP and IGES files, before Open CASCADE sees them (issue 42; private to
// millnet::ingest_io, no Open CASCADE here). Open CASCADE 7.6 recurses without a bound on what a
// file nests or refers to: parentheses nested 70,000 deep and an assembly that contains itself
// overflowed its stack, an axis placement that refers to itself and a face bound that points at its
// own shell crashed it. This pass reads the file once, linearly, with an explicit stack, and finds
// what must not reach the reader (refused outright, even when a partial read is allowed):
//  * STEP: nesting deeper than kMaxStepNesting, a reference cycle between entities, a product that
//    is its own component or a representation related to itself (through NEXT_ASSEMBLY_USAGE_
//    OCCURRENCE / REPRESENTATION_RELATIONSHIP chains), a number that does not fit a double, a
//    length unit outside [kMinUnitMm, kMaxUnitMm] (EXA METRE, an inch defined as 1e300 mm);
//  * IGES: a transformation-matrix chain (directory field 7) that loops.
// and what makes a read partial (counted, reported with what Open CASCADE lost): syntax errors
// (a ';' inside open parentheses, a stray ')', an entity defined twice) and references to entities
// the file does not define. It also counts the file's faces, which the transfer is checked against.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace millnet::ingest::detail {

/// Deepest parenthesis nesting a STEP file may use. Real files nest 4–5 levels (a complex entity
/// instance holding a list of lists of coordinates); Open CASCADE's parser and transfer recurse per
/// level. The same bound as a config's JSON nesting (app/config.cpp).
inline constexpr int kMaxStepNesting = 64;
/// A file's length unit, mm per unit: from 0.1 nm to 10 km (EXA METRE and worse are refused).
inline constexpr double kMinUnitMm = 1e-7;
inline constexpr double kMaxUnitMm = 1e7;

struct CadScan {
  /// Outright refusal: the first reason, "line 12: …" (empty = none). Nothing else is valid then.
  std::string refusal;
  /// Damage that makes Open CASCADE's read partial: count and the first one ("line 34: …").
  std::size_t syntax_errors = 0;
  std::string first_syntax_error;
  std::size_t unresolved_references = 0;
  std::string first_unresolved_reference;
  /// Face entities in the file: STEP ADVANCED_FACE and FACE_SURFACE; IGES 510 (face), 144
  /// (trimmed surface) and 143 (bounded surface). The transfer must give as many distinct faces.
  std::size_t faces = 0;
  std::size_t entities = 0;  ///< STEP entity instances / IGES directory entries
  /// The length units the file defines, mm per unit (0 = none understood); STEP only.
  double unit_mm = 0;
  int max_depth = 0;  ///< deepest nesting seen (STEP)
};

/// Scans a STEP (ISO 10303-21) file's text. O(bytes + entities + references); memory O(entities +
/// references). Never throws for malformed input (it reports it); only std::bad_alloc.
[[nodiscard]] CadScan scan_step(std::string_view bytes);

/// Scans an IGES file's directory section (fixed 80-column records). O(bytes).
[[nodiscard]] CadScan scan_iges(std::string_view bytes);

/// `s` made safe to quote in a one-line message: control bytes and bytes ≥ 0x7F escaped as \xNN,
/// at most `max_chars` characters of it, then "…" and the full length.
[[nodiscard]] std::string quote_bytes(std::string_view s, std::size_t max_chars = 40);

}  // namespace millnet::ingest::detail
