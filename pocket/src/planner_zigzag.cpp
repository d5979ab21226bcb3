// Zigzag planner: reachable area → (per direction) partition → face zigzags → order → best
// direction → world-frame chains.
#include "millnet/pocket/planner_zigzag.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/cut_links.hpp"
#include "millnet/pocket/tolerances.hpp"

#include "offset.hpp"
#include "zigzag.hpp"
#include "work_internal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

namespace millnet::pocket {

namespace {

struct Candidate {
  double angle = 0;
  Partition part;
  std::vector<std::vector<Vec2>> chains;  // scan frame, in order
  /// Per position in the order: the item's chain from each of its four corners (scan frame), the
  /// chosen one first; a link may start a region from another corner (link_regions).
  std::vector<std::vector<std::vector<Vec2>>> corners;
  int regions = 0;
  std::size_t passes = 0;
  int nonmonotone = 0;
  double cut_len = 0, rapid_len = 0;
};

double planner_polyline_length(const std::vector<Vec2>& pts) {
  double l = 0;
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) l += (pts[k + 1] - pts[k]).norm();
  return l;
}

Candidate evaluate(const std::vector<PolyArea>& reach_world, double angle, PartitionKind kind, double stepover) {
  Candidate c;
  c.angle = angle;
  const auto areas = to_scan_frame(reach_world, angle);
  c.part = partition(areas, kind);
  const auto ys = pass_heights(areas, c.part.srps, stepover);
  std::vector<FaceZigzag> faces;
  faces.reserve(c.part.faces.size());
  for (const PolyArea& f : c.part.faces) faces.emplace_back(f, ys);  // O(F · passes · V_f)
  std::vector<OrderItem> items;
  std::vector<std::size_t> face_of;
  std::vector<std::vector<Vec2>> extras;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    if (!faces[k].monotone()) {
      ++c.nonmonotone;
      for (auto& e : faces[k].extra_chains()) extras.push_back(std::move(e));
    }
    if (faces[k].empty()) continue;
    OrderItem it;
    for (int q = 0; q < 4; ++q) {
      it.entry[static_cast<std::size_t>(q)] = faces[k].entry(q);
      it.exit[static_cast<std::size_t>(q)] = faces[k].exit(q);
      it.length[static_cast<std::size_t>(q)] = planner_polyline_length(faces[k].chain(q));  // O(passes · V_f)
    }
    items.push_back(it);
    face_of.push_back(k);
    c.passes += faces[k].passes();
  }
  // Leftover intervals of non-monotone faces (never expected) are ordered as one-pass items.
  for (const auto& e : extras) {
    OrderItem it;
    for (std::size_t q = 0; q < 4; ++q) {
      it.entry[q] = (q & 2) ? e.back() : e.front();
      it.exit[q] = (q & 2) ? e.front() : e.back();
      it.length[q] = planner_polyline_length(e);
    }
    items.push_back(it);
    face_of.push_back(faces.size());
    ++c.passes;
  }
  const Ordering ord = order_items(items);
  std::size_t extra_k = 0;
  std::vector<std::size_t> extra_index(items.size(), 0);
  for (std::size_t i = 0; i < items.size(); ++i)
    if (face_of[i] == faces.size()) extra_index[i] = extra_k++;
  for (std::size_t i = 0; i < ord.order.size(); ++i) {
    const std::size_t it = ord.order[i];
    const int corner = ord.corner[i];
    auto chain_at = [&](int q) {
      if (face_of[it] < faces.size()) return faces[face_of[it]].chain(q);
      auto e = extras[extra_index[it]];
      if (q & 2) std::reverse(e.begin(), e.end());
      return e;
    };
    c.chains.push_back(chain_at(corner));
    c.corners.emplace_back();
    for (int q = 0; q < 4; ++q) {
      auto alt = chain_at((corner + q) % 4);
      auto& seen = c.corners.back();
      if (std::find(seen.begin(), seen.end(), alt) == seen.end()) seen.push_back(std::move(alt));
    }
    c.cut_len += planner_polyline_length(c.chains.back());
  }
  c.rapid_len = ord.rapid_length;
  c.regions = static_cast<int>(c.chains.size());
  return c;
}

