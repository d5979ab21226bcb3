#include "millnet/ingest/mesh.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/tolerances.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>

namespace millnet::ingest {

namespace {
std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}
Eigen::Vector3d vertex(const Mesh& m, std::int32_t i) { return m.V.row(static_cast<Eigen::Index>(i)).transpose(); }
}  // namespace

Units parse_units(std::string_view s) {
  const std::string l = lower(s);
  if (l == "mm") return Units::mm;
  if (l == "inch" || l == "in") return Units::inch;
  if (l == "m") return Units::m;
  throw Error("units: unknown value '" + std::string(s) + "', expected one of mm, inch, in, m");
}

double units_to_mm(Units u) {
  switch (u) {
    case Units::mm: return 1.0;
    case Units::inch: return 25.4;
    case Units::m: return 1000.0;
  }
  return 1.0;
}

Up parse_up(std::string_view s) {
  const std::string l = lower(s);
  if (l == "+z" || l == "z") return Up::PosZ;
  if (l == "-z") return Up::NegZ;
  if (l == "+y" || l == "y") return Up::PosY;
  if (l == "-y") return Up::NegY;
  if (l == "+x" || l == "x") return Up::PosX;
  if (l == "-x") return Up::NegX;
  if (l == "auto") return Up::Auto;
  throw Error("up: unknown value '" + std::string(s) + "', expected one of +z, -z, +y, -y, +x, -x, auto");
}

std::string to_string(Up u) {
  switch (u) {
    case Up::PosZ: return "+z";
    case Up::NegZ: return "-z";
    case Up::PosY: return "+y";
    case Up::NegY: return "-y";
    case Up::PosX: return "+x";
    case Up::NegX: return "-x";
    case Up::Auto: return "auto";
  }
  return "?";
}

void validate(const Mesh& mesh, const std::string& source, MeshReport* report) {
  const Eigen::Index nv = mesh.V.rows();
  const Eigen::Index nf = mesh.F.rows();
  if (nf == 0) throw Error(source + ": no triangles");
  // O(#V): every coordinate finite.
  for (Eigen::Index i = 0; i < nv; ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      if (!std::isfinite(mesh.V(i, k)))
        throw Error(source + ": vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or inf)");
  // O(#F): indices in range.
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      const std::int32_t i = mesh.F(f, k);
      if (i < 0 || static_cast<Eigen::Index>(i) >= nv)
        throw Error(source + ": triangle " + std::to_string(f) + " refers to vertex " + std::to_string(i) +
                    ", expected 0…" + std::to_string(nv - 1));
    }
  }
  // O(#F) at worst, O(1) for a real surface (it stops at the first triangle with an area): a mesh
  // of collinear or coincident triangles was sampled and roughed as a part ("1 level, cut 270 mm";
  // issue 42 §8, tests/corpus/mesh/every_triangle_collinear.off).
  {
    Eigen::Index f = 0;
    for (; f < nf; ++f) {
      const Eigen::Vector3d a = vertex(mesh, mesh.F(f, 0)), b = vertex(mesh, mesh.F(f, 1)),
                            c = vertex(mesh, mesh.F(f, 2));
      if (0.5 * (b - a).cross(c - a).norm() > tol::degenerate_area_mm2) break;
    }
    if (f == nf)
      throw Error(source + ": every triangle has zero area (" + std::to_string(nf) +
                  " triangles of collinear or coincident vertices), expected a surface");
  }
  if (!report) return;
  // O(#F): degenerate (zero-area) triangles.
  std::size_t degenerate = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = vertex(mesh, mesh.F(f, 0)), b = vertex(mesh, mesh.F(f, 1)),
                          c = vertex(mesh, mesh.F(f, 2));
    if (0.5 * (b - a).cross(c - a).norm() <= tol::degenerate_area_mm2) ++degenerate;
  }
  report->triangles = static_cast<std::size_t>(nf);
  report->degenerate_triangles = degenerate;

  // Duplicates: sort the vertex triples (as sets) — O(#F log #F).
  std::vector<std::array<std::int32_t, 3>> tris(static_cast<std::size_t>(nf));
  // Edges as (min, max) pairs packed in 64 bits, sorted and run-length counted — O(#F log #F).
  std::vector<std::uint64_t> edges;
  edges.reserve(static_cast<std::size_t>(nf) * 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    std::array<std::int32_t, 3> t{mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(t[static_cast<std::size_t>(k)]);
      const auto b = static_cast<std::uint32_t>(t[static_cast<std::size_t>((k + 1) % 3)]);
      if (a == b) continue;  // collapsed edge of a degenerate triangle
      edges.push_back((static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b));
    }
    std::sort(t.begin(), t.end());
    tris[static_cast<std::size_t>(f)] = t;
  }
  std::sort(tris.begin(), tris.end());
  std::size_t dup = 0;
  for (std::size_t i = 1; i < tris.size(); ++i)
    if (tris[i] == tris[i - 1]) ++dup;
  std::sort(edges.begin(), edges.end());
  std::size_t boundary = 0, nonmanifold = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++boundary;
    if (j - i > 2) ++nonmanifold;
    i = j;
  }
  report->duplicate_triangles = dup;
  report->boundary_edges = boundary;
  report->non_manifold_edges = nonmanifold;
  if (degenerate) report->notes.push_back(std::to_string(degenerate) + " degenerate (zero-area) triangles");
  if (dup) report->notes.push_back(std::to_string(dup) + " duplicate triangles");
  if (boundary) report->notes.push_back(std::to_string(boundary) + " boundary edges (open shell or cracks)");
  if (nonmanifold) report->notes.push_back(std::to_string(nonmanifold) + " non-manifold edges");
}

