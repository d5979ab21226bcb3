#pragma once
// The tessellation's estimate before it runs (issue 42 §3; cad_estimate.cpp has the measurements it
// rests on). Compiled with Open CASCADE only (MILLNET_HAVE_CAD).
#if MILLNET_HAVE_CAD
#include <TopoDS_Shape.hxx>

#include <cstddef>

namespace millnet::ingest::detail {

/// The mesher's peak memory per triangle (measured 1.3–3.7 kB: cad_estimate.cpp).
inline constexpr double kMesherBytesPerTriangle = 4000;
/// The mesh returned, per triangle placed: its indices, about half a vertex, the weld's index.
inline constexpr double kMeshBytesPerTriangle = 100;

struct TessellationEstimate {
  double triangles = 0;  ///< the mesher's (each distinct face once)
  double steps = 0;
  double placed = 0;  ///< the mesh's: a face placed k times (an assembly's instances) counts k times
  std::size_t faces = 0;
};

[[nodiscard]] TessellationEstimate estimate_tessellation(const TopoDS_Shape& shape, double chord, double angle);

}  // namespace millnet::ingest::detail
#endif
