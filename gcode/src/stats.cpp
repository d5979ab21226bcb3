// Lengths and times of a program (see stats.hpp for the model).
#include "millnet/gcode/stats.hpp"

#include "millnet/core/error.hpp"
#include "millnet/gcode/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace millnet::gcode {

namespace {

constexpr double kPi = std::numbers::pi;

struct Block {
  double length = 0;         ///< mm
  Point3 dir{};              ///< unit direction
  double v_nom = 0;          ///< mm/s
  bool stop_before = false;  ///< the machine stops before this block (first block, after a pause…)
};

double norm(const Point3& d) { return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }

/// Planner state: blocks of the program in order.
class Planner {
public:
  void stop() { stop_ = true; }
  void add(const Point3& from, const Point3& to, double v_nom) {
    const Point3 d{to[0] - from[0], to[1] - from[1], to[2] - from[2]};
    const double len = norm(d);
    if (len < tol::zero_length_mm) return;
    blocks_.push_back({len, {d[0] / len, d[1] / len, d[2] / len}, v_nom, stop_ || blocks_.empty()});
    stop_ = false;
  }
  std::size_t size() const { return blocks_.size(); }

  /// Total time (s): entry speeds limited by junctions, then backward and forward passes.
  double time_s(double a, double delta) const {
    const std::size_t n = blocks_.size();
    if (n == 0) return 0;
    std::vector<double> entry(n + 1, 0.0);  // entry[n]: the final stop
    for (std::size_t k = 0; k < n; ++k) {
      const Block& b = blocks_[k];
      if (b.stop_before) continue;
      const Block& p = blocks_[k - 1];
      entry[k] = std::min({junction_speed(p.dir, b.dir, a, delta), p.v_nom, b.v_nom});
    }
    for (std::size_t k = n; k-- > 0;)  // backward: decelerate into what follows
      entry[k] = std::min(entry[k], std::sqrt(entry[k + 1] * entry[k + 1] + 2 * a * blocks_[k].length));
    for (std::size_t k = 0; k < n; ++k)  // forward: accelerate from what precedes
      entry[k + 1] = std::min(entry[k + 1], std::sqrt(entry[k] * entry[k] + 2 * a * blocks_[k].length));
    double t = 0;
    for (std::size_t k = 0; k < n; ++k)
      t += trapezoid_time_s(blocks_[k].length, entry[k], entry[k + 1], blocks_[k].v_nom, a);
    return t;
  }

private:
  std::vector<Block> blocks_;
  bool stop_ = true;
};

void positive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v)) throw Error(std::string("gcode: motion model ") + name + " must be > 0");
}

}  // namespace

double trapezoid_time_s(double len, double v_in, double v_out, double v_nom, double a) {
  const double d_acc = (v_nom * v_nom - v_in * v_in) / (2 * a);
  const double d_dec = (v_nom * v_nom - v_out * v_out) / (2 * a);
  if (d_acc + d_dec <= len)  // trapezoid: reaches v_nom and cruises
    return (v_nom - v_in) / a + (v_nom - v_out) / a + (len - d_acc - d_dec) / v_nom;
  // triangle: peaks where the acceleration and deceleration ramps meet
  const double v_peak = std::sqrt((2 * a * len + v_in * v_in + v_out * v_out) / 2);
  return (std::max(v_peak - v_in, 0.0) + std::max(v_peak - v_out, 0.0)) / a;
}

double junction_speed(const Point3& u, const Point3& v, double acceleration_mm_s2, double junction_deviation_mm) {
  const double cos_theta = -(u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);                 // θ between −u and v
  if (cos_theta > tol::straight_cos) return 0;                                         // reversal
  if (cos_theta < -tol::straight_cos) return std::numeric_limits<double>::infinity();  // straight on
  const double s = std::sqrt(std::max(0.0, 0.5 * (1 - cos_theta)));                    // sin(θ/2)
  return std::sqrt(acceleration_mm_s2 * junction_deviation_mm * s / (1 - s));
}

