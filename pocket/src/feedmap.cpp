// Feed map (Shin & Suh §6): engagement from newly cut cells, feed from eq. 9.
#include "millnet/pocket/feedmap.hpp"

#include "geometry_internal.hpp"
#include "millnet/core/error.hpp"
#include "millnet/tooling/cutting.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace millnet::pocket {

double feed_for_engagement(double n3, double n1, double n2, const CutParams& cut) {
  if (n1 == n2) throw Error("feed map: n1 == n2 (tool diameter and radius give the same cell count)");
  if (cut.max_chip_thinning > 1 && n3 < n2) {  // radial chip thinning, a_e = D·n₃/n₁
    const double ae = std::max(cut.tool.diameter * n3 / n1, 1e-9 * cut.tool.diameter);
    const double k = std::min(tooling::chip_thinning_factor(cut.tool.diameter, ae), cut.max_chip_thinning);
    return std::clamp(cut.feed_half * k, cut.feed_min, cut.feed_max);
  }
  const double f = cut.feed_half + (cut.feed_half - cut.feed_slot) / (n2 - n1) * (n3 - n2);
  return std::clamp(f, cut.feed_min, cut.feed_max);
}

namespace {

/// Cut state of the fine grid; rows = y, cols = x.
///
/// Two readings of what a step cuts. The seed's: the cells whose centre the tool's disk newly
/// covers (n₃, which sets the feeds). And the swept area: each material cell keeps the signed
/// distance sd from its centre to the outline of the disks cut so far, a cell counts as covered
/// by the share ½ − sd/g (clamped to [0, 1]), and a step's cut is the sum of the shares it adds.
/// A crescent one cell thick holds ±3–6 centres more or fewer than its area in cells, depending
/// on where the cell centres fall (the largest of thousands of steps reads 15–18° high at 90° on a
/// D/40 grid); the shares read the area to a few hundredths of a cell per outline cell.
struct FeedMap {
  Vec2 lo;
  double g = 1;
  int nx = 0, ny = 0;
  std::vector<unsigned char> cut;  ///< 1 = cut or no material
  std::vector<float> sd;           ///< signed distance to the cut outline (material cells; < 0 inside)

  struct Marked {
    int fresh = 0;     ///< cells whose centre was newly covered
    double swept = 0;  ///< cells' worth of area newly covered (the shares)
  };

  /// Marks the disk of radius r about p. O((2r/g + 3)²).
  Marked mark(const Vec2& p, double r) {
    Marked m;
    const double ro = r + g;  // the shares reach half a cell beyond the outline (a cell more: rounding)
    const int x0 = std::max(0, static_cast<int>(std::floor((p.x() - ro - lo.x()) / g)));
    const int x1 = std::min(nx - 1, static_cast<int>(std::ceil((p.x() + ro - lo.x()) / g)));
    const int y0 = std::max(0, static_cast<int>(std::floor((p.y() - ro - lo.y()) / g)));
    const int y1 = std::min(ny - 1, static_cast<int>(std::ceil((p.y() + ro - lo.y()) / g)));
    const double r2 = r * r, ro2 = ro * ro, covered = -0.5 * g;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x);
        const double old = static_cast<double>(sd[i]);
        if (old <= covered) continue;  // no material, or fully covered (and so cut) already
        const Vec2 c = lo + Vec2((x + 0.5) * g, (y + 0.5) * g);
        const double d2 = (c - p).squaredNorm();
        if (d2 > ro2) continue;
        const double d = std::sqrt(d2) - r;
        if (d < old) {
          m.swept += share(d) - share(old);
          sd[i] = static_cast<float>(d);
        }
        if (d2 <= r2 && !cut[i]) {
          cut[i] = 1;
          ++m.fresh;
        }
      }
    return m;
  }

  [[nodiscard]] double share(double dist) const { return std::clamp(0.5 - dist / g, 0.0, 1.0); }
};

