// The offset (contour-parallel) planner (planner_offset.hpp).
#include "millnet/pocket/planner_offset.hpp"

#include "millnet/pocket/tolerances.hpp"

#include "arc_fit.hpp"
#include "offset.hpp"
#include "millnet/core/settings_view.hpp"
#include "work_internal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <queue>
#include <vector>

namespace millnet::pocket {

namespace {

/// Leftover middles smaller than this are slivers of the booleans, not material, mm².
constexpr double kMinMiddleMm2 = 0.05;

/// One connected component of one offset A_k.
struct Node {
  std::size_t level = 0;
  PolyArea area;
  std::optional<std::size_t> parent;
  std::vector<std::size_t> children;
  std::size_t depth_below = 0;  ///< levels of the deepest descendant below this node
};

/// The offsets A_0, A_1, … as a forest of nodes (roots: the reachable area's components).
///
/// A_0 is the region offset by the tool's clearance (fine chords: it is the ring beside the walls).
/// A_{k+1} is A_k offset by one stepover, component by component: erosion by disks composes
/// (A ⊖ B_a) ⊖ B_b = A ⊖ B_{a+b}, and a disk inside a disjoint union lies inside one component, so
/// each component's own offset is exactly its children. Offsetting the region by d0 + k·stepover in
/// one go was the same set at far greater cost: every vertex of a rough level's staircase contour
/// became a round join of radius d0 + k·stepover, chorded at 0.2 µm, and their O(n²) crossings kept
/// Clipper busy for minutes per part. The inner rings' round joins are chorded at arc_chord_mm;
/// chords lie inside the arcs they replace, so A_{k+1} can only grow toward A_k (the gap between
/// consecutive rings stays ≤ one stepover: coverage holds), while its distance to every wall stays
/// ≥ d0 + stepover − (k+1)·arc_chord_mm, far beyond the tool's radius. Each inner ring is then
/// simplified within arc_chord_mm: repeated round joins re-chord every vertex of the ring before,
/// and the rings grew to 2.4× the vertices (and G-code lines) of the one-shot offsets; the gap
/// between consecutive rings may grow by 2·arc_chord_mm, a cusp of no measurable area.
std::vector<Node> offset_tree(const Region& region, const CutParams& cut, std::size_t& levels) {
  std::vector<Node> nodes;
  std::vector<std::size_t> previous;  // node indices of the level above
  const double d0 = cut.clearance() + tol::contour_margin_mm;
  for (std::size_t k = 0;; ++k) {
    std::vector<std::pair<std::optional<std::size_t>, PolyArea>> comps;  // (parent, area)
    if (k == 0) {
      for (PolyArea& a : offset_inward(region, d0, tol::contour_chord_mm))
        comps.emplace_back(std::nullopt, std::move(a));
    } else {
      for (std::size_t q : previous)  // O(the parent's vertices) each
        for (const PolyArea& a : offset_areas({nodes[q].area}, -cut.stepover, tol::arc_chord_mm))
          comps.emplace_back(q, simplified(a, tol::arc_chord_mm));
    }
    comps.erase(std::remove_if(comps.begin(), comps.end(), [](const auto& c) { return c.second.outer.size() < 3; }),
                comps.end());
    if (comps.empty()) break;
    levels = k + 1;
    std::vector<std::size_t> current;
    for (auto& [parent, a] : comps) {
      Node n;
      n.level = k;
      n.parent = parent;
      n.area = std::move(a);
      current.push_back(nodes.size());
      if (n.parent) nodes[*n.parent].children.push_back(nodes.size());
      nodes.push_back(std::move(n));
    }
    previous = std::move(current);
  }
  // A leaf's middle lies up to one stepover from its ring. With stepover ≤ R that is swept (at
  // most a cusp the tool's edge touches); above R one more ring at half a stepover cuts it.
  // (Beside a split, a middle wider than R stays: the metrics' uncut area reports it.)
  const std::size_t before = nodes.size();
  for (std::size_t i = 0; i < before && cut.stepover > cut.tool.diameter / 2; ++i) {
    if (!nodes[i].children.empty()) continue;
    for (PolyArea& a : offset_areas({nodes[i].area}, -0.5 * cut.stepover, tol::contour_chord_mm)) {
      if (a.outer.size() < 3 || area(a) < kMinMiddleMm2) continue;
      Node n;
      n.level = nodes[i].level + 1;
      n.parent = i;
      n.area = std::move(a);
      nodes[i].children.push_back(nodes.size());
      nodes.push_back(std::move(n));
    }
  }
  for (std::size_t i = nodes.size(); i-- > 0;)  // children come after parents
    for (std::size_t c : nodes[i].children)
      nodes[i].depth_below = std::max(nodes[i].depth_below, nodes[c].depth_below + 1);
  return nodes;
}

/// Builds the path. A ring is appended as a closed loop; to get there the tool goes on along the
/// ring it has just cut (already cut, so nothing changes but time) to the vertex from which a
/// straight move to the new ring sweeps no wall (Clearance::move_ok), choosing the pair that
/// minimises that walk plus the move. Only where no pair is free does it retract.
class PathBuilder {
public:
  PathBuilder(const Region& region, const CutParams& cut, const OffsetParams& params)
      : clear_(region, cut.clearance()), R_(cut.tool.diameter / 2), climb_(params.climb) {
    const std::vector<Vec2> b = flatten(region.boundary, tol::arc_chord_mm);
    box_lo_ = box_hi_ = b.front();
    for (const Vec2& p : b) {
      box_lo_ = box_lo_.cwiseMin(p);
      box_hi_ = box_hi_.cwiseMax(p);
    }
  }

