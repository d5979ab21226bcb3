#include "millnet/rough/rough.hpp"

#include "millnet/pocket/work.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/pocket/gcode.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace millnet::rough {

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

std::string fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

/// The stock and its slicing height field; raster points off the part are set below every level's
/// cut-off (the fill z_min would make the whole stock material at the floor level). O(raster points).
void make_stock(const ingest::Mesh& mesh, const ingest::Box3& box, const Params& p, Result& res) {
  const std::array<double, 4> m = p.stock.sides(box.max.x() - box.min.x(), box.max.y() - box.min.y());
  res.stock_x0 = box.min.x() - m[0];
  res.stock_x1 = box.max.x() + m[1];
  res.stock_y0 = box.min.y() - m[2];
  res.stock_y1 = box.max.y() + m[3];
  res.part_x0 = box.min.x(), res.part_y0 = box.min.y(), res.part_x1 = box.max.x(), res.part_y1 = box.max.y();
  res.stock_top_part = box.max.z() + p.top_allowance_mm;
  // The height field covers the stock (points off the part carry z_min = the part's lowest point).
  check_work(ingest::raster_work(res.stock_x1 - res.stock_x0, res.stock_y1 - res.stock_y0, p.raster_mm, "stock"),
             p.limits);
  const int nx = static_cast<int>(std::ceil((res.stock_x1 - res.stock_x0) / p.raster_mm)) + 1;
  const int ny = static_cast<int>(std::ceil((res.stock_y1 - res.stock_y0) / p.raster_mm)) + 1;
  res.field = ingest::rasterize_top_cells(mesh, res.stock_x0, res.stock_y0, p.raster_mm, nx, ny);
  for (std::size_t i = 0; i < res.field.z.size(); ++i)
    if (!res.field.hit[i]) res.field.z[i] = box.min.z() - p.cut.stock_to_leave - 1.0;
}

/// Keeps the regions that hold one of the points (inside the boundary, outside every island).
/// O(regions · points · region vertices).
void keep_regions_holding(std::vector<pocket::Region>& regions, const std::vector<Eigen::Vector2d>& points) {
  std::erase_if(regions, [&](const pocket::Region& r) {
    return std::none_of(points.begin(), points.end(), [&](const Eigen::Vector2d& q) { return pocket::inside(r, q); });
  });
}

/// The given stock less what the finishing is left (Result::stock_left): a point whose stock top
/// lies within stock_to_leave + kStockSkinMm of the part's highest point within stock_to_leave +
/// one raster step of it goes below every level. O(points · (r / raster)²).
ingest::HeightField stock_left(const ingest::HeightField& top, const ingest::HeightField& part, const Params& p,
                               double below_all, std::vector<double>& near_out) {
  if (top.nx != part.nx || top.ny != part.ny || top.x0 != part.x0 || top.y0 != part.y0 || top.step_x != part.step_x)
    throw Error("roughing: the given stock's raster (" + std::to_string(top.nx) + " × " + std::to_string(top.ny) +
                ") is not the slicing raster (" + std::to_string(part.nx) + " × " + std::to_string(part.ny) + ")");
  ingest::HeightField left = top;
  near_out.assign(left.z.size(), below_all);
  // What the roughing from the block leaves along a wall: the stock to leave, the slicing's outline
  // grown to the raster (a raster step's diagonal at a corner) and its contour tolerance.
  const double r = p.cut.stock_to_leave + std::sqrt(2.0) * p.raster_mm + p.contour_tolerance_mm;
  const int k = static_cast<int>(std::ceil(r / p.raster_mm));
  const double r2 = (r + 1e-9) * (r + 1e-9);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < part.ny; ++i)
    for (int j = 0; j < part.nx; ++j) {
      double near = -std::numeric_limits<double>::infinity();  // the part's top within r
      for (int di = -k; di <= k; ++di)
        for (int dj = -k; dj <= k; ++dj) {
          const int ii = i + di, jj = j + dj;
          if (ii < 0 || jj < 0 || ii >= part.ny || jj >= part.nx) continue;
          const double dx = dj * p.raster_mm, dy = di * p.raster_mm;
          if (dx * dx + dy * dy <= r2) near = std::max(near, part.at(ii, jj));
        }
      const std::size_t at =
          static_cast<std::size_t>(i) * static_cast<std::size_t>(part.nx) + static_cast<std::size_t>(j);
      near_out[at] = near;
      if (left.z[at] <= near + p.cut.stock_to_leave + kStockSkinMm) left.z[at] = below_all;
    }
  left.z_min = std::min(left.z_min, below_all);
  return left;
}

