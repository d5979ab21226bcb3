#pragma once
// Cutters of the finishing work (ARCHITECTURE.md, finish/): rotationally symmetric end mills with a
// vertical axis, described by their profile. The cutter location (CL) is the tool TIP: the lowest
// point of the cutter on its axis. Flute length and shank are not modelled (the cutter is taken as
// infinitely long above its profile); callers that need a holder check do it themselves.
//
//   flat  (end mill):  corner_radius = 0
//   ball  (ball nose): corner_radius = diameter / 2
//   bull  (torus):     0 < corner_radius < diameter / 2
#include <string>

namespace millnet::finish {

enum class CutterType { Flat, Ball, Bull };

struct Cutter {
  CutterType type = CutterType::Ball;
  double diameter = 2;       ///< mm, > 0
  double corner_radius = 1;  ///< mm; flat 0, ball diameter/2, bull in (0, diameter/2)

  [[nodiscard]] static Cutter flat(double diameter) { return {CutterType::Flat, diameter, 0}; }
  [[nodiscard]] static Cutter ball(double diameter) { return {CutterType::Ball, diameter, diameter / 2}; }
  [[nodiscard]] static Cutter bull(double diameter, double corner_radius) {
    return {CutterType::Bull, diameter, corner_radius};
  }
  [[nodiscard]] double radius() const { return diameter / 2; }
  /// Height of the cutter's surface above the tip at radial distance d from the axis (0 ≤ d ≤ R);
  /// +infinity for d > R (outside the cutter).
  [[nodiscard]] double profile_height(double d) const;
  /// Throws millnet::Error when the dimensions are not finite or out of the ranges above.
  void check() const;
  /// "ball D2", "flat D10", "bull D6 r1" (for comments and metrics).
  [[nodiscard]] std::string describe() const;
};

}  // namespace millnet::finish
