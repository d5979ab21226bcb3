// Tool-down links through material already cut (cut_links.hpp).
#include "millnet/pocket/cut_links.hpp"

#include "millnet/pocket/tolerances.hpp"

#include "offset.hpp"
#include "raster_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

namespace millnet::pocket {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Lattice spacing of the search, mm.
constexpr double kLatticeMm = 1.0;
/// Lattice positions keep this much more than the tool's clearance from the walls: a move between
/// two neighbours (≤ 1.42 mm) then cannot dip into the clearance round a convex wall (sagitta of a
/// 1.5 mm chord on a 5 mm arc: 0.06 mm).
constexpr double kLatticeMarginMm = 0.1;
/// The links' moves may come this much closer to a wall than the clearance: the chains they join
/// end on Clipper's offsets of the walls, whose chords lie up to tol::arc_chord_mm inside the true
/// offset of a wall arc (twice for an offset of an offset), so an end point itself may be that close.
constexpr double kEndSlackMm = 2 * tol::arc_chord_mm;
/// A way leaves the lattice this far beyond the tool's radius from its ends at most.
constexpr double kSeedMm = 2.5;
/// Graph edges join nodes (lattice positions, retrace nodes) this far apart at most, mm.
constexpr double kJoinMm = 1.5;
/// The exact check also allows a sliver this deep along the way (the raster sees the swept area
/// within a cell: a way pulled taut along its edge may graze it), mm: an engagement of ≈ 14° on Ø10.
constexpr double kSliverDepthMm = 0.15;
/// Candidates (a target and the lattice position its way leaves from) tried per query at most.
constexpr std::size_t kMaxCandidates = 4000;

/// Cells of the default raster at most; past them the cell doubles until they fit (a 2 × 2 m pocket
/// with a Ø10 tool: 6.5·10⁷ cells at D/40 were refused, issue 42; 1.6·10⁷ is a 1 × 1 m pocket at D/40).
constexpr double kMaxDefaultCells = 1.6e7;

/// D/40, or the first doubling of it whose raster over the region fits kMaxDefaultCells.
double default_cell(const Region& region, double tool_diameter) {
  double h = tool_diameter / 40;
  while (raster::cells_of(region, h, tool_diameter) > kMaxDefaultCells && h < tool_diameter / 4) h *= 2;
  return h;
}

}  // namespace

std::vector<Vec2> approach_of(const std::vector<Vec2>& chain, double tool_diameter) {
  std::vector<Vec2> out;
  if (chain.empty()) return out;
  out.push_back(chain.front());
  double left = kApproachDiameters * tool_diameter;
  for (std::size_t k = 1; k < chain.size() && left > 0; ++k) {
    const Vec2 d = chain[k] - out.back();
    const double L = d.norm();
    if (L <= left) {
      out.push_back(chain[k]);
      left -= L;
    } else {
      out.push_back(out.back() + d * (left / L));
      left = 0;
    }
  }
  return out;
}

struct CutLinker::Impl {
  Impl(const Region& region, const CutParams& cut, double max_new, double cell)
      : R(cut.tool.diameter / 2),
        max_new_mm2(max_new),
        g(raster::grid_of(region, cell > 0 ? cell : default_cell(region, cut.tool.diameter), cut.tool.diameter,
                          "links through cut material")),
        st(raster::material(region, g)),
        walls(region, cut.clearance() - kEndSlackMm),
        lattice_walls(region, cut.clearance() + kLatticeMarginMm) {
    lnx = static_cast<int>(std::floor((g.nx - 1) * g.h / kLatticeMm)) + 1;
    lny = static_cast<int>(std::floor((g.ny - 1) * g.h / kLatticeMm)) + 1;
    lat_wall.assign(raster::lin(0, lny, lnx), -1);
    buckets.resize(lat_wall.size());
    // The wall band: material within clearance + R of a wall, what the contour pass sweeps.
    std::vector<std::uint8_t> outside(st.size());
    for (std::size_t i = 0; i < st.size(); ++i) outside[i] = st[i] == 0;
    const std::vector<double> wd2 = raster::edt(outside, g.nx, g.ny);
    const double band_cells = (cut.clearance() + R) / g.h + 1;
    band.assign(st.size(), 0);
    for (std::size_t i = 0; i < st.size(); ++i) band[i] = st[i] != 0 && wd2[i] <= band_cells * band_cells;
    inner = offset_inward(region, cut.clearance() + R, tol::arc_chord_mm);
    reach_b = cut.tool.diameter + R;
  }

