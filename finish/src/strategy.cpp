// The strategy registry and the top function: passes by the strategy, simplified, linked.
#include "boundary.hpp"
#include "sampling.hpp"

#include "millnet/core/error.hpp"
#include "millnet/finish/tolerances.hpp"
#include "millnet/finish/work.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>
#include <cmath>
#include <string>

namespace millnet::finish {
namespace {

using detail::Box;
using detail::Sample;
using detail::Sampler;
using Lines = std::vector<std::vector<Sample>>;

using Levels = std::vector<std::vector<std::vector<Sample>>>;

/// Pieces that several strategies share, computed once per plan_finish call: the fixed-spacing
/// raster lines (2 and the shallow part of 1) and the Z-level loops (4 and the steep part of 1).
/// Each strategy plans with its own parameters (`p`, set before its passes are made); a piece is
/// reused only when the parameters it depends on are the same (raster: stepover, angle, chord
/// tolerance; Z-levels: step-down, chord tolerance), else it is computed anew and kept.
struct Shared {
  const Sampler& s;
  const Box& box;
  const FinishParams* p = nullptr;
  template <class Piece>
  struct Cached {
    std::vector<double> key;
    Piece piece;
    std::size_t drops = 0;  ///< what it cost when it was computed
  };
  std::vector<Cached<Lines>> rasters;
  std::vector<Cached<Levels>> levels;
  std::size_t reused_drops = 0;  ///< the current plan's: pieces it used that an earlier plan paid for
  template <class Piece, class Make>
  const Piece& cached(std::vector<Cached<Piece>>& cache, std::vector<double> key, Make make) {
    for (const Cached<Piece>& c : cache)  // O(strategies)
      if (c.key == key) {
        reused_drops += c.drops;
        return c.piece;
      }
    const std::size_t d0 = s.drops();
    Piece piece = make();
    cache.push_back({std::move(key), std::move(piece), s.drops() - d0});
    return cache.back().piece;
  }
  const Lines& raster_lines() {
    return cached(rasters, {p->stepover_mm, p->raster_angle_deg, p->chord_tolerance_mm},
                  [&] { return detail::raster_lines(s, box, *p, false); });
  }
  const Levels& waterline_loops() {
    return cached(levels, {p->step_down_mm, p->chord_tolerance_mm},
                  [&] { return detail::waterline_loops(s, box, *p); });
  }
};

/// The box cut down to the polygons' box (they may reach beyond the part: the box stays the part's
/// where they do). Throws when they miss it.
/// The XY box of the selected triangles that are not vertical, as a rectangle (the planning area of
/// a boundary made of faces). Throws millnet::Error when every selected triangle is vertical. O(F).
std::vector<Eigen::Vector2d> selection_outline(const ingest::Mesh& mesh, const Boundary& b) {
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  std::size_t selected = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (static_cast<std::size_t>(f) >= b.triangles.size() || !b.triangles[static_cast<std::size_t>(f)]) continue;
    ++selected;
    const Eigen::Vector3d p = mesh.V.row(mesh.F(f, 0)), q = mesh.V.row(mesh.F(f, 1)), r = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d n = (q - p).cross(r - p);
    if (!(std::abs(n.z()) > 1e-9 * n.norm())) continue;  // vertical: nothing over it
    for (const Eigen::Vector3d* v : {&p, &q, &r}) {
      x0 = std::min(x0, v->x()), y0 = std::min(y0, v->y());
      x1 = std::max(x1, v->x()), y1 = std::max(y1, v->y());
    }
  }
  if (!(x1 >= x0))
    throw Error("finish: the machining boundary's " + std::to_string(selected) +
                " selected triangles are all vertical: nothing of them is machined from above");
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

Box within_polygons(const Box& box, const std::vector<std::vector<Eigen::Vector2d>>& polygons) {
  Box b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& poly : polygons)  // O(polygon points)
    for (const Eigen::Vector2d& q : poly) {
      b.x0 = std::min(b.x0, q.x()), b.y0 = std::min(b.y0, q.y());
      b.x1 = std::max(b.x1, q.x()), b.y1 = std::max(b.y1, q.y());
    }
  const Box out{std::max(box.x0, b.x0), std::max(box.y0, b.y0), std::min(box.x1, b.x1), std::min(box.y1, b.y1)};
  if (!(out.x1 > out.x0 && out.y1 > out.y0))
    throw Error("finish: the machining boundary (X " + std::to_string(b.x0) + ".." + std::to_string(b.x1) + ", Y " +
                std::to_string(b.y0) + ".." + std::to_string(b.y1) + ") lies off the part (X " +
                std::to_string(box.x0) + ".." + std::to_string(box.x1) + ", Y " + std::to_string(box.y0) + ".." +
                std::to_string(box.y1) + ")");
  return out;
}

Lines raster(Shared& sh) { return sh.raster_lines(); }

Lines scallop_mode(Shared& sh) { return detail::raster_lines(sh.s, sh.box, *sh.p, true); }

double near_mm(const FinishParams& p) { return p.tool.diameter + 4 * p.stepover_mm; }

Lines waterline(Shared& sh) { return detail::order_by_level(sh.waterline_loops(), near_mm(*sh.p)); }

Lines equidistant(Shared& sh) {
  return detail::order_by_level(detail::equidistant_loops(sh.s, sh.box, *sh.p), near_mm(*sh.p));
}

/// Steep pieces of the Z-levels first (top-down per island), then the shallow runs of the raster.
Lines slope_mode(Shared& sh) {
  const FinishParams& p = *sh.p;
  const double shallow_to = p.boundary_angle_deg + tol::slope_overlap_deg;
  Lines out = detail::order_by_level(detail::steep_pieces(sh.waterline_loops(), p), near_mm(p));
  for (const auto& line : sh.raster_lines())
    for (auto& r : detail::runs(line, [&](const Sample& q) { return q.slope_deg < shallow_to; }))
      out.push_back(std::move(r));
  return out;
}

}  // namespace

