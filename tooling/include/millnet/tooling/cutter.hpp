#pragma once
// The cutter: the one description of a tool's cutting shape that every module takes (finishing's
// drop-cutter and waterline, the z-map simulator, roughing's clearances, the previews). Its checks
// are the only ones: a cutter that passes check() is machined, simulated and drawn alike.
//
// Rotationally symmetric tools with a vertical axis. The cutter location (CL) is the tool TIP: the
// lowest point of the cutter on its axis. With R = diameter/2 and r = corner_radius:
//
//   flat  (end mill)   r = 0              profile 0
//   ball  (ball nose)  r = R              profile R − √(R² − d²)
//   bull  (torus)      0 < r ≤ R          profile 0 for d ≤ R − r, then the corner arc
//                                         r − √(r² − (d − R + r)²); a bull with r = R is a ball
//   drill (twist drill) r = 0, point angle  profile d / tan(point_angle/2): a cone
//
// The profile is the height of the cutter's surface above the tip at radial distance d ≤ R; the
// cutter is taken as a cylinder of radius R above it up to its flute length (0 = not stated), and
// the holder starts at its reach (stick-out; 0 = not stated).
#include <cstdint>
#include <string>

namespace millnet::tooling {

enum class CutterType : std::uint8_t { Flat, Ball, Bull, Drill };

/// Largest tool diameter any cutter may have, mm (the tool library's range too).
inline constexpr double kMaxCutterDiameterMm = 1000;
/// A drill's point angle when none is given (the common 118° twist drill), degrees.
inline constexpr double kDefaultPointAngleDeg = 118;

struct Cutter {
  CutterType type = CutterType::Ball;
  double diameter = 2;                             ///< mm, in (0, kMaxCutterDiameterMm]
  double corner_radius = 1;                        ///< mm; flat and drill 0, ball diameter/2, bull in (0, diameter/2]
  double point_angle_deg = kDefaultPointAngleDeg;  ///< drill only: included angle of the tip, (0, 180)
  double flute_length_mm = 0;                      ///< cutting length above the tip; 0 = not stated
  double reach_mm = 0;                             ///< stick-out: tip to holder; 0 = not stated

  [[nodiscard]] static Cutter flat(double diameter) { return {CutterType::Flat, diameter, 0}; }
  [[nodiscard]] static Cutter ball(double diameter) { return {CutterType::Ball, diameter, diameter / 2}; }
  [[nodiscard]] static Cutter bull(double diameter, double corner_radius) {
    return {CutterType::Bull, diameter, corner_radius};
  }
  [[nodiscard]] static Cutter drill(double diameter, double point_angle_deg = kDefaultPointAngleDeg) {
    return {CutterType::Drill, diameter, 0, point_angle_deg};
  }
  [[nodiscard]] double radius() const { return diameter / 2; }
  /// The shape its profile has: a bull nose whose corner radius is its radius is a ball; every
  /// other cutter has the shape of its type. Kernels switch on this, never on `type`.
  [[nodiscard]] CutterType shape() const;
  /// The corner radius the profile uses: 0 for flat and drill, R for ball (whatever was stored).
  [[nodiscard]] double profile_corner_radius() const;
  /// Height of the tip cone of a drill above its tip, R / tan(point_angle/2); 0 for other cutters.
  [[nodiscard]] double point_height() const;
  /// Height of the cutter's surface above the tip at radial distance d from the axis (0 ≤ |d| ≤ R);
  /// +infinity for |d| > R (outside the cutter).
  [[nodiscard]] double profile_height(double d) const;
  /// The Euclidean distance from point (px, py, pz) to the cutter's solid with its tip at (cx, cy,
  /// tip), axis vertical: the profile revolved (the core disk of radius R − rc at tip + rc widened
  /// by a ball of radius rc) and the shank, a cylinder of radius R, above it; 0 inside. Exact for
  /// flat, ball and bull; a drill is taken as a flat of its diameter (its cone not modelled). O(1).
  [[nodiscard]] double distance_to_solid(double cx, double cy, double tip, double px, double py, double pz) const;
  /// Throws millnet::Error "cutter: …" when a dimension is not finite or outside the ranges above.
  void check() const;
  /// "ball D2", "flat D10", "bull D6 r1", "drill D5" (comments, metrics, previews).
  [[nodiscard]] std::string describe() const;
};

}  // namespace millnet::tooling