  double R;
  double max_new_mm2;
  raster::Grid g;
  std::vector<std::uint8_t> st;    ///< 0 no material, 1 uncut, 2 cut
  std::vector<std::uint8_t> band;  ///< within clearance + R (+ a cell) of a wall: the contour pass's sweep
  std::vector<PolyArea> inner;     ///< the material the contour pass leaves (region offset by clearance + R)
  double reach_b = 0;              ///< a target's approach includes the wall band this near it
  Clearance walls, lattice_walls;
  int lnx = 0, lny = 0;
  mutable std::vector<signed char> lat_wall;      ///< lattice position keeps the walls' clearance (cached)
  std::vector<std::vector<Vec2>> swept;           ///< every polyline marked, for the exact check
  std::vector<Vec2> path_pos;                     ///< retrace nodes along the swept polylines
  std::vector<std::uint8_t> path_joined;          ///< node i is joined to node i − 1 (the same polyline)
  std::vector<std::vector<std::size_t>> buckets;  ///< retrace nodes per lattice cell

  /// Calls f(index) for the cells whose centre lies within r of segment [a, b]: per row, the
  /// interval where the row's centre line meets the capsule (two disks and the band between them;
  /// the capsule is convex, so the union of the three is one interval). O(rows · cells per row).
  template <class F>
  void capsule(const Vec2& a, const Vec2& b, double r, F&& f) const {
    const double h = g.h;
    const int y0 = std::max(0, static_cast<int>(std::ceil((std::min(a.y(), b.y()) - r - g.lo.y()) / h - 0.5)));
    const int y1 = std::min(g.ny - 1, static_cast<int>(std::floor((std::max(a.y(), b.y()) + r - g.lo.y()) / h - 0.5)));
    const Vec2 d = b - a;
    const double L = d.norm();
    const Vec2 t = L > 0 ? Vec2(d / L) : Vec2(1, 0);
    const Vec2 n(-t.y(), t.x());
    for (int y = y0; y <= y1; ++y) {
      const double yc = g.lo.y() + (y + 0.5) * h;
      double lo = kInf, hi = -kInf;
      for (const Vec2* c : {&a, &b}) {
        const double dy = yc - c->y();
        if (dy * dy > r * r) continue;
        const double w = std::sqrt(r * r - dy * dy);
        lo = std::min(lo, c->x() - w);
        hi = std::max(hi, c->x() + w);
      }
      if (L > 0) {
        // The band: 0 ≤ (p − a)·t ≤ L and |(p − a)·n| ≤ r, each linear in x along the row.
        double blo = -kInf, bhi = kInf;
        auto clip = [&](double coef, double c0, double lo_v, double hi_v) {  // lo_v ≤ coef·x + c0 ≤ hi_v
          if (std::abs(coef) < 1e-12) {
            if (c0 < lo_v || c0 > hi_v) blo = kInf;
            return;
          }
          double u = (lo_v - c0) / coef, v = (hi_v - c0) / coef;
          if (u > v) std::swap(u, v);
          blo = std::max(blo, u);
          bhi = std::min(bhi, v);
        };
        clip(t.x(), -a.x() * t.x() + (yc - a.y()) * t.y(), 0, L);
        clip(n.x(), -a.x() * n.x() + (yc - a.y()) * n.y(), -r, r);
        if (blo <= bhi) {
          lo = std::min(lo, blo);
          hi = std::max(hi, bhi);
        }
      }
      if (!(lo <= hi)) continue;
      const int x0 = std::max(0, static_cast<int>(std::ceil((lo - g.lo.x()) / h - 0.5)));
      const int x1 = std::min(g.nx - 1, static_cast<int>(std::floor((hi - g.lo.x()) / h - 0.5)));
      for (int x = x0; x <= x1; ++x) f(raster::lin(x, y, g.nx));
    }
  }