Chain make_chain(const std::vector<Vec2>& pts, const std::string& role, bool predrill) {
  Chain ch;
  ch.role = role;
  ch.predrill = predrill;
  for (const Vec2& p : pts) ch.pts.push_back({p.x(), p.y(), 0.0});
  return ch;
}

/// ZigzagParams::link_regions. After each region the tool goes, with the tool down, to the region
/// (of those left, from any of its corners: a zigzag started elsewhere is the same passes joined
/// along the other walls) that a way through cut material reaches with the shortest link plus the
/// corner's extra length (CutLinker: every position's disk within the area swept so far, up to
/// kLinkSliverMm2 of slivers, the last move also through what the region's first pass cuts
/// anyway); where none is reachable, the next region of the planned order from its planned corner
/// is entered anew. O(regions · (raster + lattice search + regions · corners · goal checks +
/// swept-area booleans)).
std::vector<std::vector<Vec2>> link_regions(const std::vector<std::vector<std::vector<Vec2>>>& corners,
                                            const Region& region, const CutParams& cut, std::size_t& links) {
  std::vector<std::vector<Vec2>> out;
  const std::size_t n = corners.size();
  if (n == 0) return out;
  CutLinker linker(region, cut, kLinkSliverMm2);
  std::vector<char> done(n, 0);
  out.push_back(corners.front().front());
  done[0] = 1;
  linker.sweep(out.back());
  for (std::size_t step = 1; step < n; ++step) {
    std::vector<LinkTarget> targets;
    std::vector<std::pair<std::size_t, std::size_t>> owner;  // (region, corner)
    for (std::size_t i = 0; i < n; ++i) {
      if (done[i]) continue;
      double shortest = std::numeric_limits<double>::infinity();
      for (const auto& ch : corners[i]) shortest = std::min(shortest, planner_polyline_length(ch));
      for (std::size_t q = 0; q < corners[i].size(); ++q) {
        const auto& ch = corners[i][q];
        targets.push_back({ch.front(), approach_of(ch, cut.tool.diameter), planner_polyline_length(ch) - shortest});
        owner.push_back({i, q});
      }
    }
    if (const auto l = linker.best_link(out.back().back(), targets)) {
      const auto [i, q] = owner[l->target];
      std::vector<Vec2>& prev = out.back();
      for (const Vec2& p : l->way)
        if ((p - prev.back()).norm() > tol::join_mm) prev.push_back(p);
      for (const Vec2& p : corners[i][q])
        if ((p - prev.back()).norm() > tol::join_mm) prev.push_back(p);
      linker.sweep(l->way);
      linker.sweep(corners[i][q]);
      done[i] = 1;
      ++links;
    } else {
      const auto i = static_cast<std::size_t>(std::find(done.begin(), done.end(), 0) - done.begin());
      out.push_back(corners[i].front());
      linker.sweep(out.back());
      done[i] = 1;
    }
  }
  return out;
}

}  // namespace

std::vector<double> candidate_angles(const Region& region, double step_deg) {
  if (!(step_deg > 0) || !std::isfinite(step_deg))
    throw Error("zigzag: angle_step_deg must be > 0, got " + std::to_string(step_deg));
  std::vector<double> a;
  for (double t = 0; t < 180.0 - 1e-9; t += step_deg) a.push_back(t);
  auto add_loop = [&](const Loop& loop) {
    for (const Segment& s : segments(loop)) {  // O(edges)
      if (s.is_arc()) continue;
      const Vec2 d = s.b - s.a;
      if (d.norm() <= tol::join_mm) continue;
      double t = std::atan2(d.y(), d.x()) * 180.0 / std::numbers::pi;
      t = std::fmod(t + 360.0, 180.0);
      if (t >= 180.0 - 1e-9) t = 0;
      a.push_back(t);
    }
  };
  add_loop(region.boundary);
  for (const Loop& l : region.islands) add_loop(l);
  std::sort(a.begin(), a.end());
  std::vector<double> out;
  for (double t : a)
    if (out.empty() || t - out.back() > tol::same_angle_deg) out.push_back(t);
  return out;
}