/// Splits segments longer than max_len into equal parts (lines: points on the line; arcs: equal
/// sub-arcs, bulge tan(θ/4n)), keeping feeds per part. O(output vertices).
void split_long(Chain& ch, double max_len) {
  if (ch.pts.size() < 2) return;
  std::vector<Vertex> out;
  std::vector<double> feeds;
  for (std::size_t k = 0; k + 1 < ch.pts.size(); ++k) {
    const Segment s{ch.pts[k].p(), ch.pts[k + 1].p(), ch.pts[k].bulge};
    const double len = length(s);
    const int n = len > 1.5 * max_len ? static_cast<int>(std::ceil(len / max_len)) : 1;
    const double f = k < ch.feed.size() ? ch.feed[k] : 0.0;
    const double bulge = s.is_arc() ? std::tan(std::atan(s.bulge) / n) : 0.0;
    for (int i = 0; i < n; ++i) {
      const Vec2 p = point_at(s, static_cast<double>(i) / n);
      out.push_back({p.x(), p.y(), bulge});
      feeds.push_back(f);
    }
  }
  out.push_back(ch.pts.back());
  ch.pts = std::move(out);
  ch.feed = std::move(feeds);
}
/// The map over the boundary's box grown by the tool radius R (cells of g): material = cells whose
/// centre is inside the region (+inf: nothing cut yet), the rest "covered" for the shares (−inf).
FeedMap material_map(const Region& region, double g, double R) {
  detail::BBox box;
  for (const Segment& s : segments(region.boundary)) {
    const detail::BBox b = detail::bbox(s);
    box.lo = box.lo.cwiseMin(b.lo);
    box.hi = box.hi.cwiseMax(b.hi);
  }
  FeedMap map;
  map.g = g;
  map.lo = box.lo - Vec2(R + g, R + g);
  map.nx = static_cast<int>(std::ceil((box.hi.x() - box.lo.x() + 2 * (R + g)) / g));
  map.ny = static_cast<int>(std::ceil((box.hi.y() - box.lo.y() + 2 * (R + g)) / g));
  if (static_cast<double>(map.nx) * map.ny > 5e7)
    throw Error("feed map: grid of " + std::to_string(map.nx) + " x " + std::to_string(map.ny) +
                " cells is too fine; raise feed_grid");
  map.cut.assign(static_cast<std::size_t>(map.nx) * static_cast<std::size_t>(map.ny), 1);
  // A clearance-0 query object makes the inside test cheap for cells far from walls. O(cells).
  const Clearance inside_q(region, 0.0);
  for (int y = 0; y < map.ny; ++y)
    for (int x = 0; x < map.nx; ++x)
      if (inside_q.point_ok(map.lo + Vec2((x + 0.5) * g, (y + 0.5) * g)))
        map.cut[static_cast<std::size_t>(y) * static_cast<std::size_t>(map.nx) + static_cast<std::size_t>(x)] = 0;
  map.sd.resize(map.cut.size());
  for (std::size_t i = 0; i < map.cut.size(); ++i)
    map.sd[i] = map.cut[i] ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
  return map;
}

/// What a chain engages, measured segment by segment in steps of at most a cell. Steps shorter
/// than a cell are pooled until they make a cell: a column of cells is cut once per cell of
/// travel, so a step of a tenth of a cell reads 0 or ten columns, scaled to a full cell (a slot
/// where the crescent is half). A segment that completes no pool reads the last pooled value.
/// The swept width: the shares pooled over at least a cell of travel (a window may span pieces).
struct ChainGauge {
  double pool_fresh = 0, pool_len = 0, last_n = 0;
  double win_area = 0, win_len = 0, last_w = 0;