  /// Smallest distance between a vertex of the ring just cut (or the current point) and `loop`:
  /// the order of the loops of one node. O(ring · loop vertices).
  [[nodiscard]] double gap_to(const std::vector<Vec2>& loop) const {
    double best = std::numeric_limits<double>::infinity();
    const std::vector<Vec2>& from = last_;  // none cut yet: every loop is as near (infinity)
    const std::size_t sa = stride(from.size()), sb = stride(loop.size());
    for (std::size_t i = 0; i < from.size(); i += sa)
      for (std::size_t j = 0; j < loop.size(); j += sb) best = std::min(best, (from[i] - loop[j]).squaredNorm());
    return std::sqrt(best);
  }

  void add_ring(const std::vector<Vec2>& loop) {
    std::vector<Vec2> ring = loop;
    if (!climb_) std::reverse(ring.begin(), ring.end());
    std::size_t start = 0;
    if (last_.empty()) {
      path_.chains.push_back(Chain{});
      path_.chains.back().predrill = true;
    } else if (!link_to(ring, start)) {
      ++retractions_;
      start = nearest(ring, last_.front());
      Chain c;
      c.predrill = !near_cut(ring[start]);
      path_.chains.push_back(std::move(c));
    }
    last_.clear();
    for (std::size_t i = 0; i < ring.size(); ++i) last_.push_back(ring[(start + i) % ring.size()]);
    Chain& c = path_.chains.back();
    for (std::size_t i = 0; i <= last_.size(); ++i) push(c, last_[i % last_.size()]);
    ++rings_;
  }

  Path2D take() { return std::move(path_); }
  std::size_t rings() const { return rings_; }
  std::size_t links() const { return links_; }
  std::size_t retractions() const { return retractions_; }

private:
  static void push(Chain& c, const Vec2& p) {
    if (!c.pts.empty() && (c.pts.back().p() - p).norm() <= tol::join_mm) return;
    c.pts.push_back({p.x(), p.y(), 0.0});
  }

  /// Every k-th vertex of a loop of n, at most kSamples of them: the ring orders and link exits
  /// are chosen among these, so that a link costs O(kSamples · ring) however fine the rings are
  /// (a rough level's contours have thousands of vertices).
  static std::size_t stride(std::size_t n) { return std::max<std::size_t>(1, n / kSamples); }
  static constexpr std::size_t kSamples = 128;

  static std::size_t nearest(const std::vector<Vec2>& ring, const Vec2& p) {
    std::size_t best_i = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < ring.size(); ++i)
      if (const double d = (ring[i] - p).squaredNorm(); d < best) {
        best = d;
        best_i = i;
      }
    return best_i;
  }