namespace {

/// The direction to cut in, of `angles`: fewest regions, then lowest path cost; ties keep the
/// smaller angle. Each evaluated direction goes to *scores when given. O(angles · plan).
Candidate best_direction(const std::vector<PolyArea>& reach, const std::vector<double>& angles,
                         const ZigzagParams& params, const CutParams& cut, std::vector<AngleScore>* scores) {
  Candidate best;
  bool have = false;
  for (double a : angles) {
    Candidate c = evaluate(reach, a, params.partition, cut.stepover);
    if (scores) scores->push_back({a, c.regions, c.cut_len + c.rapid_len, c.passes});
    // Path cost = cut + rapid length + a turn penalty per pass: the slanted directions of a
    // thin pocket are a little shorter (their end passes are short) but turn ten times as often.
    const double pen = params.turn_penalty_mm >= 0 ? params.turn_penalty_mm : cut.stepover;
    const double lc = c.cut_len + c.rapid_len + pen * static_cast<double>(c.passes);
    const double lb = best.cut_len + best.rapid_len + pen * static_cast<double>(best.passes);
    const bool better =
        !have || c.regions < best.regions || (c.regions == best.regions && lc < lb - tol::improvement_mm);
    if (better) {
      best = std::move(c);
      have = true;
    }
  }
  return best;
}

/// The chosen direction's chains in world coordinates: the regions linked with the tool down
/// where params.link_regions (links counts the links), else in the planned order.
std::vector<std::vector<Vec2>> world_chains(const Candidate& best, const Region& region, const CutParams& cut,
                                            const ZigzagParams& params, std::size_t& links) {
  auto to_world = [&](const std::vector<Vec2>& ch) {
    std::vector<Vec2> world;
    world.reserve(ch.size());
    for (const Vec2& p : ch) world.push_back(from_scan_frame(p, best.angle));
    return world;
  };
  std::vector<std::vector<Vec2>> worlds;
  links = 0;
  if (params.link_regions) {
    std::vector<std::vector<std::vector<Vec2>>> corners;
    for (const auto& alts : best.corners) {
      corners.emplace_back();
      for (const auto& ch : alts) corners.back().push_back(to_world(ch));
    }
    worlds = link_regions(corners, region, cut, links);
  } else {
    for (const auto& ch : best.chains) worlds.push_back(to_world(ch));
  }
  return worlds;
}

ZigzagStats zigzag_stats(const Candidate& best, std::size_t angles_tried, std::size_t links) {
  ZigzagStats st;
  st.regions = best.regions;
  st.faces = best.part.faces.size();
  st.srps = best.part.srps.size();
  st.nls = best.part.nls;
  st.islands = best.part.n_islands;
  st.components = best.part.n_components;
  st.formula_regions = best.part.formula_regions();
  st.passes = best.passes;
  st.angle_deg = best.angle;
  st.angles_tried = angles_tried;
  st.nonmonotone_faces = best.nonmonotone;
  st.zigzag_cut_length_mm = best.cut_len;
  st.zigzag_rapid_length_mm = best.rapid_len;
  st.region_links = links;
  return st;
}

}  // namespace

