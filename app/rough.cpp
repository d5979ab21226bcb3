#include "rough.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/zlevels.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/report/plots.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

pocket::Loop to_loop(const std::vector<Eigen::Vector2d>& pts, bool reverse) {
  pocket::Loop l;
  l.reserve(pts.size());
  for (const auto& p : pts) l.push_back({p.x(), p.y(), 0.0});
  if (reverse) std::reverse(l.begin(), l.end());
  return l;
}

pocket::Loop rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
}

/// Regions of one level: the stock region with every top-level material outline as an island, and
/// one region per material hole (cavity) with the outlines nested in it as islands.
std::vector<pocket::Region> level_regions(const std::vector<ingest::ContourLoop>& loops, const pocket::Loop& stock,
                                          std::size_t* islands) {
  // Containment tree: for every outer loop, the innermost hole that contains it (or none).
  std::vector<int> holder(loops.size(), -1);
  std::vector<double> hole_area(loops.size(), 0);
  std::vector<pocket::Loop> hole_loop(loops.size());  // built once, not once per outer loop
  for (std::size_t h = 0; h < loops.size(); ++h)
    if (loops[h].hole) {
      hole_area[h] = std::abs(ingest::signed_area(loops[h].pts));
      hole_loop[h] = to_loop(loops[h].pts, false);
    }
  for (std::size_t o = 0; o < loops.size(); ++o) {
    if (loops[o].hole || loops[o].pts.empty()) continue;
    const Eigen::Vector2d probe = loops[o].pts.front();
    double best = 0;
    for (std::size_t h = 0; h < loops.size(); ++h) {
      if (!loops[h].hole) continue;
      if (pocket::inside(hole_loop[h], {probe.x(), probe.y()}) && (holder[o] < 0 || hole_area[h] < best)) {
        holder[o] = static_cast<int>(h);
        best = hole_area[h];
      }
    }
  }
  std::vector<pocket::Region> out;
  pocket::Region top;
  top.boundary = stock;
  *islands = 0;
  for (std::size_t o = 0; o < loops.size(); ++o)
    if (!loops[o].hole && holder[o] < 0) {
      top.islands.push_back(to_loop(loops[o].pts, true));  // CCW outline → CW island
      ++*islands;
    }
  out.push_back(std::move(top));
  for (std::size_t h = 0; h < loops.size(); ++h) {
    if (!loops[h].hole) continue;
    pocket::Region cav;
    cav.boundary = to_loop(loops[h].pts, true);  // CW hole → CCW boundary
    for (std::size_t o = 0; o < loops.size(); ++o)
      if (!loops[o].hole && holder[o] == static_cast<int>(h)) {
        cav.islands.push_back(to_loop(loops[o].pts, true));
        ++*islands;
      }
    out.push_back(std::move(cav));
  }
  return out;
}

}  // namespace

RoughParams rough_params(const Json& config, const Json& explicit_pocket, const PocketFlags& flags) {
  const Json& r = config["rough"];
  RoughParams p;
  p.margin_mm = r["margin_mm"].get<double>();
  p.top_allowance_mm = r["top_allowance_mm"].get<double>();
  p.raster_mm = r["raster_mm"].get<double>();
  p.contour_tolerance_mm = r["contour_tolerance_mm"].get<double>();
  p.floor_allowance_mm = r["floor_allowance_mm"].get<double>();
  p.cut = cut_params(config, explicit_pocket, nullptr, flags);
  p.choice = planner_choice(config, p.cut, flags);
  return p;
}

