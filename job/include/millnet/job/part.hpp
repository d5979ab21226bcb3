#pragma once
// A part as the pipeline carries it: its prepared mesh and what reading its file found. The file is
// read in app/ (ingest_io's load_prepared); from there on the part travels as this value — the CAD
// report goes with it to every metrics file instead of through a global keyed by file path.
#include "millnet/ingest/mesh.hpp"

#include <cstddef>
#include <filesystem>
#include <cstdint>
#include <optional>
#include <vector>
#include <string>

namespace millnet::job {

struct Part {
  std::string name;                      ///< the outputs' stem (the file's stem unless given)
  std::filesystem::path file;            ///< where it was read from
  ingest::Mesh mesh;                     ///< prepared (frame.hpp: the part frame)
  std::optional<ingest::CadReport> cad;  ///< a STEP/IGES file: its unit, tessellation and bodies
  std::size_t triangles = 0;             ///< of the mesh as read (before preparation)
};

/// A selection of a mesh's triangles from a selection of faces: triangle t is selected when
/// chosen_face[triangle_face[t]] (triangle_face: each triangle's 1-based face, ingest::CadReport;
/// chosen_face indexed by face, [0] unused). O(triangles).
[[nodiscard]] std::vector<bool> triangles_of_faces(const std::vector<std::int32_t>& triangle_face,
                                                   const std::vector<bool>& chosen_face);

/// The triangles of a STEP/IGES part's faces named by 1-based index ("7") or by their name in the
/// file (every face of that name), as a selection of its mesh's triangles. Throws millnet::Error
/// naming the part file for a mesh part (no faces), a face index out of range or a name no face has.
/// O(faces · names + triangles).
[[nodiscard]] std::vector<bool> face_selection(const Part& part, const std::vector<std::string>& faces);

}  // namespace millnet::job