/// Where a given stock holds material at a level: its outlines (stock top ≥ z + kStockSkinMm) grown
/// by the tool's clearance + kStockReachMm (the tool's edge reaches every bit of it), as areas
/// (outer loops with their holes).
std::vector<pocket::PolyArea> stock_material(const ingest::HeightField& top, double z_part, const Params& p) {
  const std::vector<ingest::ContourLoop> loops =
      ingest::material_contours(top, z_part + kStockSkinMm, p.cut.clearance() + kStockReachMm);
  std::vector<pocket::PolyArea> out;
  std::vector<int> area_of(loops.size(), -1);
  for (std::size_t k = 0; k < loops.size(); ++k)  // outer loops first, then their holes
    if (!loops[k].hole) {
      area_of[k] = static_cast<int>(out.size());
      out.push_back({{loops[k].pts.begin(), loops[k].pts.end()}, {}});
    }
  for (const ingest::ContourLoop& l : loops)
    if (l.hole && l.parent >= 0 && area_of[static_cast<std::size_t>(l.parent)] >= 0)
      out[static_cast<std::size_t>(area_of[static_cast<std::size_t>(l.parent)])].holes.emplace_back(l.pts.begin(),
                                                                                                    l.pts.end());
  return out;
}

std::vector<const pocket::Loop*> loops_of(const pocket::Region& r) {
  std::vector<const pocket::Loop*> out{&r.boundary};
  for (const pocket::Loop& l : r.islands) out.push_back(&l);
  return out;
}

/// The level's regions cut to where the stock holds material (Params::stock_top).
std::vector<pocket::Region> within_stock(const std::vector<pocket::Region>& regions,
                                         const std::vector<pocket::PolyArea>& material, const Result& res) {
  std::vector<pocket::Region> out;
  if (material.empty()) return out;
  // A piece with no vertex inside the block's outline is the margin ring alone: air.
  const auto inside_block = [&](const pocket::Region& r) {
    for (const pocket::Loop* l : loops_of(r))
      for (const pocket::Vertex& v : *l)
        if (v.x > res.stock_x0 + 1e-6 && v.x < res.stock_x1 - 1e-6 && v.y > res.stock_y0 + 1e-6 &&
            v.y < res.stock_y1 - 1e-6)
          return true;
    return false;
  };
  for (const pocket::Region& r : regions) {  // O(regions · Clipper)
    std::vector<pocket::Region> pieces = pocket::intersect(r, material);
    // Wholly within the stock: the region as it was, not its copy on Clipper's integer grid (whose
    // rounding moves the area by at most the perimeter × the grid).
    double perimeter = 0;
    for (const pocket::Loop* l : loops_of(r))
      for (std::size_t k = 0; k < l->size(); ++k) perimeter += ((*l)[(k + 1) % l->size()].p() - (*l)[k].p()).norm();
    if (pieces.size() == 1 && std::abs(pocket::area(pieces[0]) - pocket::area(r)) <=
                                  2 * pocket::tol::clipper_resolution_mm * perimeter + 1e-9) {
      out.push_back(r);
      continue;
    }
    for (pocket::Region& piece : pieces)
      if (inside_block(piece)) out.push_back(std::move(piece));
  }
  return out;
}

