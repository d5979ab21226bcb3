// Rapids over the stock that is left (links.hpp).
#include "millnet/job/links.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

namespace millnet::job {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

/// The stock max-pooled onto coarse cells: a cell's height is the highest of the z-map cells in it.
class PooledStock {
public:
  PooledStock(const simulate::ZMap& stock) {  // O(cells)
    const simulate::GridSpec& g = stock.spec();
    k_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::floor(kLinkCellMm / g.cell)));
    edge_ = static_cast<double>(k_) * g.cell;
    x0_ = g.x0, y0_ = g.y0;
    nx_ = (g.nx + k_ - 1) / k_, ny_ = (g.ny + k_ - 1) / k_;
    z_.assign(nx_ * ny_, kNone);
    for (std::size_t iy = 0; iy < g.ny; ++iy)
      for (std::size_t ix = 0; ix < g.nx; ++ix) {
        double& p = z_[(iy / k_) * nx_ + ix / k_];
        p = std::max(p, stock.at(ix, iy));
      }
  }

  /// The highest stock under a disk of radius r swept from a to b (XY); −inf where the stock is
  /// not known. A coarse cell counts when its centre lies within r + half its diagonal of the
  /// segment (so every z-map cell the disk covers is in one that counts).
  [[nodiscard]] double under(double ax, double ay, double bx, double by, double r) const {
    const double reach = r + edge_ * std::sqrt(0.5);
    const auto lo = [&](double v, double o, std::size_t n) {
      return static_cast<std::size_t>(std::clamp(std::floor((v - o) / edge_), 0.0, static_cast<double>(n)));
    };
    const auto hi = [&](double v, double o, std::size_t n) {
      return static_cast<std::size_t>(std::clamp(std::floor((v - o) / edge_) + 1, 0.0, static_cast<double>(n)));
    };
    const std::size_t px0 = lo(std::min(ax, bx) - reach, x0_, nx_), px1 = hi(std::max(ax, bx) + reach, x0_, nx_);
    const std::size_t py0 = lo(std::min(ay, by) - reach, y0_, ny_), py1 = hi(std::max(ay, by) + reach, y0_, ny_);
    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
    double h = kNone;
    for (std::size_t py = py0; py < py1; ++py)
      for (std::size_t px = px0; px < px1; ++px) {
        const double z = z_[py * nx_ + px];
        if (z <= h) continue;
        const double cx = x0_ + (static_cast<double>(px) + 0.5) * edge_,
                     cy = y0_ + (static_cast<double>(py) + 0.5) * edge_;
        const double t = l2 > 0 ? std::clamp(((cx - ax) * dx + (cy - ay) * dy) / l2, 0.0, 1.0) : 0.0;
        if (std::hypot(cx - (ax + t * dx), cy - (ay + t * dy)) <= reach) h = z;
      }
    return h;
  }

private:
  std::size_t k_ = 1, nx_ = 0, ny_ = 0;
  double edge_ = kLinkCellMm, x0_ = 0, y0_ = 0;
  std::vector<double> z_;
};

gcode::Move rapid_to(double x, double y, double z, std::uint8_t axes, std::uint8_t op) {
  gcode::Move m;
  m.motion = gcode::Motion::Rapid;
  m.to = {x, y, z};
  m.axes = axes;
  m.op = op;
  return m;
}

}  // namespace

gcode::Program clear_rapids(const gcode::Program& program, const simulate::ZMap& stock, const tooling::Cutter& cutter,
                            double clearance_mm, double plunge_feed_mm_min, LinkChanges* changes) {
  const PooledStock pooled(stock);
  const double r = cutter.radius();
  LinkChanges ch;
  gcode::Program out = program;
  out.items.clear();
  out.source_line.clear();  // the items change: their lines are the written program's
  bool xy_known = false, z_known = false;
  gcode::Point3 at{0, 0, 0};
  // A rapid straight down from `top` to `to`: to the clearance over the stock under the tool, then at the plunge feed.
  const auto descend = [&](double top, const gcode::Move& to) {
    const double safe = pooled.under(to.to[0], to.to[1], to.to[0], to.to[1], r) + clearance_mm;
    if (to.to[2] >= safe) {
      out.items.emplace_back(to);
      return;
    }
    if (top > safe) out.items.emplace_back(rapid_to(to.to[0], to.to[1], safe, gcode::kZ, to.op));
    gcode::Move feed = to;
    feed.motion = gcode::Motion::Line;
    feed.feed = plunge_feed_mm_min;
    out.items.emplace_back(feed);
    ++ch.fed;
  };
  for (const gcode::Item& item : program.items) {  // O(items), each rapid O(its coarse cells)
    const auto* m = std::get_if<gcode::Move>(&item);
    if (m == nullptr) {
      out.items.push_back(item);
      continue;
    }
    const bool known = xy_known && z_known;
    const gcode::Point3 from = at;
    for (std::size_t a = 0; a < 3; ++a)  // the stated axes (an unstated one keeps its value)
      if ((m->axes & (1U << a)) != 0 ||
          (m->motion != gcode::Motion::Rapid && m->motion != gcode::Motion::Line && a < 2))
        at[a] = m->to[a];
    xy_known = xy_known || ((m->axes & gcode::kX) && (m->axes & gcode::kY));
    z_known = z_known || (m->axes & gcode::kZ);
    if (m->motion != gcode::Motion::Rapid || !known) {
      out.items.push_back(item);
      continue;
    }
    gcode::Move target = *m;
    target.to = at;
    const bool vertical = from[0] == target.to[0] && from[1] == target.to[1];
    if (vertical) {
      if (target.to[2] >= from[2])
        out.items.push_back(item);  // up: nothing to hit
      else
        descend(from[2], target);
      continue;
    }
    const double h = pooled.under(from[0], from[1], target.to[0], target.to[1], r) + clearance_mm;
    if (std::min(from[2], target.to[2]) >= h) {
      out.items.push_back(item);
      continue;
    }
    const double top = std::max({from[2], target.to[2], h});
    if (top > from[2]) out.items.emplace_back(rapid_to(from[0], from[1], top, gcode::kZ, target.op));
    out.items.emplace_back(rapid_to(target.to[0], target.to[1], top, gcode::kX | gcode::kY, target.op));
    if (target.to[2] < top) descend(top, target);
    ++ch.raised;
  }
  if (changes) *changes = ch;
  return out;
}

}  // namespace millnet::job
