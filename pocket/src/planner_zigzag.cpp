// Zigzag planner: reachable area → (per direction) partition → face zigzags → order → best
// direction → world-frame chains.
#include "millnet/pocket/planner_zigzag.hpp"

#include "millnet/core/error.hpp"
#include "millnet/pocket/offset.hpp"
#include "millnet/pocket/tolerances.hpp"
#include "millnet/pocket/zigzag.hpp"

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
  int regions = 0;
  std::size_t passes = 0;
  int nonmonotone = 0;
  double cut_len = 0, rapid_len = 0;
};

double polyline_length(const std::vector<Vec2>& pts) {
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
      it.length[static_cast<std::size_t>(q)] = polyline_length(faces[k].chain(q));  // O(passes · V_f)
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
      it.length[q] = polyline_length(e);
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
    if (face_of[it] < faces.size()) {
      c.chains.push_back(faces[face_of[it]].chain(corner));
    } else {
      auto e = extras[extra_index[it]];
      if (corner & 2) std::reverse(e.begin(), e.end());
      c.chains.push_back(std::move(e));
    }
    c.cut_len += polyline_length(c.chains.back());
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

/// ZigzagParams::link_regions. Regions are taken in the planner's order; region i joins the chain
/// before it (as it is, or reversed: a zigzag cut backwards is the same passes) when the straight
/// move from that chain's end to its start is clear of the walls and its swept disk cuts at most
/// kLinkNewMaterialMm2 outside the area swept so far plus the disk at the start (where the region's
/// first pass engages anyway). The shorter admissible link wins. O(regions · swept-area booleans
/// over the path so far).
std::vector<std::vector<Vec2>> link_regions(std::vector<std::vector<Vec2>> chains, const Region& region,
                                            const CutParams& cut, std::size_t& links) {
  if (chains.size() < 2) return chains;
  const Clearance clear(region, cut.clearance());
  const double R = cut.tool_diameter / 2;
  std::vector<std::vector<Vec2>> out{std::move(chains.front())};
  std::vector<std::vector<Vec2>> swept_lines{out.front()};
  for (std::size_t i = 1; i < chains.size(); ++i) {
    std::vector<Vec2>& next = chains[i];
    const Vec2 end = out.back().back();
    std::optional<bool> pick;  // reversed?
    double best_len = std::numeric_limits<double>::infinity();
    std::optional<std::vector<PolyArea>> done;  // computed once, on the first wall-clear candidate
    for (const bool rev : {false, true}) {
      const Vec2 start = rev ? next.back() : next.front();
      const double len = (start - end).norm();
      if (len >= best_len || !clear.move_ok(end, start)) continue;
      if (!done) {
        auto lines = swept_lines;
        done = swept_area(lines, R, tol::arc_chord_mm);
      }
      std::vector<PolyArea> allowed = *done;
      for (PolyArea& a : swept_area({{start}}, R, tol::arc_chord_mm)) allowed.push_back(std::move(a));
      const double fresh = area(difference(swept_area({{end, start}}, R, tol::arc_chord_mm), allowed));
      if (fresh > kLinkNewMaterialMm2) continue;
      pick = rev;
      best_len = len;
    }
    if (pick) {
      if (*pick) std::reverse(next.begin(), next.end());
      std::vector<Vec2>& prev = out.back();
      for (const Vec2& p : next)
        if ((p - prev.back()).norm() > tol::join_mm) prev.push_back(p);
      ++links;
    } else {
      out.push_back(next);
    }
    swept_lines.push_back(std::move(next));
  }
  return out;
}

}  // namespace

std::vector<double> candidate_angles(const Region& region, double step_deg) {
  if (!(step_deg > 0) || !std::isfinite(step_deg)) throw Error("zigzag: angle_step_deg must be > 0, got " + std::to_string(step_deg));
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
    if (out.empty() || t - out.back() > 1e-6) out.push_back(t);
  return out;
}

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
    m << "the tool (diameter " << cut.tool_diameter << " mm, stock " << cut.stock_to_leave
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
  // Fewest regions, then lowest path cost; ties keep the smaller angle. O(angles · plan).
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
    const bool better = !have || c.regions < best.regions || (c.regions == best.regions && lc < lb - 1e-9);
    if (better) { best = std::move(c); have = true; }
  }

  std::vector<std::vector<Vec2>> worlds;
  for (const auto& ch : best.chains) {
    std::vector<Vec2> world;
    world.reserve(ch.size());
    for (const Vec2& p : ch) world.push_back(from_scan_frame(p, best.angle));
    worlds.push_back(std::move(world));
  }
  std::size_t links = 0;
  if (params.link_regions) worlds = link_regions(std::move(worlds), region, cut, links);
  for (const auto& world : worlds) {
    res.path.chains.push_back(make_chain(world, "cut", true));
    res.predrill.push_back(world.front());
  }
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
  st.angles_tried = angles.size();
  st.nonmonotone_faces = best.nonmonotone;
  st.zigzag_cut_length_mm = best.cut_len;
  st.zigzag_rapid_length_mm = best.rapid_len;
  st.region_links = links;
  res.stats = st;
  MILLNET_ASSERT(static_cast<int>(best.part.faces.size()) == best.part.formula_regions(),
                 "partition face count differs from n_s - n_i + n_c - n_n");
  if (res.path.chains.empty()) {
    res.status = PlanStatus::NothingToCut;
    res.message = "no zigzag pass meets the reachable area";
  }
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace millnet::pocket