  /// Walks on along last_ to vertex i, then straight to ring[j], for the cheapest free (i, j):
  /// for each i its nearest j (O(|last_|·|ring|)), candidates by walk + move, the first that
  /// move_ok accepts. Appends the walk and sets `start` = j; false when none is free.
  bool link_to(const std::vector<Vec2>& ring, std::size_t& start) {
    const std::size_t n = last_.size();
    std::vector<double> walk(n + 1, 0.0);  // walk[i]: along last_ from its start (= its end) to vertex i
    for (std::size_t i = 1; i <= n; ++i) walk[i] = walk[i - 1] + (last_[i % n] - last_[i - 1]).norm();
    struct Cand {
      double cost;
      std::size_t i, j;
    };
    std::vector<Cand> cands;
    cands.reserve(n);
    for (std::size_t i = 0; i < n; i += stride(n)) {
      const std::size_t j = nearest(ring, last_[i]);
      cands.push_back({walk[i] + (ring[j] - last_[i]).norm(), i, j});
    }
    std::sort(cands.begin(), cands.end(),
              [](const Cand& a, const Cand& b) { return a.cost < b.cost || (a.cost == b.cost && a.i < b.i); });
    for (const Cand& k : cands) {  // usually the first few
      if (!clear_.move_ok(last_[k.i], ring[k.j])) continue;
      Chain& c = path_.chains.back();
      for (std::size_t i = 1; i <= k.i; ++i) push(c, last_[i]);
      ++links_;
      start = k.j;
      return true;
    }
    return link_via(ring, start);
  }

  /// Where no straight move is free (the offsets split around islands): the shortest way from
  /// the ring just cut to the new ring's vertex nearest to it, searched on a grid of free tool
  /// centres (A*, 8 neighbours), pulled taut into straight moves that move_ok accepts.
  bool link_via(const std::vector<Vec2>& ring, std::size_t& start) {
    const Vec2 from = last_.front();
    const std::size_t j = nearest(ring, from);
    std::vector<Vec2> way;
    if (!grid_path(from, ring[j], way)) return false;
    std::vector<Vec2> taut{from};
    std::size_t k = 0;
    while (k + 1 < way.size()) {  // O(way²) move checks at worst; ways are short
      std::size_t far = k + 1;
      if (!clear_.move_ok(taut.back(), way[far])) return false;
      while (far + 1 < way.size() && clear_.move_ok(taut.back(), way[far + 1])) ++far;
      taut.push_back(way[far]);
      k = far;
    }
    Chain& c = path_.chains.back();
    for (std::size_t t = 1; t < taut.size(); ++t) push(c, taut[t]);
    ++links_;
    ++grid_links_;
    start = j;
    return true;
  }