namespace detail {

std::vector<std::vector<std::vector<Sample>>> steep_pieces(std::vector<std::vector<std::vector<Sample>>> levels,
                                                           const FinishParams& p) {
  const double steep_from = p.boundary_angle_deg - tol::slope_overlap_deg;
  for (auto& level : levels) {
    std::vector<std::vector<Sample>> kept;
    for (auto& loop : level) {
      if (std::all_of(loop.begin(), loop.end(), [&](const Sample& q) { return q.slope_deg >= steep_from; })) {
        kept.push_back(std::move(loop));
        continue;
      }
      if (detail::is_closed(loop)) {  // start the ring at a shallow point so pieces do not wrap
        const auto it =
            std::find_if(loop.begin(), loop.end(), [&](const Sample& q) { return q.slope_deg < steep_from; });
        loop.pop_back();
        std::rotate(loop.begin(), loop.begin() + (it - loop.begin()), loop.end());
        loop.push_back(loop.front());
      }
      for (auto& r : detail::runs(loop, [&](const Sample& q) { return q.slope_deg >= steep_from; }))
        kept.push_back(std::move(r));
    }
    level = std::move(kept);
  }
  return levels;
}

}  // namespace detail

namespace {

struct Entry {
  Strategy id;
  const char* name;
  Lines (*passes)(Shared&);
  bool straight_passes;  ///< every pass lies on a straight XY line (simplify in Z only)
  unsigned sampling;     ///< the CL grids it samples (Sampling bits): its work estimate
};

/// The registry: a new strategy is one function above and one line here (slots 6–8 are free; its
/// id may be Strategy{6} until it earns an enumerator), and its slot in the schema's /finish/strategy.
constexpr auto kRegistry = std::to_array<Entry>({
    {Strategy::SlopeMode, "profile + Z finishing, slope mode", slope_mode, false, kRasterSampling | kWaterlineSampling},
    {Strategy::Raster, "3D finishing (parallel)", raster, true, kRasterSampling},
    {Strategy::ScallopMode, "profile finishing, scallop-height mode", scallop_mode, true, kScallopSampling},
    {Strategy::Waterline, "Z-level finishing", waterline, false, kWaterlineSampling},
    {Strategy::Equidistant, "profile finishing, equidistant, constant in-feed", equidistant, false,
     kEquidistantSampling},
});

const Entry& entry(Strategy s) {
  for (const Entry& e : kRegistry)
    if (e.id == s) return e;
  throw Error("unknown finishing strategy " + std::to_string(static_cast<int>(s)));
}

void require(bool ok, const std::string& key, const std::string& what) {
  if (!ok) throw Error("finish: " + key + " " + what);
}

}  // namespace