PlanResult plan_zigzag(const Region& region, const CutParams& cut, const ZigzagParams& params,
                       std::vector<AngleScore>* scores) {
  const auto t0 = std::chrono::steady_clock::now();
  cut.check("zigzag");
  PlanResult res;
  res.planner = params.partition == PartitionKind::T ? "zigzag-t" : "zigzag-i";
  const auto reach = offset_inward(region, cut.clearance(), tol::arc_chord_mm);
  if (reach.empty()) {
    res.status = PlanStatus::NoToolPoints;
    std::ostringstream m;
    m << "the tool (diameter " << cut.tool.diameter << " mm, stock " << cut.stock_to_leave
      << " mm) fits nowhere in the pocket";
    res.message = m.str();
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  std::vector<double> angles;
  if (params.angle_deg) {
    if (!std::isfinite(*params.angle_deg)) throw Error("zigzag: angle_deg is not finite");
    angles.push_back(*params.angle_deg);
  } else {
    angles = candidate_angles(region, params.angle_step_deg);
  }
  const Candidate best = best_direction(reach, angles, params, cut, scores);
  std::size_t links = 0;
  for (const auto& world : world_chains(best, region, cut, params, links)) {
    res.path.chains.push_back(make_chain(world, "cut", true));
    res.predrill.push_back(world.front());
  }
  res.stats = zigzag_stats(best, angles.size(), links);
  MILLNET_ASSERT(static_cast<int>(best.part.faces.size()) == best.part.formula_regions(),
                 "partition face count differs from n_s - n_i + n_c - n_n");
  if (res.path.chains.empty()) {
    res.status = PlanStatus::NothingToCut;
    res.message = "no zigzag pass meets the reachable area";
  }
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

// ---- the registry's entry ----

std::optional<double> parse_zigzag_angle(const std::string& text, const std::string& where) {
  if (text == "auto") return std::nullopt;
  try {
    std::size_t used = 0;
    const double deg = std::stod(text, &used);
    if (used != text.size() || !(std::abs(deg) <= 360)) throw std::invalid_argument(text);
    return deg;
  } catch (const std::exception&) {
    throw Error(where + ": expected a number of degrees in [-360, 360] or \"auto\", got \"" + text.substr(0, 40) +
                "\"");
  }
}

namespace {

/// /pocket/zigzag/angle: degrees in [-360, 360], or "auto" (searched).
std::optional<double> zigzag_angle(const SettingsView& z) {
  if (!z.is_text("angle")) return z.number("angle");
  return parse_zigzag_angle(z.text("angle"), z.pointer() + "/angle");
}

PlannerSpec parse_zigzag(const SettingsView& pc, const PlannerContext&) {
  const auto z = pc.section("zigzag");
  ZigzagSpec spec;
  const std::string part = z->text("partition");
  spec.zigzag.partition = (part == "t" || part == "T") ? PartitionKind::T : PartitionKind::I;
  spec.zigzag.link_regions = z->flag("link_regions");
  spec.zigzag.angle_deg = zigzag_angle(*z);
  return spec;
}

PlanResult plan_zigzag_spec(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  return plan_zigzag(region, cut, spec.get<ZigzagSpec>()->zigzag);
}

/// Scan lines: (box diagonal / stepover + 1) per direction tried (one with a fixed angle, else
/// ⌈180 / angle_step⌉ + one per boundary segment), 64 bytes per line — an upper bound.
std::vector<WorkEstimate> zigzag_work(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  const ZigzagParams& zz = spec.get<ZigzagSpec>()->zigzag;
  const detail::BBox box = detail::boundary_box(region);
  const double diag = (box.hi - box.lo).norm();
  const double lines = std::floor(diag / cut.stepover) + 1;
  double directions = 1;
  if (!zz.angle_deg) {
    const double step = zz.angle_step_deg > 0 ? zz.angle_step_deg : 1.0;
    directions = std::ceil(180.0 / step) + static_cast<double>(region.boundary.size());
  }
  const double n = lines * directions;
  return {{detail::over("stepover", cut.stepover, box), n, "zigzag scan lines", 64.0 * n}};
}

}  // namespace

PlannerEntry zigzag_planner() {
  return {"zigzag",
          "Suh & Kim's zigzag over a T- or I-partition of the pocket",
          parse_zigzag,
          plan_zigzag_spec,
          zigzag_work,
          {{"zigzag-t", {{"zigzag/angle", "auto"}}, {{"zigzag/partition", "t"}}},
           {"zigzag-i", {{"zigzag/angle", "auto"}}, {{"zigzag/partition", "i"}}}}};
}

}  // namespace millnet::pocket