Eigen::Matrix3d up_rotation(Up up) {
  Eigen::Matrix3d r;
  switch (up) {
    case Up::PosZ: r.setIdentity(); break;
    case Up::NegZ: r << 1, 0, 0, 0, -1, 0, 0, 0, -1; break;  // (x, −y, −z)
    case Up::PosY: r << 1, 0, 0, 0, 0, -1, 0, 1, 0; break;   // (x, −z, y): +Y → +Z
    case Up::NegY: r << 1, 0, 0, 0, 0, 1, 0, -1, 0; break;   // (x, z, −y): −Y → +Z
    case Up::PosX: r << 0, 0, -1, 0, 1, 0, 1, 0, 0; break;   // (−z, y, x): +X → +Z
    case Up::NegX: r << 0, 0, 1, 0, 1, 0, -1, 0, 0; break;   // (z, y, −x): −X → +Z
    case Up::Auto: throw Error("up_rotation: Up::Auto must be resolved with choose_up() first");
  }
  return r;
}

Up choose_up(const Mesh& mesh, Up requested) {
  if (requested != Up::Auto) return requested;
  constexpr std::array<Up, 6> candidates{Up::PosZ, Up::NegZ, Up::PosY, Up::NegY, Up::PosX, Up::NegX};
  const Box3 box = bounds(mesh);
  const double cos_flat = std::cos(tol::auto_up_flat_deg * std::numbers::pi / 180.0);
  // Per axis a (0..2) and sign: flat area on the low plane facing −a, on the high plane facing +a,
  // and projected area facing ±a. One pass over the triangles: O(#F).
  std::array<double, 3> flat_low{}, flat_high{};
  std::array<double, 3> proj_pos{}, proj_neg{};
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = vertex(mesh, mesh.F(f, 0)), b = vertex(mesh, mesh.F(f, 1)),
                          c = vertex(mesh, mesh.F(f, 2));
    const Eigen::Vector3d n2 = (b - a).cross(c - a);  // 2·area·unit normal
    const double area2 = n2.norm();
    if (area2 <= 0) continue;
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      const double comp = n2(k) / area2;
      if (n2(k) > 0)
        proj_pos[ku] += 0.5 * n2(k);
      else
        proj_neg[ku] -= 0.5 * n2(k);
      const double lo = std::min({a(k), b(k), c(k)}), hi = std::max({a(k), b(k), c(k)});
      if (comp <= -cos_flat && hi <= box.min(k) + tol::auto_up_plane_mm) flat_low[ku] += 0.5 * area2;
      if (comp >= cos_flat && lo >= box.max(k) - tol::auto_up_plane_mm) flat_high[ku] += 0.5 * area2;
    }
  }
  auto axis_of = [](Up u) -> std::size_t {
    return (u == Up::PosX || u == Up::NegX) ? 0 : (u == Up::PosY || u == Up::NegY) ? 1 : 2;
  };
  auto positive = [](Up u) { return u == Up::PosX || u == Up::PosY || u == Up::PosZ; };
  double best = 0;
  Up chosen = Up::PosZ;
  bool found = false;
  for (Up u : candidates) {
    const std::size_t k = axis_of(u);
    // Working face towards d: the base is the flat face on the opposite extreme plane.
    const double base = positive(u) ? flat_low[k] : flat_high[k];
    const double cap = positive(u) ? flat_high[k] : flat_low[k];
    const double score = base - cap;
    if (score > best) {
      best = score;
      chosen = u;
      found = true;
    }
  }
  if (found) return chosen;
  double best_vis = -1;
  for (Up u : candidates) {
    const std::size_t k = axis_of(u);
    const double vis = positive(u) ? proj_pos[k] : proj_neg[k];
    if (vis > best_vis * (1 + 1e-12) + 1e-12) {
      best_vis = vis;
      chosen = u;
    }
  }
  return chosen;
}

Mesh prepare(const Mesh& raw, const PrepareOptions& options, MeshReport* report) {
  Mesh m = raw;
  const double s = units_to_mm(options.units);
  if (s != 1.0) m.V *= s;
  const Up up = choose_up(m, options.up);
  if (up != Up::PosZ) {
    const Eigen::Matrix3d r = up_rotation(up);
    // Row-vector layout: v' = v·Rᵀ. O(#V).
    m.V = (m.V * r.transpose()).eval();
  }
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  if (options.recentre && m.V.rows() > 0) {
    shift = bounds(m).min;
    m.V.rowwise() -= shift.transpose();
  }
  if (report) {
    report->up_used = up;
    report->recentred_by = shift;
    if (options.up == Up::Auto) report->notes.push_back("up axis chosen automatically: " + to_string(up));
  }
  return m;
}

Box3 bounds(const Mesh& mesh) {
  Box3 b{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (mesh.V.rows() == 0) return b;
  b.min = mesh.V.colwise().minCoeff().transpose();
  b.max = mesh.V.colwise().maxCoeff().transpose();
  return b;
}

}  // namespace millnet::ingest
