#pragma once
// A part as the pipeline carries it: its prepared mesh and what reading its file found. The file is
// read in app/ (ingest_io's load_prepared); from there on the part travels as this value — the CAD
// report goes with it to every metrics file instead of through a global keyed by file path.
#include "millnet/ingest/mesh.hpp"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace millnet::job {

struct Part {
  std::string name;                      ///< the outputs' stem (the file's stem unless given)
  std::filesystem::path file;            ///< where it was read from
  ingest::Mesh mesh;                     ///< prepared (frame.hpp: the part frame)
  std::optional<ingest::CadReport> cad;  ///< a STEP/IGES file: its unit, tessellation and bodies
  std::size_t triangles = 0;             ///< of the mesh as read (before preparation)
};

}  // namespace millnet::job