const std::vector<StrategyInfo>& strategy_registry() {
  static const std::vector<StrategyInfo> kInfo = [] {
    std::vector<StrategyInfo> v;
    for (const Entry& e : kRegistry) v.push_back({e.id, e.name, e.sampling});
    return v;
  }();
  return kInfo;
}

std::vector<std::string> strategy_choices() {
  std::vector<std::string> c;
  for (const Entry& e : kRegistry) c.push_back(std::to_string(static_cast<int>(e.id)));
  c.emplace_back("all");
  return c;
}

Strategy parse_strategy(std::string_view s) {
  for (const Entry& e : kRegistry)
    if (s == std::to_string(static_cast<int>(e.id))) return e.id;
  std::string slots;
  for (const Entry& e : kRegistry)
    slots += (slots.empty()                 ? ""
              : e.id == kRegistry.back().id ? " or "
                                            : ", ") +
             std::to_string(static_cast<int>(e.id));
  throw Error("unknown finishing strategy '" + std::string(s.substr(0, 40)) + "' (expected " + slots + ")");
}

std::string strategy_name(Strategy s) {
  const Entry& e = entry(s);
  return std::to_string(static_cast<int>(e.id)) + " " + e.name;
}

std::vector<Strategy> all_strategies() {
  std::vector<Strategy> out;
  for (const Entry& e : kRegistry) out.push_back(e.id);
  return out;
}

void FinishParams::check() const {
  check_finishing_cutter(tool);
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  require(positive(stepover_mm), "stepover_mm", "must be > 0 (got " + std::to_string(stepover_mm) + ")");
  require(positive(step_down_mm), "step_down_mm", "must be > 0 (got " + std::to_string(step_down_mm) + ")");
  require(positive(chord_tolerance_mm), "chord_tolerance_mm", "must be > 0");
  require(positive(scallop_mm), "scallop_mm", "must be > 0");
  require(std::isfinite(boundary_angle_deg) && boundary_angle_deg > 0 && boundary_angle_deg < 90, "boundary_angle_deg",
          "must be in (0, 90)");
  require(std::isfinite(raster_angle_deg), "raster_angle_deg", "must be finite");
  require(positive(feed_mm_min), "feed_mm_min", "must be > 0");
  require(positive(plunge_feed_mm_min), "plunge_feed_mm_min", "must be > 0");
  require(positive(spindle_rpm), "spindle_rpm", "must be > 0");
  require(positive(clearance_mm), "clearance_mm", "must be > 0");
  require(std::isfinite(safe_z_mm) && std::isfinite(z_shift), "safe_z_mm", "must be finite");
}

std::vector<FinishPlan> plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper,
                                    const std::vector<Strategy>& strategies, const FinishParams& params) {
  return plan_finish(mesh, dropper, strategies, std::vector<FinishParams>(strategies.size(), params));
}

