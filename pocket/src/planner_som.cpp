#include "millnet/pocket/planner_som.hpp"

#include "millnet/core/error.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

namespace millnet::pocket {

PlanResult plan_som(const Region& region, const CutParams& cut, const GridFrame& frame, const SomParams& som,
                    const SmoothingParams& smooth) {
  const auto t0 = std::chrono::steady_clock::now();
  cut.check("plan_som");
  PlanResult res;
  res.planner = "som";
  const double clearance = cut.clearance();
  res.tool_points = make_tool_points(region, frame, clearance);  // O(grid cells)
  const ToolPoints& tp = res.tool_points;
  const std::size_t n = tp.pts.size();
  if (n == 0) {
    std::ostringstream msg;
    msg << "no tool point fits: no grid point (spacing " << frame.spacing << " mm) keeps the tool disk (radius "
        << clearance << " mm incl. stock to leave) inside the pocket";
    res.status = PlanStatus::NoToolPoints;
    res.message = msg.str();
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  const Clearance clear(region, clearance);
  const MoveOk move_ok = [&clear](const Vec2& p, const Vec2& q) { return clear.move_ok(p, q); };

  const SomResult ring = som_tour(tp.pts, som);
  SmoothedTour sm = smooth_tour(tp, ring.order, move_ok, smooth);

  for (const auto& ch : sm.chains) {  // O(path vertices)
    Chain c;
    for (int k : ch) {
      const Vec2& p = tp.pts[static_cast<std::size_t>(k)];
      c.pts.push_back(Vertex{p.x(), p.y(), 0.0});
    }
    c.predrill = true;
    c.role = "cut";
    res.predrill.push_back(c.pts.front().p());
    res.path.chains.push_back(std::move(c));
  }
  SomStats st;
  st.tool_points = n;
  st.som_passes = ring.passes;
  st.som_converged = ring.converged;
  st.som_nodes = ring.nodes;
  st.smoothing = sm.stats;
  st.cut_length_mm = res.path.cut_length();
  st.rapid_length_mm = res.path.rapid_length();
  st.retractions = res.path.retractions();
  st.predrill_points = res.predrill.size();
  st.grid_bound_mm = (static_cast<double>(n) - 1) * frame.spacing;
  st.cut_over_bound = st.grid_bound_mm > 0 ? st.cut_length_mm / st.grid_bound_mm : 1.0;
  res.stats = st;
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace millnet::pocket