  void mark(const std::vector<Vec2>& pl) {
    if (pl.empty()) return;
    swept.push_back(pl);
    // Retrace nodes: every vertex and a point every kLatticeMm between, so that two consecutive
    // nodes of one polyline lie on one of its segments (moving between them sweeps nothing new).
    auto add_node = [&](const Vec2& p, bool joined) {
      int x = 0, y = 0;
      lattice_cell(p, x, y);
      path_pos.push_back(p);
      path_joined.push_back(joined ? 1 : 0);
      if (x >= 0 && y >= 0 && x < lnx && y < lny) buckets[raster::lin(x, y, lnx)].push_back(path_pos.size() - 1);
    };
    add_node(pl.front(), false);
    for (std::size_t k = 0; k + 1 < pl.size(); ++k) {
      const Vec2 d = pl[k + 1] - pl[k];
      const int n = std::max(1, static_cast<int>(std::ceil(d.norm() / kLatticeMm)));
      for (int i = 1; i <= n; ++i) add_node(pl[k] + d * (static_cast<double>(i) / n), true);
    }
    auto cut_cell = [&](std::size_t i) {
      if (st[i] == 1) st[i] = 2;
    };
    if (pl.size() == 1) capsule(pl[0], pl[0], R, cut_cell);
    for (std::size_t k = 0; k + 1 < pl.size(); ++k) capsule(pl[k], pl[k + 1], R, cut_cell);
  }

  /// p's raster cell has its centre in the region. For a p that keeps the clearance (> a cell)
  /// from every wall, as every point a way passes does, that is p itself inside.
  [[nodiscard]] bool inside(const Vec2& p) const {
    const int x = static_cast<int>(std::floor((p.x() - g.lo.x()) / g.h));
    const int y = static_cast<int>(std::floor((p.y() - g.lo.y()) / g.h));
    return x >= 0 && y >= 0 && x < g.nx && y < g.ny && st[raster::lin(x, y, g.nx)] != 0;
  }

  [[nodiscard]] Vec2 lattice_point(std::size_t k) const {
    return g.centre(0, 0) + kLatticeMm * Vec2(static_cast<double>(k % static_cast<std::size_t>(lnx)),
                                              static_cast<double>(k / static_cast<std::size_t>(lnx)));
  }
  void lattice_cell(const Vec2& p, int& x, int& y) const {
    const Vec2 o = g.centre(0, 0);
    x = static_cast<int>(std::lround((p.x() - o.x()) / kLatticeMm));
    y = static_cast<int>(std::lround((p.y() - o.y()) / kLatticeMm));
  }

  /// One query's view: the distance transform of the uncut cells outside the start's disk.
  struct Query {
    const Impl& L;
    Vec2 a;
    std::vector<double> d2;  ///< squared cells to the nearest blocked cell
    double need2 = 0;

    Query(const Impl& impl, const Vec2& start) : L(impl), a(start) {
      std::vector<std::uint8_t> blocked(L.st.size(), 0);
      for (std::size_t i = 0; i < L.st.size(); ++i) blocked[i] = L.st[i] == 1;
      L.capsule(a, a, L.R, [&](std::size_t i) { blocked[i] = 0; });
      d2 = raster::edt(blocked, L.g.nx, L.g.ny);
      const double need = L.R / L.g.h + 0.5;
      need2 = need * need;
    }
    /// No uncut cell centre within R + cell/2 of the centre of p's cell (outside the start's disk):
    /// none within R − 0.21·cell of p.
    [[nodiscard]] bool clear(const Vec2& p) const {
      const int x = static_cast<int>(std::floor((p.x() - L.g.lo.x()) / L.g.h));
      const int y = static_cast<int>(std::floor((p.y() - L.g.lo.y()) / L.g.h));
      if (x < 0 || y < 0 || x >= L.g.nx || y >= L.g.ny) return false;
      return d2[raster::lin(x, y, L.g.nx)] >= need2;
    }
    /// clear, or every uncut cell within R − cell of p is allowed (stamped by allow()).
    [[nodiscard]] bool clear_for(const Vec2& p, const std::vector<std::uint32_t>* stamp, std::uint32_t gen) const {
      if (clear(p)) return true;
      if (!stamp) return false;
      bool ok = true;
      L.capsule(p, p, L.R - L.g.h, [&](std::size_t i) {
        if (L.st[i] == 1 && (*stamp)[i] != gen) ok = false;
      });
      return ok;
    }
    /// The straight move p→q: the walls' clearance (exact) and clear at every cell step
    /// (clear_for the stamped allowance where one is given).
    [[nodiscard]] bool straight(const Vec2& p, const Vec2& q, const std::vector<std::uint32_t>* stamp = nullptr,
                                std::uint32_t gen = 0) const {
      if (!L.inside(p) || !L.walls.segment_clear(p, q)) return false;
      const int n = std::max(1, static_cast<int>(std::ceil((q - p).norm() / L.g.h)));
      for (int i = 0; i <= n; ++i)
        if (!clear_for(p + (q - p) * (static_cast<double>(i) / n), stamp, gen)) return false;
      return true;
    }
  };