/// Slices and plans one level (a flat's level: only its regions that hold the flat, when `flat`).
Level plan_level(const Result& res, const Params& p, const pocket::Loop& stock, double z_part, double top_z,
                 const Flat* flat, std::vector<pocket::LevelPlan>& plans, std::size_t& tool_points) {
  Level lv;
  lv.z_part = z_part;
  lv.z = lv.z_part - res.stock_top_part;
  // The tool's flat bottom at z_part must stay stock_to_leave above the part: material is every
  // point whose surface lies above z_part − stock_to_leave.
  const auto loops = ingest::material_contours(res.field, lv.z_part - p.cut.stock_to_leave, p.contour_tolerance_mm);
  lv.regions = level_regions(loops, stock, &lv.islands);
  if (flat != nullptr) keep_regions_holding(lv.regions, flat->samples);
  if (p.stock_top) {
    // Where the stock holds material, and beyond the block's outline the margin ring the block's
    // regions have (the tool may pass there as it does around the block).
    // The stock a tool at this level can reach: not within the stock to leave (+ a raster step) of
    // the part's section here (its island, grown as the planner keeps the tool off it).
    ingest::HeightField here = res.stock_left;
    for (std::size_t k = 0; k < here.z.size(); ++k)  // O(points)
      if (res.stock_part_near[k] >= lv.z_part - p.cut.stock_to_leave) here.z[k] = here.z_min;
    std::vector<pocket::PolyArea> keep = stock_material(here, lv.z_part, p);
    const double c = 2 * p.cut.clearance();
    if (!keep.empty())
      keep.push_back({{{res.stock_x0 - c, res.stock_y0 - c},
                       {res.stock_x1 + c, res.stock_y0 - c},
                       {res.stock_x1 + c, res.stock_y1 + c},
                       {res.stock_x0 - c, res.stock_y1 + c}},
                      {{{res.stock_x0, res.stock_y0},
                        {res.stock_x0, res.stock_y1},
                        {res.stock_x1, res.stock_y1},
                        {res.stock_x1, res.stock_y0}}}});
    lv.regions = within_stock(lv.regions, keep, res);
  }
  for (std::size_t ri = 0; ri < lv.regions.size(); ++ri) {
    auto& region = lv.regions[ri];
    try {
      (void)pocket::validate_and_normalize(region, "level Z" + fixed(lv.z, 3) + " region " + std::to_string(ri + 1));
    } catch (const Error& e) {
      throw Error(std::string("slicing produced an invalid region: ") + e.what());
    }
    pocket::check_work(region, p.cut, p.planner, p.limits);
    pocket::PlanResult plan = pocket::plan(region, p.cut, p.planner);
    tool_points += plan.tool_points.pts.size();
    if (plan.status == pocket::PlanStatus::Ok && !plan.path.chains.empty()) {
      // The wall pass on every loop, the stock's outline included (until 2026-11-25 loops starting
      // near the outline were skipped as "in the air", but a planner without its own wall pass
      // leaves wedges along it: zigzag 120–310 mm² per level on the default test parts), and the
      // chains joined through cut material.
      pocket::complete_path(region, p.cut, plan, p.machining, plan.path, plan.predrill);
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
  return lv;
}

/// Every level plans within the stock's outline (its regions are that rectangle less the part's
/// section, or cavities inside it) and every level's plan is kept: the levels × the estimates of the
/// whole outline bound the run, checked before the first level (issue 42 §7: --step-down 0.01
/// planned 2,700 levels, each within its own estimate; the SOM at stepover 0.05 too).
void check_levels_work(const pocket::Loop& stock, std::int64_t n_levels, std::size_t flats, double height,
                       const Params& p) {
  const double levels = static_cast<double>(n_levels);
  pocket::Region outline;
  outline.boundary = stock;
  for (WorkEstimate e : pocket::estimate_work(outline, p.cut, p.planner)) {
    e.cause = std::to_string(n_levels) + " Z levels (step_down " + format_size(p.cut.step_down) + " mm over " +
              format_size(height) + " mm of stock" +
              (flats == 1  ? ", 1 at a flat area"
               : flats > 1 ? ", " + std::to_string(flats) + " at flat areas"
                           : "") +
              ") × " + e.cause;
    e.count *= levels;
    e.bytes *= levels;
    check_work(e, p.limits);
  }
}

/// The levels' heights (part frame), highest first: the even split of the stock's height at ≤
/// step_down, then a level per flat that no level keeps within kFlatToleranceMm (flat_z[k]: the
/// flat of level k, NaN for a step-down level). O(levels · flats).
std::vector<double> level_heights(const Result& res, double floor, std::int64_t n_levels,
                                  const std::vector<Flat>& flats, double stock_to_leave, std::vector<double>& flat_z) {
  const double dz = (res.stock_top_part - floor) / static_cast<double>(n_levels);
  std::vector<std::pair<double, double>> zs;  // (level, flat or NaN)
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::int64_t k = 1; k <= n_levels; ++k) zs.emplace_back(res.stock_top_part - static_cast<double>(k) * dz, nan);
  for (const Flat& f : flats) {
    const double z = f.z + stock_to_leave + kFlatClearanceMm;
    if (z <= floor || z >= res.stock_top_part) continue;
    // A level cuts the flat when it lies above the flat + stock to leave; within the tolerance of that it keeps it.
    const bool kept = std::any_of(zs.begin(), zs.end(), [&](const auto& l) {
      return l.first > f.z + stock_to_leave && l.first <= f.z + stock_to_leave + kFlatToleranceMm;
    });
    if (!kept) zs.emplace_back(z, f.z);
  }
  std::sort(zs.begin(), zs.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<double> out;
  flat_z.clear();
  for (const auto& [z, fz] : zs) {
    out.push_back(z);
    flat_z.push_back(fz);
  }
  return out;
}

}  // namespace

std::vector<Flat> flat_areas(const ingest::Mesh& mesh, double max_angle_deg, double min_area_mm2) {
  // Upward faces within the angle: (highest vertex z, projected area), sorted by height and grouped
  // while consecutive heights stay within kFlatZToleranceMm of the group's lowest.
  const double min_nz = std::cos(max_angle_deg * 3.14159265358979323846 / 180.0);
  struct FlatFace {
    double top, area;
    std::array<Eigen::Vector2d, 4> at;  ///< centroid, then the corners (a big face's centroid may lie under another)
  };
  std::vector<FlatFace> faces;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose();
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose();
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0) || n.z() < min_nz * len) continue;
    const double top = std::max({a.z(), b.z(), c.z()});
    if (top - std::min({a.z(), b.z(), c.z()}) > kFlatZToleranceMm) continue;
    faces.push_back({top, 0.5 * n.z(), {((a + b + c) / 3).head<2>(), a.head<2>(), b.head<2>(), c.head<2>()}});
  }
  std::sort(faces.begin(), faces.end(), [](const FlatFace& p, const FlatFace& q) {
    return p.top != q.top ? p.top < q.top
                          : std::make_pair(p.at[0].x(), p.at[0].y()) < std::make_pair(q.at[0].x(), q.at[0].y());
  });
  std::vector<Flat> out;
  for (std::size_t i = 0; i < faces.size();) {
    Flat f{faces[i].top, 0, {}};
    std::size_t j = i;
    for (; j < faces.size() && faces[j].top - faces[i].top <= kFlatZToleranceMm; ++j) {
      f.z = faces[j].top;
      f.area_mm2 += faces[j].area;
    }
    const std::size_t every = (j - i + kFlatSamples - 1) / kFlatSamples;  // ≤ kFlatSamples, spread
    for (std::size_t k = i; k < j; k += every)
      f.samples.insert(f.samples.end(), faces[k].at.begin(), faces[k].at.end());
    if (f.area_mm2 >= min_area_mm2) out.push_back(f);
    i = j;
  }
  std::reverse(out.begin(), out.end());
  return out;
}