RoughResult rough_mesh(const ingest::Mesh& mesh, const RoughParams& p) {
  const auto t0 = std::chrono::steady_clock::now();
  if (p.cut.step_down <= 0) throw Error("/pocket/step_down must be > 0");
  const ingest::Box3 box = ingest::bounds(mesh);
  RoughResult res;
  res.stock_x0 = box.min.x() - p.margin_mm;
  res.stock_y0 = box.min.y() - p.margin_mm;
  res.stock_x1 = box.max.x() + p.margin_mm;
  res.stock_y1 = box.max.y() + p.margin_mm;
  res.stock_top_part = box.max.z() + p.top_allowance_mm;
  // The height field covers the stock (points off the part carry z_min = the part's lowest point).
  const int nx = static_cast<int>(std::ceil((res.stock_x1 - res.stock_x0) / p.raster_mm)) + 1;
  const int ny = static_cast<int>(std::ceil((res.stock_y1 - res.stock_y0) / p.raster_mm)) + 1;
  res.field = ingest::rasterize_top(mesh, res.stock_x0, res.stock_y0, p.raster_mm, nx, ny);
  // Raster points off the part are never material (the fill z_min would make the whole stock
  // material at the floor level): below every level threshold. O(raster points).
  for (std::size_t i = 0; i < res.field.z.size(); ++i)
    if (!res.field.hit[i]) res.field.z[i] = box.min.z() - p.cut.stock_to_leave - 1.0;
  const double floor = box.min.z() + p.floor_allowance_mm;
  const double height = res.stock_top_part - floor;
  if (height <= 0) throw Error("nothing to rough: the stock top is not above the floor");
  const int n_levels = static_cast<int>(std::ceil(height / p.cut.step_down - 1e-9));
  const double dz = height / n_levels;
  const double clearance = p.cut.clearance();
  // Tool centres may pass up to one clearance outside the stock edge (the tool then just touches
  // it from the air side), so that the margin ring around the part is cleared even when the margin
  // is narrower than the clearance plus the islands' growth.
  const pocket::Loop stock = rectangle(res.stock_x0 - 2 * clearance, res.stock_y0 - 2 * clearance,
                                       res.stock_x1 + 2 * clearance, res.stock_y1 + 2 * clearance);
  std::vector<pocket::LevelPlan> plans;
  double top_z = 0;
  for (int k = 1; k <= n_levels; ++k) {
    RoughLevel lv;
    lv.z_part = res.stock_top_part - k * dz;
    lv.z = lv.z_part - res.stock_top_part;
    // The tool's flat bottom at z_part must stay stock_to_leave above the part: material is every
    // point whose surface lies above z_part − stock_to_leave.
    const auto loops = ingest::material_contours(res.field, lv.z_part - p.cut.stock_to_leave, p.contour_tolerance_mm);
    lv.regions = level_regions(loops, stock, &lv.islands);
    for (std::size_t ri = 0; ri < lv.regions.size(); ++ri) {
      auto& region = lv.regions[ri];
      try {
        (void)pocket::validate_and_normalize(region, "level Z" + fixed(lv.z, 3) + " region " + std::to_string(ri + 1));
      } catch (const Error& e) {
        throw Error(std::string("slicing produced an invalid region: ") + e.what());
      }
      pocket::PlanResult plan = plan_region(region, p.cut, p.choice);
      res.tool_points += plan.tool_points.pts.size();
      if (plan.status == pocket::PlanStatus::Ok && !plan.path.chains.empty()) {
        pocket::LevelPlan lp;
        lp.z = lv.z;
        lp.top_z = top_z;
        lp.region = region;
        lp.path = plan.path;
        lp.predrill = plan.predrill;
        plans.push_back(std::move(lp));
      } else if (ri == 0) {
        lv.status = std::string(pocket::to_string(plan.status)) + (plan.message.empty() ? "" : ": " + plan.message);
      }
      lv.plans.push_back(std::move(plan));
    }
    top_z = lv.z;
    res.levels.push_back(std::move(lv));
  }
  if (plans.empty()) {
    res.machining.status = pocket::PlanStatus::NothingToCut;
    res.machining.message = "no level has room for the tool";
  } else {
    pocket::MachiningOptions mo;
    mo.entry = p.choice.entry;
    mo.contour = false;
    mo.comments = {"roughing: stock top Z 0 = part top + " + format_double(p.top_allowance_mm) + " mm, " +
                   std::to_string(res.levels.size()) + " Z levels"};
    pocket::CutParams cut = p.cut;
    cut.depth = height;  // the program's floor: the last level
    res.machining = pocket::machine_levels(std::move(plans), cut, mo);
  }
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

Json write_rough_outputs(const fs::path& dir, const std::string& stem, const RoughResult& r, const RoughParams& p) {
  Json levels = Json::array();
  std::size_t li = 0;
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const RoughLevel& lv = r.levels[k];
    double cut = 0, tp = 0;
    std::size_t chains = 0;
    pocket::Path2D all;
    for (const auto& pl : lv.plans) {
      tp += static_cast<double>(pl.tool_points.pts.size());
      chains += pl.path.chains.size();
    }
    // The machined paths (with feeds) of this level, in program order.
    while (li < r.machining.levels.size() && std::abs(r.machining.levels[li].z - lv.z) < 1e-9) {
      for (const auto& c : r.machining.levels[li].path.chains) all.chains.push_back(c);
      ++li;
    }
    cut = all.cut_length();
    levels.push_back({{"level", k + 1},
                      {"z", lv.z},
                      {"z_part_mm", lv.z_part},
                      {"regions", lv.regions.size()},
                      {"islands", lv.islands},
                      {"tool_points", tp},
                      {"chains", chains},
                      {"retractions", chains > 0 ? chains - 1 : 0},
                      {"cut_length_mm", cut},
                      {"status", lv.status}});
    std::vector<pocket::Vec2> pts;
    for (const auto& pl : lv.plans) pts.insert(pts.end(), pl.tool_points.pts.begin(), pl.tool_points.pts.end());
    (void)report::level_png(dir / (stem + ".level_" + std::to_string(k + 1) + ".png"), lv.regions, all, lv.z,
                            stem, {{"islands", std::to_string(lv.islands)}, {"cut", fixed(cut, 0) + " mm"},
                                   {"chains", std::to_string(chains)}});
  }
  Json j = Json::object();
  j["status"] = pocket::to_string(r.machining.status);
  if (!r.machining.message.empty()) j["message"] = r.machining.message;
  j["planner"] = p.choice.name;
  j["stock_top_above_part_mm"] = p.top_allowance_mm;
  j["stock_to_leave_mm"] = p.cut.stock_to_leave;
  j["stock"] = {{"x0", r.stock_x0}, {"y0", r.stock_y0}, {"x1", r.stock_x1}, {"y1", r.stock_y1},
                {"height_mm", r.stock_top_part}};
  j["raster_mm"] = p.raster_mm;
  j["contour_tolerance_mm"] = p.contour_tolerance_mm;
  j["tool_points"] = r.tool_points;
  j["planning_time_s"] = r.planning_time_s;
  for (const auto& [k, v] : r.machining.metrics.to_key_values())
    if (!j.contains(k)) j[k] = v;
  j["levels"] = r.levels.size();
  j["per_level"] = levels;
  j["parameters"] = cut_json(p.cut);
  if (r.machining.status == pocket::PlanStatus::Ok) write_file_atomic(dir / (stem + ".nc"), r.machining.gcode);
  write_file_atomic(dir / (stem + ".metrics.json"), j.dump(2) + "\n");
  return j;
}

}  // namespace millnet::app