std::vector<FinishPlan> plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper,
                                    const std::vector<Strategy>& strategies,
                                    const std::vector<FinishParams>& params_each) {
  if (params_each.size() != strategies.size())
    throw Error("finish: " + std::to_string(params_each.size()) + " parameter sets for " +
                std::to_string(strategies.size()) + " strategies");
  if (strategies.empty()) return {};
  for (const FinishParams& p : params_each) p.check();
  for (const Strategy st : strategies) (void)entry(st);
  const FinishParams& params = params_each.front();  // what every strategy's parameters share
  // The part is machined from above: it needs a face that looks up (n_z > 0). O(#F).
  bool faces_up = false;
  for (Eigen::Index f = 0; f < mesh.F.rows() && !faces_up; ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    faces_up = n.z() > 1e-9 * n.norm();
  }
  if (!faces_up)
    throw Error("finish: the mesh has no top surface: none of its " + std::to_string(mesh.F.rows()) +
                " faces looks up (is --up right?)");
  const Sampler s(mesh, dropper);
  Box box{params.x0, params.y0, params.x1, params.y1};
  if (!(box.x1 > box.x0 && box.y1 > box.y0)) {
    box = {mesh.V.col(0).minCoeff(), mesh.V.col(1).minCoeff(), mesh.V.col(0).maxCoeff(), mesh.V.col(1).maxCoeff()};
  }
  const detail::Fence fence(mesh, params.boundary);
  if (!params.boundary.polygons.empty()) box = within_polygons(box, params.boundary.polygons);
  if (!params.boundary.triangles.empty()) box = within_polygons(box, {selection_outline(mesh, params.boundary)});
  for (std::size_t i = 0; i < strategies.size(); ++i)  // before any CL point is dropped (issue 12)
    for (const WorkEstimate& e : estimate_work(box.x0, box.y0, box.x1, box.y1, {strategies[i]}, params_each[i]))
      check_work(e, params.limits);
  if (std::min(box.x1 - box.x0, box.y1 - box.y0) < params.tool.diameter)
    throw Error("finish: the tool (" + params.tool.describe() + ") is larger than the machining boundary (" +
                std::to_string(box.x1 - box.x0) + " × " + std::to_string(box.y1 - box.y0) + " mm)");
  if (!(s.top_z() + params.z_shift + params.clearance_mm <= params.safe_z_mm))
    throw Error("finish: safe_z_mm " + std::to_string(params.safe_z_mm) +
                " is not above the part top plus the clearance (" +
                std::to_string(s.top_z() + params.z_shift + params.clearance_mm) + ")");
  Shared shared{s, box, nullptr, {}, {}, 0};
  std::vector<FinishPlan> plans;
  for (std::size_t i = 0; i < strategies.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t drops0 = s.drops();
    const FinishParams& p = params_each[i];
    shared.p = &p;
    shared.reused_drops = 0;
    const Entry& e = entry(strategies[i]);
    FinishPlan plan;
    plan.strategy = strategies[i];
    Lines lines = fence.clip(e.passes(shared));
    std::vector<Lines::value_type> simple(lines.size());
#pragma omp parallel for schedule(dynamic, 4)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lines.size()); ++k)
      simple[static_cast<std::size_t>(k)] =
          detail::simplify(lines[static_cast<std::size_t>(k)], p.chord_tolerance_mm, e.straight_passes);
    plan.passes = detail::to_passes(std::move(simple));
    if (plan.passes.empty()) throw Error("finish: no surface under the machining boundary to finish");
    detail::link_passes(s, p, fence, plan);
    plan.drops = s.drops() - drops0;
    plan.drops_needed = plan.drops + shared.reused_drops;
    plan.planning_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    plans.push_back(std::move(plan));
  }
  return plans;
}

FinishPlan plan_finish(const ingest::Mesh& mesh, const DropCutter& dropper, Strategy strategy,
                       const FinishParams& params) {
  return std::move(plan_finish(mesh, dropper, std::vector{strategy}, params).front());
}

}  // namespace millnet::finish
