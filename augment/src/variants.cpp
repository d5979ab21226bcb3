#include "millnet/augment/variants.hpp"

#include "millnet/core/error.hpp"

#include <Eigen/Geometry>

#include <cctype>
#include <cmath>
#include <numbers>

namespace millnet::augment {

Axis parse_axis(std::string_view s) {
  if (s.size() == 1) {
    switch (std::tolower(static_cast<unsigned char>(s[0]))) {
      case 'x': return Axis::X;
      case 'y': return Axis::Y;
      case 'z': return Axis::Z;
      default: break;
    }
  }
  throw Error("axis: unknown value '" + std::string(s) + "', expected one of x, y, z");
}

char to_char(Axis a) {
  switch (a) {
    case Axis::X: return 'x';
    case Axis::Y: return 'y';
    case Axis::Z: return 'z';
  }
  return '?';
}

AugmentParams AugmentParams::defaults() {
  AugmentParams p;
  // Integer steps, so the angles are exact (no accumulated 10° rounding).
  for (int k = -5; k <= 5; ++k) p.angles_deg.push_back(10.0 * k);
  p.axes = {Axis::X};
  p.flip = true;
  return p;
}

std::vector<Variant> make_variants(const std::string& source, const AugmentParams& params) {
  if (params.angles_deg.empty()) throw Error("augment: the list of angles is empty");
  if (params.axes.empty()) throw Error("augment: the list of axes is empty");
  for (double a : params.angles_deg)
    if (!std::isfinite(a)) throw Error("augment: angle " + std::to_string(a) + " is not a finite number of degrees");
  std::vector<Variant> out;
  out.reserve((params.flip ? 2 : 1) * params.axes.size() * params.angles_deg.size());
  for (int f = 0; f < (params.flip ? 2 : 1); ++f)
    for (Axis ax : params.axes)
      for (double a : params.angles_deg) out.push_back(Variant{source, ax, a, f == 1});
  return out;
}

ingest::Mesh apply(const ingest::Mesh& mesh, const Variant& variant) {
  ingest::Mesh out = mesh;
  if (mesh.V.rows() == 0) return out;
  const Eigen::Vector3d axis = variant.axis == Axis::X   ? Eigen::Vector3d::UnitX()
                               : variant.axis == Axis::Y ? Eigen::Vector3d::UnitY()
                                                         : Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d r = Eigen::AngleAxisd(variant.angle_deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
  if (variant.flip) {
    // Exact 180° about Z (cos π is not exactly −1 in floating point).
    Eigen::Matrix3d fz;
    fz << -1, 0, 0, 0, -1, 0, 0, 0, 1;
    r = (r * fz).eval();
  }
  if (variant.angle_deg == 0.0 && !variant.flip) return out;  // identity, bit for bit
  const ingest::Box3 box = ingest::bounds(mesh);
  const Eigen::RowVector3d c = (0.5 * (box.min + box.max)).transpose();
  out.V = ((mesh.V.rowwise() - c) * r.transpose()).rowwise() + c;
  return out;
}

}  // namespace millnet::augment
