// Cutter profiles (cutter.hpp): one torus description covers the three types. With R = diameter/2,
// r = corner_radius and a = R − r (the radius of the circle of corner-arc centres):
//   flat  r = 0, a = R;  ball  r = R, a = 0;  bull  0 < r < R.
// The profile is flat (height 0) for d ≤ a and the corner arc r − √(r² − (d − a)²) for a < d ≤ R.
#include "millnet/finish/cutter.hpp"

#include "millnet/core/error.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace millnet::finish {

double Cutter::profile_height(double d) const {
  const double R = radius();
  d = std::abs(d);
  if (d > R) return std::numeric_limits<double>::infinity();
  const double r = type == CutterType::Flat ? 0.0 : corner_radius;
  const double a = R - r;
  if (d <= a) return 0.0;
  const double u = d - a;
  return r - std::sqrt(std::max(0.0, r * r - u * u));
}

void Cutter::check() const {
  if (!std::isfinite(diameter) || !(diameter > 0))
    throw Error("cutter: diameter must be a finite number > 0 mm, got " + std::to_string(diameter));
  if (!std::isfinite(corner_radius))
    throw Error("cutter: corner radius must be finite, got " + std::to_string(corner_radius));
  const double R = radius();
  switch (type) {
    case CutterType::Flat:
      if (corner_radius != 0.0)
        throw Error("cutter: a flat end mill has corner radius 0, got " + std::to_string(corner_radius));
      break;
    case CutterType::Ball:
      // Ball radius = diameter / 2, up to rounding of the caller's arithmetic.
      if (std::abs(corner_radius - R) > 1e-12 * R)
        throw Error("cutter: a ball end mill has corner radius = diameter/2 = " + std::to_string(R) + ", got " +
                    std::to_string(corner_radius));
      break;
    case CutterType::Bull:
      if (!(corner_radius > 0) || corner_radius > R)
        throw Error("cutter: a bull nose needs 0 < corner radius <= diameter/2 = " + std::to_string(R) + ", got " +
                    std::to_string(corner_radius));
      break;
  }
}

std::string Cutter::describe() const {
  std::ostringstream os;
  os.precision(6);
  switch (type) {
    case CutterType::Flat: os << "flat D" << diameter; break;
    case CutterType::Ball: os << "ball D" << diameter; break;
    case CutterType::Bull: os << "bull D" << diameter << " r" << corner_radius; break;
  }
  return os.str();
}

}  // namespace millnet::finish