std::vector<pocket::Region> level_regions(const std::vector<ingest::ContourLoop>& loops, const pocket::Loop& stock,
                                          std::size_t* islands) {
  std::size_t n_islands = 0;
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
  for (std::size_t o = 0; o < loops.size(); ++o)
    if (!loops[o].hole && holder[o] < 0) {
      top.islands.push_back(to_loop(loops[o].pts, true));  // CCW outline → CW island
      ++n_islands;
    }
  out.push_back(std::move(top));
  for (std::size_t h = 0; h < loops.size(); ++h) {
    if (!loops[h].hole) continue;
    pocket::Region cav;
    cav.boundary = to_loop(loops[h].pts, true);  // CW hole → CCW boundary
    for (std::size_t o = 0; o < loops.size(); ++o)
      if (!loops[o].hole && holder[o] == static_cast<int>(h)) {
        cav.islands.push_back(to_loop(loops[o].pts, true));
        ++n_islands;
      }
    out.push_back(std::move(cav));
  }
  if (islands) *islands = n_islands;
  return out;
}

Result rough_mesh(const ingest::Mesh& mesh, const Params& p) {
  const auto t0 = std::chrono::steady_clock::now();
  if (p.cut.step_down <= 0) throw Error("/pocket/step_down must be > 0");
  const ingest::Box3 box = ingest::bounds(mesh);
  Result res;
  make_stock(mesh, box, p, res);
  if (p.stock_top)
    res.stock_left =
        stock_left(*p.stock_top, res.field, p, box.min.z() - p.cut.stock_to_leave - 1.0, res.stock_part_near);
  const double floor = box.min.z() + p.floor_allowance_mm;
  const double height = res.stock_top_part - floor;
  if (height <= 0) throw Error("nothing to rough: the stock top is not above the floor");
  // Counted in 64 bits and bounded before any level is planned (issue 15: --step-down 1e-9).
  const std::int64_t n_steps = pocket::level_count(height, p.cut.step_down);
  std::vector<double> flat_z;
  const std::vector<Flat> part_flats =
      p.flat_levels ? flat_areas(mesh, p.flat_max_angle_deg, p.flat_min_area_mm2) : std::vector<Flat>{};
  const std::vector<double> zs = level_heights(res, floor, n_steps, part_flats, p.cut.stock_to_leave, flat_z);
  const auto n_levels = static_cast<std::int64_t>(zs.size());
  const double clearance = p.cut.clearance();
  // Tool centres may pass up to one clearance outside the stock edge (the tool then just touches
  // it from the air side), so that the margin ring around the part is cleared even when the margin
  // is narrower than the clearance plus the islands' growth.
  const pocket::Loop stock = rectangle(res.stock_x0 - 2 * clearance, res.stock_y0 - 2 * clearance,
                                       res.stock_x1 + 2 * clearance, res.stock_y1 + 2 * clearance);
  const auto flats =
      static_cast<std::size_t>(std::count_if(flat_z.begin(), flat_z.end(), [](double f) { return !std::isnan(f); }));
  check_levels_work(stock, n_levels, flats, height, p);
  std::vector<pocket::LevelPlan> plans;
  double top_z = 0;
  for (std::size_t k = 0; k < zs.size(); ++k) {
    const Flat* flat = nullptr;  // a flat's level clears only where the flat is (unless everywhere)
    for (const Flat& f : part_flats)
      if (!p.flat_levels_everywhere && f.z == flat_z[k]) flat = &f;
    res.levels.push_back(plan_level(res, p, stock, zs[k], top_z, flat, plans, res.tool_points));
    res.levels.back().flat_z_part = flat_z[k];
    top_z = res.levels.back().z;
  }
  if (plans.empty()) {
    res.machining.status = pocket::PlanStatus::NothingToCut;
    res.machining.message = "no level has room for the tool";
  } else {
    pocket::MachiningOptions mo = p.machining;
    mo.contour = false;
    mo.comments = {"roughing: stock top Z 0 = part top + " + format_double(p.top_allowance_mm) + " mm, " +
                   std::to_string(res.levels.size()) + " Z levels" +
                   (flats > 0 ? " (" + std::to_string(flats) + " at flat areas)" : "")};
    pocket::CutParams cut = p.cut;
    cut.depth = height;  // the program's floor: the last level
    res.machining = pocket::machine_levels(std::move(plans), cut, mo);
  }
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

std::vector<LevelSummary> level_summaries(const Result& r) {
  std::vector<LevelSummary> out;
  out.reserve(r.levels.size());
  std::size_t li = 0;
  for (const Level& lv : r.levels) {
    LevelSummary s;
    for (const auto& pl : lv.plans) {
      s.tool_points += pl.tool_points.pts.size();
      s.chains += pl.path.chains.size();
    }
    // The machined paths (with feeds) of this level, in program order.
    while (li < r.machining.levels.size() && std::abs(r.machining.levels[li].z - lv.z) < 1e-9) {
      for (const auto& c : r.machining.levels[li].path.chains) s.path.chains.push_back(c);
      if (li < r.machining.level_uncut_mm2.size()) s.uncut_area_mm2 += r.machining.level_uncut_mm2[li];
      ++li;
    }
    s.cut_length_mm = s.path.cut_length();
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace millnet::rough
