// Passes → one program: the start at safe Z, stay-down links where short (they follow the CL
// surface at feed, so they cannot gouge), lifts elsewhere (up to the highest CL point under the
// link plus the clearance, across at rapid, down at rapid to the clearance, plunge at the plunge
// feed), the end at safe Z. Over a stock (FinishParams::stock_tip, rest finishing) the lifts clear
// the stock too, the rapid down stops tol::rest_approach_mm above it instead of the clearance, and
// a short link stays down only when that is quicker on the machine (FinishParams::motion) than a lift;
// where it stays down, its runs through air (FinishParams::stock_cut_depth) are hopped over.
#include "boundary.hpp"
#include "sampling.hpp"

#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cmath>

namespace millnet::finish::detail {
namespace {

class Builder {
public:
  Builder(const FinishParams& p, FinishPlan& plan) : p_(p), plan_(plan) {}

  void rapid(double x, double y, double z, std::uint8_t axes) {
    gcode::Move m;
    m.motion = gcode::Motion::Rapid;
    m.to = {x, y, z + p_.z_shift};
    m.axes = axes;
    push(m);
  }
  void rapid_z_abs(double z_prog) {  // a program Z (safe Z)
    gcode::Move m;
    m.motion = gcode::Motion::Rapid;
    m.to = {at_[0], at_[1], z_prog};
    m.axes = gcode::kZ;
    push(m);
  }
  void line(const Eigen::Vector3d& q, double feed) {
    gcode::Move m;
    m.motion = gcode::Motion::Line;
    m.to = {q.x(), q.y(), q.z() + p_.z_shift};
    m.feed = feed;
    m.axes = gcode::kXYZ;
    const double len = std::sqrt((m.to[0] - at_[0]) * (m.to[0] - at_[0]) + (m.to[1] - at_[1]) * (m.to[1] - at_[1]) +
                                 (m.to[2] - at_[2]) * (m.to[2] - at_[2]));
    if (len < 1e-9) return;  // nothing to move
    if (p_.stock_cut) p_.stock_cut(Eigen::Vector3d(at_[0], at_[1], at_[2] - p_.z_shift), q);
    plan_.path_length_mm += len;
    ++plan_.cl_points;
    push(m);
  }

private:
  void push(const gcode::Move& m) {
    at_ = m.to;
    plan_.program.items.emplace_back(m);
  }
  const FinishParams& p_;
  FinishPlan& plan_;
  gcode::Point3 at_{0, 0, 0};
};

/// Seconds the machine takes over `moves` from `from`, from rest to rest (gcode::stats' planner).
double moves_time_s(const gcode::Point3& from, const std::vector<gcode::Move>& moves, const gcode::MotionModel& m) {
  gcode::Program prog;
  gcode::Move at;
  at.motion = gcode::Motion::Rapid;
  at.to = from;
  at.axes = gcode::kXYZ;
  prog.items.emplace_back(at);
  for (const gcode::Move& mv : moves) prog.items.emplace_back(mv);  // O(moves)
  return gcode::stats(prog, m).kinematic_time_min * 60;
}

/// A stay-down link's moves from `from` through `path` (its samples, on one XY line, and the next
/// pass's start), each run of moves through air (FinishParams::stock_cut_depth under
/// tol::rest_air_cut_mm) at least tol::rest_air_hop_radii tool radii long hopped instead, when a
/// move that cuts follows it on the link: up at rapid from the last place that cut to
/// tol::rest_approach_mm over the run's highest sample and that move's cut, across, down at rapid
/// to tol::rest_approach_mm over that move's end and cut, and down at the plunge feed into its end
/// (as an entry comes down over the stock). Safe by the stock being a height field: a tool raised
/// over a place where it cuts nothing (the run), or over the most it would cut (the move after),
/// cuts nothing. O(path · placements).
void link_with_hops(const FinishParams& p, Builder& b, const Eigen::Vector3d& from,
                    const std::vector<Eigen::Vector3d>& path, FinishPlan& plan) {
  const double hop_min = tol::rest_air_hop_radii * p.tool.radius();
  Eigen::Vector3d at = from;
  std::size_t k = 0;
  while (k < path.size()) {  // O(path)
    std::size_t e = k;       // the run of moves through air from here: [k, e)
    double len = 0;
    if (p.stock_cut_depth) {
      Eigen::Vector3d q = at;
      while (e < path.size() && p.stock_cut_depth(q, path[e]) < tol::rest_air_cut_mm) {
        len += (path[e] - q).norm();
        q = path[e++];
      }
    }
    if (e > k && e < path.size() && len >= hop_min) {
      const Eigen::Vector3d &last = path[e - 1], &to = path[e];
      double top = std::max(at.z(), to.z());
      for (std::size_t i = k; i < e; ++i) top = std::max(top, path[i].z());
      const double cut = p.stock_cut_depth(last, to), safe = p.safe_z_mm - p.z_shift;
      const double hop = std::min(top + cut + tol::rest_approach_mm, safe);
      const double land = std::min(to.z() + cut + tol::rest_approach_mm, safe);
      b.rapid(at.x(), at.y(), hop, gcode::kZ);
      b.rapid(to.x(), to.y(), hop, gcode::kX | gcode::kY);
      if (land < hop) b.rapid(to.x(), to.y(), land, gcode::kZ);
      b.line(to, p.plunge_feed_mm_min);
      ++plan.lifts;
      ++plan.hops;
      at = to;
      k = e + 1;
      continue;
    }
    const std::size_t upto = std::max(e, k + 1);  // a short run (or one at the link's end) at feed
    for (; k < upto; ++k) b.line(path[k], p.feed_mm_min);
    at = path[k - 1];
  }
}

}  // namespace

void link_passes(const Sampler& s, const FinishParams& p, const Fence& fence, FinishPlan& plan) {
  auto& prog = plan.program;
  if (!p.program_name.empty()) prog.header.push_back(p.program_name);
  prog.header.push_back("strategy: " + strategy_name(plan.strategy));
  for (const auto& c : p.comments) prog.header.push_back(c);
  prog.items.emplace_back(
      gcode::Comment{strategy_name(plan.strategy) + ", " + (p.tool_label.empty() ? p.tool.describe() : p.tool_label)});
  prog.items.emplace_back(gcode::Spindle{gcode::SpindleDir::CW, p.spindle_rpm});
  Builder b(p, plan);
  b.rapid_z_abs(p.safe_z_mm);
  const double h0 = std::min(tol::initial_sample_mm, s.cutter().radius() / 4);
  const double stay_max = p.tool.diameter * tol::stay_down_link_diameters + 4 * p.stepover_mm;
  // Where a pass's plunge begins: the clearance over its start, or, over a stock (rest
  // finishing), just above the stock.
  auto entry = [&p](const Eigen::Vector3d& q) {
    if (!p.stock_tip) return q.z() + p.clearance_mm;
    return std::max(q.z(), p.stock_tip(q.x(), q.y())) + tol::rest_approach_mm;
  };
  const Eigen::Vector3d* prev = nullptr;
  for (const Pass& pass : plan.passes) {
    if (pass.points.size() < 2) continue;
    const Eigen::Vector3d& start = pass.points.front();
    if (prev == nullptr) {
      b.rapid(start.x(), start.y(), p.safe_z_mm - p.z_shift, gcode::kX | gcode::kY);
      b.rapid(start.x(), start.y(), std::min(entry(start), p.safe_z_mm - p.z_shift), gcode::kZ);
      b.line(start, p.plunge_feed_mm_min);
    } else {
      const double d = (start.head<2>() - prev->head<2>()).norm();
      std::vector<Sample> link;
      if (d <= stay_max) link = sample_segment(s, prev->head<2>(), start.head<2>(), h0, p.chord_tolerance_mm);
      const double floor_z = p.stock_tip ? std::min(prev->z(), start.z()) : -HUGE_VAL;
      const bool stays_in = std::all_of(link.begin(), link.end(), [&](const Sample& q) {
        return fence.inside(q.p) &&
               (!p.stock_engagement ||
                p.stock_engagement(q.p.x(), q.p.y(), std::max(q.p.z(), floor_z)) <= p.link_max_cut_mm);
      });
      // Over a stock a link never dips below the lower of its ends: between two raised passes
      // stepping a corner's rest down it would cut through what they leave.
      std::vector<Eigen::Vector3d> stay;
      if (d <= stay_max && stays_in)
        for (std::size_t i = 1; i + 1 < link.size(); ++i)
          stay.emplace_back(link[i].p.x(), link[i].p.y(), std::max(link[i].p.z(), floor_z));
      // The lift's height: the highest CL point (and stock) under the link plus the clearance.
      auto lift_height = [&] {
        double top = std::max(prev->z(), start.z());
        const auto n = static_cast<int>(std::ceil(d / h0));
        for (int i = 0; i <= n; ++i) {  // O(d / h0) drops (and stock tips)
          const Eigen::Vector2d q = prev->head<2>() + (start.head<2>() - prev->head<2>()) * (i / double(n));
          if (i > 0 && i < n) top = std::max(top, s.z(q.x(), q.y()));
          if (p.stock_tip) top = std::max(top, p.stock_tip(q.x(), q.y()));
        }
        return std::min(top + p.clearance_mm, p.safe_z_mm - p.z_shift);
      };
      bool stays = d <= stay_max && stays_in;
      double lift = 0;
      if (!stays || p.stock_tip) lift = lift_height();
      if (stays && p.stock_tip) {  // over a stock: the quicker of the two
        const auto move = [](gcode::Motion kind, const Eigen::Vector3d& q, double feed) {
          gcode::Move m;
          m.motion = kind;
          m.to = {q.x(), q.y(), q.z()};
          m.feed = feed;
          m.axes = gcode::kXYZ;
          return m;
        };
        std::vector<gcode::Move> fed, lifted;
        for (const Eigen::Vector3d& q : stay) fed.push_back(move(gcode::Motion::Line, q, p.feed_mm_min));
        fed.push_back(move(gcode::Motion::Line, start, p.feed_mm_min));
        lifted.push_back(move(gcode::Motion::Rapid, Eigen::Vector3d(prev->x(), prev->y(), lift), 0));
        lifted.push_back(move(gcode::Motion::Rapid, Eigen::Vector3d(start.x(), start.y(), lift), 0));
        if (entry(start) < lift)
          lifted.push_back(move(gcode::Motion::Rapid, Eigen::Vector3d(start.x(), start.y(), entry(start)), 0));
        lifted.push_back(move(gcode::Motion::Line, start, p.plunge_feed_mm_min));
        const gcode::Point3 from{prev->x(), prev->y(), prev->z()};
        stays = moves_time_s(from, fed, p.motion) <= moves_time_s(from, lifted, p.motion);
      }
      if (stays) {
        stay.push_back(start);
        link_with_hops(p, b, *prev, stay, plan);
      } else {
        b.rapid(prev->x(), prev->y(), lift, gcode::kZ);
        b.rapid(start.x(), start.y(), lift, gcode::kX | gcode::kY);
        if (entry(start) < lift) b.rapid(start.x(), start.y(), entry(start), gcode::kZ);
        b.line(start, p.plunge_feed_mm_min);
        ++plan.lifts;
      }
    }
    for (std::size_t i = 1; i < pass.points.size(); ++i) b.line(pass.points[i], p.feed_mm_min);
    prev = &pass.points.back();
  }
  b.rapid_z_abs(p.safe_z_mm);
  prog.items.emplace_back(gcode::Spindle{gcode::SpindleDir::Off, 0});
}

}  // namespace millnet::finish::detail
