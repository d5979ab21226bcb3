#pragma once
// millnet's own PLY and OFF readers (private to millnet::ingest_io; load_mesh picks them by extension).
// assimp's readers of these formats aborted, crashed, hung or clamped on malformed bytes
// (issue 15: zero-vertex faces, indices out of range, a header without end_header, a header that
// announces 10⁹ vertices in a 1 KB file); these check every count against the file's size before
// allocating and name the file and the line (text) or byte offset (binary) in every error.
#include "millnet/ingest/mesh.hpp"

#include <string>

namespace millnet::ingest::detail {

/// PLY, ASCII or binary (little/big endian): element "vertex" with float/double/integer x y z
/// (other properties and elements skipped), element "face" with the list "vertex_indices" (or
/// "vertex_index"); polygons are triangulated as a fan (v0, vi, vi+1). O(file size).
/// Throws millnet::Error "<name>:<line>: …" (ASCII, header) or "<name>: byte <offset>: …" (binary).
[[nodiscard]] Mesh parse_ply(const std::string& bytes, const std::string& name);

/// OFF (also COFF, NOFF, CNOFF, STOFF: extra values on a line are ignored): keyword, the counts
/// "#V #F [#E]" (on the keyword's line or the next), #V lines "x y z", #F lines "n i1 … in";
/// '#' starts a comment; polygons are triangulated as a fan. O(file size).
[[nodiscard]] Mesh parse_off(const std::string& bytes, const std::string& name);

/// ASCII STL: one or more "solid … endsolid", each of "facet [normal i j k] / outer loop /
/// vertex x y z (3, or more: a fan) / endloop / endfacet"; keywords in any case; stored normals
/// ignored; bit-identical vertices joined. O(file size · log #V). assimp's reader leaked on
/// malformed files (fuzz_mesh_stl). Throws millnet::Error "<name>:<line>: expected …, found …".
[[nodiscard]] Mesh parse_stl_ascii(const std::string& bytes, const std::string& name);

/// Most bytes a PLY header may take before "end_header" (a file without it is refused, not scanned whole).
inline constexpr std::size_t kMaxPlyHeaderBytes = 1 << 20;

}  // namespace millnet::ingest::detail
