#pragma once
// STEP and IGES parts (private to millnet::ingest_io): Open CASCADE lives in cad_occt.cpp only, and only
// when the build found it (CMake option MILLNET_CAD); load_mesh picks this reader by extension.
#include "millnet/ingest/mesh.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace millnet::ingest::detail {

/// ".step", ".stp", ".iges", ".igs".
[[nodiscard]] const std::vector<std::string>& cad_extensions();

/// True when this build reads CAD files (MILLNET_CAD=ON).
[[nodiscard]] bool cad_supported();

/// Reads a STEP or IGES file, keeps every solid, shell and free face (or options.body), tessellates
/// with BRepMesh_IncrementalMesh at options' linear and angular deflections (sequential: the same bytes
/// for any thread count) and returns the triangles in mm, whatever the file's unit (Open CASCADE
/// converts to its session unit, set to mm). Bit-identical vertices of neighbouring faces are joined;
/// the winding follows each face's orientation (outward normals for a solid). Fills report->cad.
/// Throws millnet::Error naming the file: not STEP/IGES, truncated, unreadable, no solid/shell/face,
/// an unknown body (listing the available ones), an Open CASCADE failure; "built without CAD support"
/// when MILLNET_CAD=OFF. Nothing is printed: Open CASCADE's messenger is silenced.
/// Issue 42: the file is pre-scanned first (cad_scan.hpp: nesting, reference cycles, assemblies
/// that contain themselves, numbers and units out of range are refused before Open CASCADE reads
/// it); the read, the transfer check (a partial read is refused unless options.allow_partial,
/// counting what was lost), the size check (no coordinate beyond 1e5 mm), the tessellation's
/// estimate (check_work against options.limits) and the tessellation run in a child process
/// (cad_isolate.hpp, unless !options.isolate) under options.timeout_s and the memory limit: a
/// crash, a timeout or runaway memory there is one line, "<file>: the STEP reader crashed (signal
/// 11, SIGSEGV, segmentation fault): …".
[[nodiscard]] Mesh load_cad(const std::filesystem::path& path, const CadOptions& options, MeshReport* report);

}  // namespace millnet::ingest::detail