  /// Segment s (length len) cut by a disk of radius R: its engagement n₃ (the largest step's
  /// count scaled to a cell, at most n₁) and swept width. O(steps · (D/g)²).
  std::pair<double, double> segment(FeedMap& map, const Segment& s, double len, double R, const CutParams& cut,
                                    double n1) {
    const double g = map.g;
    const int steps = std::max(1, static_cast<int>(std::ceil(len / g - 1e-9)));
    const double step_len = len / steps;
    double n3 = 0, sw = 0;
    bool measured = false, sw_measured = false;
    for (int i = 1; i <= steps; ++i) {
      const FeedMap::Marked mk = map.mark(point_at(s, static_cast<double>(i) / steps), R);
      const int fresh = mk.fresh;
      win_area += mk.swept;
      win_len += step_len;
      if (win_len >= g * (1 - 1e-9)) {
        last_w = std::min(win_area * g * g / win_len, cut.tool.diameter);
        sw = std::max(sw, last_w);
        sw_measured = true;
        win_area = win_len = 0;
      }
      // Scale to a full cell step (short steps cut fewer cells at the same width); a disk cannot
      // engage more than its diameter, so the scaled count is capped at n₁ (raster noise).
      double n = 0;
      if (step_len >= g * (1 - 1e-9) || !cut.feed_pool_short_steps) {
        n = fresh * (g / step_len);
      } else {
        pool_fresh += fresh;
        pool_len += step_len;
        if (pool_len < g * (1 - 1e-9)) continue;
        n = pool_fresh * (g / pool_len);
        pool_fresh = pool_len = 0;
      }
      last_n = std::min(n, n1);
      n3 = std::max(n3, last_n);
      measured = true;
    }
    if (!measured) n3 = last_n;
    if (!sw_measured) sw = last_w;
    return {n3, sw};
  }
};

/// The feed piece of segment k of chain ci (length len, from s_mm along the path) at engagement n3.
FeedPiece feed_piece(std::size_t ci, std::size_t k, double s_mm, double len, double n3, double sw,
                     const FeedProfile& prof, const CutParams& cut) {
  FeedPiece p;
  p.chain = ci;
  p.segment = k;
  p.s_mm = s_mm;
  p.length_mm = len;
  p.engagement = n3;
  p.width_mm = std::min(n3 * prof.grid_mm, cut.tool.diameter);
  p.swept_width_mm = sw;
  p.feed = cut.feed_adjust ? feed_for_engagement(n3, prof.n1, prof.n2, cut) : cut.feed_half;
  // Cuts no cell: a link. Never slower than the map's own feed for no engagement (with
  // chip thinning on, f₂ × max_chip_thinning within feed_max).
  if (n3 == 0 && cut.feed_air > 0) p.feed = std::max(p.feed, cut.feed_air);
  p.mrr_mm3_min = p.feed * p.width_mm * prof.axial_depth_mm;
  return p;
}

}  // namespace

FeedProfile assign_feeds(Path2D& path, const Region& region, const CutParams& cut, double axial_depth_mm,
                         const std::vector<EntryHole>& holes) {
  cut.check("feed map");
  const double g = cut.feed_grid > 0 ? cut.feed_grid : cut.tool.diameter / 10;
  const double R = cut.tool.diameter / 2;
  FeedProfile prof;
  prof.grid_mm = g;
  prof.n1 = cut.tool.diameter / g;
  prof.n2 = R / g;
  prof.axial_depth_mm = axial_depth_mm;
  FeedMap map = material_map(region, g, R);
  double s_total = 0;
  for (std::size_t ci = 0; ci < path.chains.size(); ++ci) {
    Chain& ch = path.chains[ci];
    if (ch.pts.empty()) continue;
    split_long(ch, cut.stepover);
    ch.feed.assign(ch.pts.size() - 1, cut.feed_half);
    map.mark(ch.pts.front().p(), R);  // the plunge: not a lateral engagement
    for (const EntryHole& h : holes)  // what the entry cleared (a helix): not the chain's engagement
      if (h.chain == ci) map.mark(h.centre, h.radius_mm);
    ChainGauge gauge;
    for (std::size_t k = 0; k + 1 < ch.pts.size(); ++k) {  // O(segments · steps per segment · (D/g)²)
      const Segment s{ch.pts[k].p(), ch.pts[k + 1].p(), ch.pts[k].bulge};
      const double len = length(s);
      const auto [n3, sw] = gauge.segment(map, s, len, R, cut, prof.n1);
      const FeedPiece p = feed_piece(ci, k, s_total, len, n3, sw, prof, cut);
      ch.feed[k] = p.feed;
      prof.pieces.push_back(p);
      s_total += len;
    }
  }
  return prof;
}

}  // namespace millnet::pocket