  /// A* over cells of h mm (the free ones: point_ok at the centre); way = from, cell centres, to.
  bool grid_path(const Vec2& from, const Vec2& to, std::vector<Vec2>& way) {
    if (free_.empty()) build_grid();
    auto cell_of = [&](const Vec2& p) -> long {
      const long cx = std::lround((p.x() - lo_.x()) / h_), cy = std::lround((p.y() - lo_.y()) / h_);
      if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return -1;
      return cy * nx_ + cx;
    };
    auto centre = [&](long c) {
      return Vec2(lo_.x() + static_cast<double>(c % nx_) * h_, lo_.y() + static_cast<double>(c / nx_) * h_);
    };
    // Enter and leave the grid at the nearest free cell the straight move reaches.
    auto attach = [&](const Vec2& p) -> long {
      const long c0 = cell_of(p);
      if (c0 < 0) return -1;
      long best = -1;
      double bd = std::numeric_limits<double>::infinity();
      for (long dy = -2; dy <= 2; ++dy)
        for (long dx = -2; dx <= 2; ++dx) {
          const long cx = c0 % nx_ + dx, cy = c0 / nx_ + dy;
          if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) continue;
          const long c = cy * nx_ + cx;
          const double d = (centre(c) - p).norm();
          if (free_[static_cast<std::size_t>(c)] && d < bd && clear_.move_ok(p, centre(c))) {
            bd = d;
            best = c;
          }
        }
      return best;
    };
    const long s = attach(from), g = attach(to);
    if (s < 0 || g < 0) return false;
    const std::size_t n = free_.size();
    std::vector<double> dist(n, std::numeric_limits<double>::infinity());
    std::vector<long> prev(n, -1);
    using Item = std::pair<double, long>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    const Vec2 goal = centre(g);
    dist[static_cast<std::size_t>(s)] = 0;
    open.push({(centre(s) - goal).norm(), s});
    while (!open.empty()) {  // O(cells · log cells)
      const auto [f, c] = open.top();
      open.pop();
      if (c == g) break;
      const double dc = dist[static_cast<std::size_t>(c)];
      if (f > dc + (centre(c) - goal).norm() + 1e-9) continue;  // stale
      const long cx = c % nx_, cy = c / nx_;
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx) {
          const long x = cx + dx, y = cy + dy;
          if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
          const long q = y * nx_ + x;
          if (!free_[static_cast<std::size_t>(q)]) continue;
          const double nd = dc + h_ * ((dx != 0 && dy != 0) ? M_SQRT2 : 1.0);
          if (nd < dist[static_cast<std::size_t>(q)]) {
            dist[static_cast<std::size_t>(q)] = nd;
            prev[static_cast<std::size_t>(q)] = c;
            open.push({nd + (centre(q) - goal).norm(), q});
          }
        }
    }
    if (prev[static_cast<std::size_t>(g)] < 0 && g != s) return false;
    std::vector<Vec2> rev{to};
    for (long c = g; c >= 0; c = prev[static_cast<std::size_t>(c)]) rev.push_back(centre(c));
    rev.push_back(from);
    way.assign(rev.rbegin(), rev.rend());
    return true;
  }

  /// Free-centre grid over the region's box: h = max(R/4, box/512) so that it has ≤ 512² cells.
  void build_grid() {
    lo_ = box_lo_;
    const Vec2 ext = box_hi_ - box_lo_;
    h_ = std::max({R_ / 4, ext.x() / 512, ext.y() / 512});
    nx_ = static_cast<long>(std::ceil(ext.x() / h_)) + 1;
    ny_ = static_cast<long>(std::ceil(ext.y() / h_)) + 1;
    free_.assign(static_cast<std::size_t>(nx_ * ny_), 0);
    for (long c = 0; c < nx_ * ny_; ++c)
      free_[static_cast<std::size_t>(c)] = clear_.point_ok(
          Vec2(lo_.x() + static_cast<double>(c % nx_) * h_, lo_.y() + static_cast<double>(c / nx_) * h_));
  }

  /// Within R/2 of a vertex already cut (the contour pass's rule: no pre-drill needed there).
  bool near_cut(const Vec2& p) const {
    for (const Chain& c : path_.chains)  // O(path vertices), at most once per retraction
      for (const Vertex& v : c.pts)
        if ((v.p() - p).norm() <= 0.5 * R_) return true;
    return false;
  }

  Clearance clear_;
  double R_;
  bool climb_;
  Path2D path_;
  std::vector<Vec2> last_;  ///< the ring just cut, from its start vertex
  std::size_t rings_ = 0, links_ = 0, retractions_ = 0, grid_links_ = 0;
  Vec2 box_lo_, box_hi_, lo_;
  double h_ = 0;
  long nx_ = 0, ny_ = 0;
  std::vector<char> free_;
};

/// The node's island loops, each next the one nearest the ring just cut, then its outer loop (at
/// the root: the wall pass last).
void add_rings(PathBuilder& b, const Node& n) {
  std::vector<const std::vector<Vec2>*> left;
  for (const auto& h : n.area.holes) left.push_back(&h);
  while (!left.empty()) {
    std::size_t pick = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < left.size() && left.size() > 1; ++k)
      if (const double g = b.gap_to(*left[k]); g < best) {
        best = g;
        pick = k;
      }
    b.add_ring(*left[pick]);
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(pick));
  }
  b.add_ring(n.area.outer);
}

/// The outer ring of the first deepest leaf below node i (where its subtree is entered).
const std::vector<Vec2>& deepest_leaf_ring(const std::vector<Node>& nodes, std::size_t i) {
  while (!nodes[i].children.empty())
    i = *std::max_element(nodes[i].children.begin(), nodes[i].children.end(),
                          [&](std::size_t x, std::size_t y) { return nodes[x].depth_below < nodes[y].depth_below; });
  return nodes[i].area.outer;
}