  /// Stamps `gen` on the uncut cells a way into target t may cut: within R of the start a or of
  /// the target's approach, and the wall band within reach_b of the target. O(cells stamped).
  void allow(const Vec2& a, const LinkTarget& t, std::vector<std::uint32_t>& stamp, std::uint32_t gen) const {
    auto put = [&](std::size_t i) { stamp[i] = gen; };
    capsule(a, a, R, put);
    if (t.approach.size() < 2) capsule(t.b, t.b, R, put);
    for (std::size_t k = 0; k + 1 < t.approach.size(); ++k) capsule(t.approach[k], t.approach[k + 1], R, put);
    capsule(t.b, t.b, reach_b, [&](std::size_t i) {
      if (band[i]) stamp[i] = gen;
    });
  }

  /// Graph nodes: [0, NL) lattice positions, [NL, NL + NP) retrace nodes (NL = lattice size).
  [[nodiscard]] Vec2 node_pos(std::size_t k) const {
    const std::size_t NL = lat_wall.size();
    return k < NL ? lattice_point(k) : path_pos[k - NL];
  }

  /// Calls f(node) for the lattice positions and retrace nodes within r of p.
  template <class F>
  void nodes_near(const Vec2& p, double r, F&& f) const {
    const std::size_t NL = lat_wall.size();
    int cx = 0, cy = 0;
    lattice_cell(p, cx, cy);
    const int rr = static_cast<int>(std::ceil(r / kLatticeMm)) + 1;
    for (int y = std::max(0, cy - rr); y <= std::min(lny - 1, cy + rr); ++y)
      for (int x = std::max(0, cx - rr); x <= std::min(lnx - 1, cx + rr); ++x) {
        const std::size_t k = raster::lin(x, y, lnx);
        if ((lattice_point(k) - p).norm() <= r) f(k);
        for (std::size_t j : buckets[k])
          if ((path_pos[j] - p).norm() <= r) f(NL + j);
      }
  }

  /// Shortest ways from a over the graph's nodes: their lengths (+inf: not reached) and the node
  /// before each on its way (−1: a seed, reached straight from a).
  struct Reached {
    std::vector<double> dist;
    std::vector<long> prev;
  };

