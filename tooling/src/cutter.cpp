// Cutter shapes and their checks (cutter.hpp). One torus description covers flat, ball and bull:
// with R = diameter/2, r the profile's corner radius and a = R − r (the radius of the circle of
// corner-arc centres), the profile is 0 for d ≤ a and the corner arc r − √(r² − (d − a)²) beyond.
// The drill's profile is its tip cone.
#include "millnet/tooling/cutter.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace millnet::tooling {

CutterType Cutter::shape() const {
  // A bull whose corner radius is its radius is a ball up to the rounding of the caller's
  // arithmetic (bull:4:2 is accepted and machined as ball:4; issue 36).
  if (type == CutterType::Bull && std::abs(corner_radius - radius()) <= 1e-12 * radius()) return CutterType::Ball;
  return type;
}

double Cutter::distance_to_solid(double cx, double cy, double tip, double px, double py, double pz) const {
  const double R = radius(), rc = profile_corner_radius(), a = R - rc;
  const double rho = std::hypot(px - cx, py - cy);
  if (rho <= a) return std::max(0.0, tip - pz);  // under the flat bottom
  const double dz = pz - (tip + rc);
  if (dz >= 0) return std::max(0.0, rho - R);          // beside the shank
  return std::max(0.0, std::hypot(rho - a, dz) - rc);  // below the corner's centre: the torus
}

double Cutter::profile_corner_radius() const {
  switch (shape()) {
    case CutterType::Flat:
    case CutterType::Drill: return 0;
    case CutterType::Ball: return radius();
    case CutterType::Bull: return corner_radius;
  }
  return 0;
}

double Cutter::point_height() const {
  if (type != CutterType::Drill) return 0;
  return radius() / std::tan(0.5 * point_angle_deg * std::numbers::pi / 180);
}

double Cutter::profile_height(double d) const {
  const double R = radius();
  d = std::abs(d);
  if (d > R) return std::numeric_limits<double>::infinity();
  if (type == CutterType::Drill) return d / std::tan(0.5 * point_angle_deg * std::numbers::pi / 180);
  const double r = profile_corner_radius();
  const double a = R - r;
  if (d <= a) return 0.0;
  const double u = d - a;
  return r - std::sqrt(std::max(0.0, r * r - u * u));
}

void Cutter::check() const {
  if (!std::isfinite(diameter) || !(diameter > 0) || diameter > kMaxCutterDiameterMm)
    throw Error("cutter: diameter must be a finite number > 0 and <= " + format_double(kMaxCutterDiameterMm) +
                " mm, got " + format_double(diameter));
  if (!std::isfinite(corner_radius))
    throw Error("cutter: corner radius must be finite, got " + format_double(corner_radius));
  const double R = radius();
  switch (type) {
    case CutterType::Flat:
      if (corner_radius != 0.0)
        throw Error("cutter: a flat end mill has corner radius 0, got " + format_double(corner_radius) +
                    " (a rounded corner is a bull nose)");
      break;
    case CutterType::Ball:
      // Ball radius = diameter / 2, up to rounding of the caller's arithmetic.
      if (std::abs(corner_radius - R) > 1e-12 * R)
        throw Error("cutter: a ball end mill has corner radius = diameter/2 = " + format_double(R) + ", got " +
                    format_double(corner_radius));
      break;
    case CutterType::Bull:
      if (!(corner_radius > 0) || corner_radius > R * (1 + 1e-12))
        throw Error("cutter: a bull nose needs 0 < corner radius <= diameter/2 = " + format_double(R) + ", got " +
                    format_double(corner_radius));
      break;
    case CutterType::Drill:
      if (corner_radius != 0.0) throw Error("cutter: a drill has corner radius 0, got " + format_double(corner_radius));
      if (!(point_angle_deg > 0 && point_angle_deg < 180))
        throw Error("cutter: a drill's point angle must lie in (0, 180) degrees, got " +
                    format_double(point_angle_deg));
      break;
  }
  if (!(std::isfinite(flute_length_mm) && flute_length_mm >= 0 && flute_length_mm <= 10000))
    throw Error("cutter: flute length must lie in [0, 10000] mm, got " + format_double(flute_length_mm));
  if (!(std::isfinite(reach_mm) && reach_mm >= 0 && reach_mm <= 10000))
    throw Error("cutter: reach (stick-out) must lie in [0, 10000] mm, got " + format_double(reach_mm));
}

std::string Cutter::describe() const {
  std::ostringstream os;
  os.precision(6);
  switch (type) {
    case CutterType::Flat: os << "flat D" << diameter; break;
    case CutterType::Ball: os << "ball D" << diameter; break;
    case CutterType::Bull: os << "bull D" << diameter << " r" << corner_radius; break;
    case CutterType::Drill: os << "drill D" << diameter; break;
  }
  return os.str();
}

}  // namespace millnet::tooling