/// The node and everything below it, inside out: each child's subtree (the nearest first), then
/// the node's own rings. The first subtree of a sibling is entered from the ring just cut, through
/// material the parent's ring has not reached yet (a short slotting move, gouge-checked).
void cut_inside_out(PathBuilder& b, const std::vector<Node>& nodes, std::size_t i) {
  std::vector<std::size_t> kids = nodes[i].children;
  while (!kids.empty()) {
    std::size_t pick = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < kids.size() && kids.size() > 1; ++k)
      if (const double g = b.gap_to(deepest_leaf_ring(nodes, kids[k])); g < best) {
        best = g;
        pick = k;
      }
    cut_inside_out(b, nodes, kids[pick]);
    kids.erase(kids.begin() + static_cast<std::ptrdiff_t>(pick));
  }
  add_rings(b, nodes[i]);
}

}  // namespace

PlanResult plan_offset(const Region& region, const CutParams& cut, const OffsetParams& params) {
  cut.check("offset planner");
  const auto t0 = std::chrono::steady_clock::now();
  PlanResult res;
  res.planner = "offset";
  std::size_t levels = 0;
  const std::vector<Node> nodes = offset_tree(region, cut, levels);
  OffsetStats st;
  st.offsets = levels;
  st.nodes = nodes.size();
  if (nodes.empty()) {
    res.status = PlanStatus::NoToolPoints;
    res.message = "the tool (clearance " + std::to_string(cut.clearance()) + " mm) fits nowhere in the pocket";
    res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  PathBuilder b(region, cut, params);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].children.size() > 1) ++st.splits;
    if (!nodes[i].parent) {
      ++st.components;
      cut_inside_out(b, nodes, i);
    }
  }
  st.rings = b.rings();
  st.links = b.links();
  st.retractions = b.retractions();
  res.path = b.take();
  // The rings' round joins and wall arcs as G2/G3 (arc_fit.hpp): a few hundred arcs instead of
  // thousands of sub-millimetre chords; each arc checked against the walls' clearance.
  const Clearance walls(region, cut.clearance());
  st.arcs = fit_arcs(res.path, tol::arc_fit_mm, &walls);
  for (const Chain& c : res.path.chains)
    if (c.predrill && !c.pts.empty()) res.predrill.push_back(c.pts.front().p());
  st.cut_length_mm = res.path.cut_length();
  st.rapid_length_mm = res.path.rapid_length();
  res.stats = st;
  res.walls_cut = true;
  res.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

// ---- the registry's entry ----

namespace {

PlannerSpec parse_offset(const SettingsView& pc, const PlannerContext&) {
  OffsetSpec spec;
  spec.offset.climb = pc.section("offset")->text("direction") == "climb";
  return spec;
}

PlanResult plan_offset_spec(const Region& region, const CutParams& cut, const PlannerSpec& spec) {
  return plan_offset(region, cut, spec.get<OffsetSpec>()->offset);
}

/// Offsets: at most half the box's smaller side / stepover + 1 of them, each as many vertices as the
/// walls flattened at the contour chord (round joins add about as many again): an upper bound of
/// the ring vertices, 16 bytes each.
std::vector<WorkEstimate> offset_work(const Region& region, const CutParams& cut, const PlannerSpec&) {
  const detail::BBox box = detail::boundary_box(region);
  double verts = static_cast<double>(flatten(region.boundary, tol::contour_chord_mm).size());
  for (const Loop& isl : region.islands) verts += static_cast<double>(flatten(isl, tol::contour_chord_mm).size());
  const double k = std::floor(0.5 * std::min(box.hi.x() - box.lo.x(), box.hi.y() - box.lo.y()) / cut.stepover) + 1;
  const double n = 2 * verts * k;
  return {{detail::over("stepover", cut.stepover, box), n, "offset ring vertices", 16.0 * n}};
}

}  // namespace

PlannerEntry offset_planner() {
  return {"offset",     "contour-parallel rings at the stepover, inside out",
          parse_offset, plan_offset_spec,
          offset_work,  {{"offset", {}, {}}}};
}

}  // namespace millnet::pocket