  /// Dijkstra over the clear lattice positions and the retrace nodes the start reaches, seeded with
  /// the nodes round a that a straight move reaches. O(nodes · log nodes).
  Reached reach_from(const Vec2& a, const Query& q) const {
    const std::size_t NL = lat_wall.size(), NP = path_pos.size(), n = NL + NP;
    Reached r{std::vector<double>(n, kInf), std::vector<long>(n, -1)};
    std::vector<double>& dist = r.dist;
    std::vector<long>& prev = r.prev;
    std::vector<signed char> ok(NL, -1);
    auto usable = [&](std::size_t k) {
      if (k >= NL) return true;
      if (ok[k] < 0) {
        const Vec2 p = lattice_point(k);
        if (lat_wall[k] < 0) lat_wall[k] = lattice_walls.point_ok(p) ? 1 : 0;
        ok[k] = (lat_wall[k] == 1 && q.clear(p)) ? 1 : 0;
      }
      return ok[k] == 1;
    };
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    auto relax = [&](std::size_t from, std::size_t to, double nd) {
      if (nd < dist[to]) {
        dist[to] = nd;
        prev[to] = static_cast<long>(from);
        open.push({nd, to});
      }
    };
    nodes_near(a, R + kSeedMm, [&](std::size_t k) {
      const Vec2 p = node_pos(k);
      const double d = (p - a).norm();
      if (usable(k) && (d < tol::join_mm || q.straight(a, p))) relax(k, k, d);
    });
    for (std::size_t k = 0; k < n; ++k)
      if (dist[k] < kInf) prev[k] = -1;
    while (!open.empty()) {
      const double d = open.top().first;  // (not a structured binding: clang 14 cannot capture those)
      const std::size_t k = open.top().second;
      open.pop();
      if (d > dist[k]) continue;
      const Vec2 p = node_pos(k);
      if (k >= NL) {
        // Along the polyline it lies on, both ways: nothing new is swept.
        const std::size_t j = k - NL;
        if (j > 0 && path_joined[j]) relax(k, k - 1, d + (path_pos[j - 1] - p).norm());
        if (j + 1 < NP && path_joined[j + 1]) relax(k, k + 1, d + (path_pos[j + 1] - p).norm());
      }
      nodes_near(p, kJoinMm, [&](std::size_t m) {
        if (m == k || !usable(m)) return;
        const double step = (node_pos(m) - p).norm();
        if (d + step >= dist[m]) return;
        // Lattice neighbours keep the lattice margin from the walls and are clear: no check. A
        // retrace node where another polyline begins or ends is the same point.
        if ((k < NL && m < NL) || step < tol::join_mm || q.straight(p, node_pos(m))) relax(k, m, d + step);
      });
    }
    return r;
  }

  /// A candidate way: into target t from node `goal` (kDirect: straight from the start), its cost
  /// the way's length plus the target's extra.
  static constexpr std::size_t kDirect = std::numeric_limits<std::size_t>::max();
  struct Cand {
    double cost;
    std::size_t t, goal;
    bool operator>(const Cand& o) const {
      return cost != o.cost ? cost > o.cost : (t != o.t ? t > o.t : goal > o.goal);
    }
  };
  using Cands = std::priority_queue<Cand, std::vector<Cand>, std::greater<>>;

  /// Candidates, cheapest first: the straight move into each target, and every reached lattice
  /// position round a target followed by the straight move into it.
  Cands candidates(const Vec2& a, const std::vector<LinkTarget>& targets, const Reached& r) const {
    const std::size_t NL = lat_wall.size();
    Cands cands;
    for (std::size_t i = 0; i < targets.size(); ++i) {
      const LinkTarget& t = targets[i];
      cands.push({(t.b - a).norm() + t.extra, i, kDirect});
      // Lattice positions round the target; retrace nodes as far as its wall band reaches (a pass
      // beside a wall whose corridor has no lattice position: the last move leaves the pass).
      nodes_near(t.b, reach_b, [&](std::size_t k) {
        const double e = (node_pos(k) - t.b).norm();
        if (r.dist[k] < kInf && (k >= NL || e <= R + kSeedMm)) cands.push({r.dist[k] + e + t.extra, i, k});
      });
    }
    return cands;
  }

  std::optional<CutLinker::Link> best_link(const Vec2& a, const std::vector<LinkTarget>& targets) const {
    if (targets.empty()) return std::nullopt;
    const Query q(*this, a);
    const Reached r = reach_from(a, q);
    Cands cands = candidates(a, targets, r);
    std::vector<std::uint32_t> stamp(st.size(), 0);
    std::uint32_t gen = 0;
    std::size_t stamped_for = kDirect;
    for (std::size_t tried = 0; !cands.empty() && tried < kMaxCandidates; ++tried) {
      const Cand c = cands.top();
      cands.pop();
      const LinkTarget& t = targets[c.t];
      if (stamped_for != c.t) {
        allow(a, t, stamp, ++gen);
        stamped_for = c.t;
      }
      std::vector<Vec2> way;
      if (c.goal == kDirect) {
        if (!q.straight(a, t.b, &stamp, gen)) continue;
        way = {a, t.b};
      } else {
        if ((node_pos(c.goal) - t.b).norm() > tol::join_mm && !q.straight(node_pos(c.goal), t.b, &stamp, gen)) continue;
        std::vector<Vec2> rev{t.b};
        for (long k = static_cast<long>(c.goal); k >= 0; k = r.prev[static_cast<std::size_t>(k)])
          rev.push_back(node_pos(static_cast<std::size_t>(k)));
        rev.push_back(a);
        way = taut(std::vector<Vec2>(rev.rbegin(), rev.rend()), q, t.b, stamp, gen);
      }
      if (exact_ok(way, t)) return CutLinker::Link{c.t, std::move(way)};
    }
    return std::nullopt;
  }