namespace {

/// The in-stock figures of ProgramStats (StockFrame): one pass over the moves in program order.
void add_stock_figures(const Program& program, const StockFrame& frame, ProgramStats& s) {
  Point3 pos{0, 0, frame.clearance_z_mm};
  bool cut_since = false, retracted_after_cut = false, after_rapid = true;
  for (const Item& item : program.items) {  // O(items)
    const auto* mp = std::get_if<Move>(&item);
    if (mp == nullptr) continue;
    const Move& m = *mp;
    const bool drill = m.op == 1;
    double xy = std::hypot(m.to[0] - pos[0], m.to[1] - pos[1]);
    if (m.motion == Motion::ArcCW || m.motion == Motion::ArcCCW) {
      const double r = std::hypot(pos[0] - m.center[0], pos[1] - m.center[1]);
      const double a0 = std::atan2(pos[1] - m.center[1], pos[0] - m.center[0]);
      const double a1 = std::atan2(m.to[1] - m.center[1], m.to[0] - m.center[0]);
      double sw = m.motion == Motion::ArcCCW ? a1 - a0 : a0 - a1;
      while (sw <= tol::full_circle_rad) sw += 2 * kPi;  // equal ends: a full circle
      xy = r * sw;
    }
    const double dz = std::abs(m.to[2] - pos[2]);
    const double len3 = std::hypot(xy, dz);
    if (m.motion == Motion::Rapid) {
      s.xy_rapid_length_mm += xy;
      s.time_at_feeds_min += len3 / frame.rapid_mm_min;
      s.time_constant_feed_min += len3 / frame.rapid_mm_min;
      if (!drill && m.to[2] >= frame.clearance_z_mm - tol::same_z_mm &&
          pos[2] < frame.clearance_z_mm - tol::same_z_mm && cut_since) {
        retracted_after_cut = true;
        cut_since = false;
      }
      after_rapid = true;
    } else {
      if (!drill && m.to[2] < pos[2] - tol::same_z_mm && after_rapid) {
        ++s.entries;
        if (retracted_after_cut) ++s.retractions;  // a retraction counts when the tool goes back in
        retracted_after_cut = false;
      }
      after_rapid = false;
      if (std::min(m.to[2], pos[2]) < 0) {
        s.xy_cut_length_mm += xy;
        if (!drill) cut_since = true;
      }
      const double f = m.feed > 0 ? m.feed : frame.nominal_feed_mm_min;
      s.time_at_feeds_min += len3 / f;
      const bool lateral = dz < tol::same_z_mm && !drill && frame.nominal_feed_mm_min > 0;
      s.time_constant_feed_min += len3 / (lateral ? frame.nominal_feed_mm_min : f);
    }
    pos = m.to;
  }
}

}  // namespace

ProgramStats stats(const Program& program, const MotionModel& model, const StockFrame& frame) {
  positive(model.rapid_mm_min, "rapid_mm_min");
  positive(frame.rapid_mm_min, "stock frame rapid_mm_min");
  positive(model.rapid_mm_min, "rapid_mm_min");
  positive(model.max_feed_mm_min, "max_feed_mm_min");
  positive(model.acceleration_mm_s2, "acceleration_mm_s2");
  if (!(model.junction_deviation_mm >= 0) || !std::isfinite(model.junction_deviation_mm))
    throw Error("gcode: motion model junction_deviation_mm must be >= 0");
  ProgramStats s;
  Planner plan;
  Point3 pos{0, 0, 0};
  std::uint8_t known = 0;
  double feed_time_s = 0;
  for (const Item& item : program.items) {  // O(items + arc chords)
    const Move* m = std::get_if<Move>(&item);
    if (m == nullptr) {
      if (!std::holds_alternative<Comment>(item)) plan.stop();
      continue;
    }
    Point3 from = pos;
    for (std::size_t a = 0; a < 3; ++a)
      if ((known & (1U << a)) == 0) from[a] = m->to[a];  // unknown start: no travel on that axis
    known |= m->axes;
    const bool rapid = m->motion == Motion::Rapid;
    if (!rapid && !(m->feed > 0) && !(frame.nominal_feed_mm_min > 0)) throw Error("gcode: feed move with no feed");
    const double feed = m->feed > 0 ? m->feed : frame.nominal_feed_mm_min;
    const double v_min = rapid ? model.rapid_mm_min : std::min(feed, model.max_feed_mm_min);
    const double v = v_min / 60;
    double length = 0;
    if (m->motion == Motion::Rapid || m->motion == Motion::Line) {
      length = norm({m->to[0] - from[0], m->to[1] - from[1], m->to[2] - from[2]});
      plan.add(from, m->to, v);
    } else {
      const double cx = m->center[0], cy = m->center[1];
      const double r = std::hypot(from[0] - cx, from[1] - cy);
      const double a0 = std::atan2(from[1] - cy, from[0] - cx);
      const double a1 = std::atan2(m->to[1] - cy, m->to[0] - cx);
      double sweep = m->motion == Motion::ArcCCW ? a1 - a0 : a0 - a1;
      while (sweep <= tol::full_circle_rad) sweep += 2 * kPi;  // equal ends: a full circle
      const double dz = m->to[2] - from[2];
      length = std::hypot(r * sweep, dz);
      // Chords of angle φ deviate r(1 − cos(φ/2)) from the arc.
      const double phi_max = r > kArcChordToleranceMm ? 2 * std::acos(1 - kArcChordToleranceMm / r) : sweep;
      const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(sweep / phi_max)));
      const double sign = m->motion == Motion::ArcCCW ? 1.0 : -1.0;
      Point3 p = from;
      for (std::size_t k = 1; k <= n; ++k) {
        const double t = static_cast<double>(k) / static_cast<double>(n);
        const Point3 q = k == n ? m->to
                                : Point3{cx + r * std::cos(a0 + sign * sweep * t),
                                         cy + r * std::sin(a0 + sign * sweep * t), from[2] + dz * t};
        plan.add(p, q, v);
        p = q;
      }
    }
    if (rapid)
      s.rapid_length_mm += length;
    else {
      s.cut_length_mm += length;
      s.plunge_length_mm += std::max(0.0, from[2] - m->to[2]);
    }
    feed_time_s += length / v;
    pos = m->to;
  }
  s.feed_time_min = feed_time_s / 60;
  s.kinematic_time_min = plan.time_s(model.acceleration_mm_s2, model.junction_deviation_mm) / 60;
  s.blocks = plan.size();
  add_stock_figures(program, frame, s);
  return s;
}

}  // namespace millnet::gcode