  /// Each straight move as long as allowed (the allowance near the target b), looking from the far
  /// end first. O(way² · samples) at worst; ways are a few dozen lattice steps.
  std::vector<Vec2> taut(const std::vector<Vec2>& way, const Query& q, const Vec2& b,
                         const std::vector<std::uint32_t>& stamp, std::uint32_t gen) const {
    std::vector<Vec2> out{way.front()};
    std::size_t k = 0;
    while (k + 1 < way.size()) {
      std::size_t far = k + 1;
      for (std::size_t j = way.size() - 1; j > k + 1; --j)
        if (q.straight(way[k], way[j], (way[j] - b).norm() <= R + kSeedMm ? &stamp : nullptr, gen)) {
          far = j;
          break;
        }
      out.push_back(way[far]);
      k = far;
    }
    return out;
  }

  /// The exact check: the way's swept area outside what is swept so far, the start's disk and the
  /// target's approach (its first moves, and the wall band near it).
  bool exact_ok(const std::vector<Vec2>& way, const LinkTarget& t) const {
    // Only what was swept near the way matters: the runs of marked segments that meet the way's
    // box grown by 2R (anything farther cannot overlap the way's swept area). O(marked segments)
    // to select, booleans on the local runs only.
    Vec2 lo = way.front(), hi = way.front();
    for (const Vec2& p : way) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    lo -= Vec2(2 * R, 2 * R);
    hi += Vec2(2 * R, 2 * R);
    auto meets = [&](const Vec2& a, const Vec2& b) {
      return std::max(a.x(), b.x()) >= lo.x() && std::min(a.x(), b.x()) <= hi.x() && std::max(a.y(), b.y()) >= lo.y() &&
             std::min(a.y(), b.y()) <= hi.y();
    };
    std::vector<std::vector<Vec2>> local;
    for (const auto& pl : swept) {
      if (pl.size() == 1) {
        if (meets(pl[0], pl[0])) local.push_back(pl);
        continue;
      }
      bool open_run = false;
      for (std::size_t k = 0; k + 1 < pl.size(); ++k) {
        if (!meets(pl[k], pl[k + 1])) {
          open_run = false;
          continue;
        }
        if (!open_run) local.push_back({pl[k]});
        local.back().push_back(pl[k + 1]);
        open_run = true;
      }
    }
    std::vector<PolyArea> allowed = swept_area(local, R, tol::arc_chord_mm);
    std::vector<std::vector<Vec2>> ends{{way.front()}, t.approach.empty() ? std::vector<Vec2>{t.b} : t.approach};
    for (PolyArea& p : swept_area(ends, R, tol::arc_chord_mm)) allowed.push_back(std::move(p));
    for (PolyArea& p : difference(swept_area({{t.b}}, reach_b, tol::arc_chord_mm), inner))
      allowed.push_back(std::move(p));
    double len = 0;
    for (std::size_t k = 0; k + 1 < way.size(); ++k) len += (way[k + 1] - way[k]).norm();
    return area(difference(swept_area({way}, R, tol::arc_chord_mm), allowed)) <= max_new_mm2 + kSliverDepthMm * len;
  }
};

CutLinker::CutLinker(const Region& region, const CutParams& cut, double max_new_mm2, double cell_mm)
    : impl_(std::make_unique<Impl>(region, cut, max_new_mm2, cell_mm)) {}
CutLinker::~CutLinker() = default;
CutLinker::CutLinker(CutLinker&&) noexcept = default;
CutLinker& CutLinker::operator=(CutLinker&&) noexcept = default;

void CutLinker::sweep(const std::vector<Vec2>& polyline) { impl_->mark(polyline); }

void CutLinker::sweep(const Chain& chain) { impl_->mark(flatten_open(chain.pts, tol::arc_chord_mm)); }

std::optional<CutLinker::Link> CutLinker::best_link(const Vec2& a, const std::vector<LinkTarget>& targets) const {
  return impl_->best_link(a, targets);
}

}  // namespace millnet::pocket
