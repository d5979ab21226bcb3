// The adaptive planner's last passes (adaptive_internal.hpp): the wall pass round every loop of the
// tool-centre area, and the raw chains simplified into the PlanResult (Douglas–Peucker, every kept
// chord checked against the walls).
#include "millnet/pocket/tolerances.hpp"

#include "adaptive_internal.hpp"
#include "offset.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace millnet::pocket::adaptive {

namespace {

/// Douglas–Peucker on an open polyline within eps, keeping a chord only where the walls allow it.
void simplify_into(const std::vector<Vec2>& pts, double eps, const Clearance& walls, std::vector<Vec2>& out) {
  if (pts.empty()) return;
  std::vector<char> keep(pts.size(), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, pts.size() - 1}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (b <= a + 1) continue;
    const Vec2 A = pts[a], B = pts[b];
    const Vec2 ab = B - A;
    const double L2 = ab.squaredNorm();
    double worst = -1;
    std::size_t wi = a + 1;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double t = L2 > 0 ? std::clamp((pts[i] - A).dot(ab) / L2, 0.0, 1.0) : 0.0;
      const double d = (pts[i] - (A + t * ab)).norm();
      if (d > worst) {
        worst = d;
        wi = i;
      }
    }
    if (worst <= eps && walls.move_ok(A, B)) continue;
    keep[wi] = 1;
    stack.push_back({a, wi});
    stack.push_back({wi, b});
  }
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (keep[i]) out.push_back(pts[i]);
}

/// The wall loops (wall_loops), reversed for conventional milling, with a vertex every
/// kWallStartMm of straight edge: a loop may start there (a corner holds the band the passes could
/// not reach, which a link into it would cut at once).
std::vector<std::vector<Vec2>> dense_wall_loops(const Region& region, double clearance, bool climb) {
  std::vector<std::vector<Vec2>> loops = wall_loops(region, clearance);
  for (auto& l : loops) {
    if (!climb) std::reverse(l.begin(), l.end());
    std::vector<Vec2> dense;
    for (std::size_t j = 0; j < l.size(); ++j) {
      const Vec2 a = l[j], b = l[(j + 1) % l.size()];
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kWallStartMm)));
      for (int t = 0; t < n; ++t) dense.push_back(a + (b - a) * (static_cast<double>(t) / n));
    }
    l = std::move(dense);
  }
  return loops;
}

}  // namespace

void Planner::cut_walls() {
  if (chains_.empty()) return;
  std::vector<std::vector<Vec2>> loops = dense_wall_loops(region_, cut_.clearance(), climb_);
  while (!loops.empty()) {
    std::size_t li = 0, vi = 0;
    const bool linked = link_to_wall_loop(loops, li, vi);
    std::vector<Vec2> loop;
    for (std::size_t j = 0; j <= loops[li].size(); ++j) loop.push_back(loops[li][(vi + j) % loops[li].size()]);
    loops.erase(loops.begin() + static_cast<std::ptrdiff_t>(li));
    if (!linked && !backtrack_to(loop.front())) {
      chains_.push_back(RawChain{});
      chains_.back().predrill = !safe(loop.front());
      ++stats_.wall_retractions;
    }
    RawChain& c = chains_.back();
    for (std::size_t j = 0; j < loop.size(); ++j) {
      if (!c.pts.empty()) mark_move(c.pts.back(), loop[j]);
      c.pts.push_back(loop[j]);
    }
  }
}

bool Planner::link_to_wall_loop(const std::vector<std::vector<Vec2>>& loops, std::size_t& li, std::size_t& vi) {
  const Vec2 at_ = current_end();
  // Candidate starts: every loop's vertices, nearest first; the first a link reaches (or a
  // backtrack along the path, for the nearest) wins.
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> cand;
  for (std::size_t i = 0; i < loops.size(); ++i)
    for (std::size_t j = 0; j < loops[i].size(); ++j) cand.push_back({(loops[i][j] - at_).squaredNorm(), {i, j}});
  const std::size_t keep = std::min<std::size_t>(cand.size(), kWallStartTries);
  std::partial_sort(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(keep), cand.end());
  li = cand.front().second.first;
  vi = cand.front().second.second;
  for (std::size_t k = 0; k < keep; ++k) {
    Vec2 start, toward;
    std::vector<Vec2> way;
    const auto [i, j] = cand[k].second;
    if (find_start(at_, start, toward, way, &loops[i][j]) && link_along(way)) {
      li = i;
      vi = j;
      return true;
    }
  }
  return false;
}

PlanResult Planner::result(PlanResult res) {
  AdaptiveStats& st = stats_;
  for (auto& raw : chains_) {
    Chain c;
    c.predrill = raw.predrill;
    std::vector<Vec2> pts;
    // The turn round the entry's bore and the rest apart, so that its end is kept.
    std::size_t turn_end = 0;  // in pts
    if (raw.turn_end > 0 && raw.turn_end < raw.pts.size()) {
      const auto split = raw.pts.begin() + static_cast<std::ptrdiff_t>(raw.turn_end);
      simplify_into(std::vector<Vec2>(raw.pts.begin(), split + 1), tol::adaptive_simplify_mm, exact_, pts);
      turn_end = pts.size() - 1;
      simplify_into(std::vector<Vec2>(split, raw.pts.end()), tol::adaptive_simplify_mm, exact_, pts);
    } else {
      simplify_into(raw.pts, tol::adaptive_simplify_mm, exact_, pts);
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2& p = pts[i];
      if (c.pts.empty() || (c.pts.back().p() - p).norm() > tol::join_mm) c.pts.push_back({p.x(), p.y(), 0.0});
      if (turn_end > 0 && i == turn_end) c.entry_turn = c.pts.size() - 1;
    }
    if (c.pts.size() == 1) c.pts.push_back(c.pts.front());  // a lone entry: keep it a move
    res.path.chains.push_back(std::move(c));
  }
  for (const Chain& c : res.path.chains)
    if (c.predrill && !c.pts.empty()) res.predrill.push_back(c.pts.front().p());
  st.retractions = res.path.retractions();
  st.cut_length_mm = res.path.cut_length();
  st.rapid_length_mm = res.path.rapid_length();
  st.uncut_target_mm2 = static_cast<double>(raster_.uncut_target_cells()) * raster_.h() * raster_.h();
  std::size_t v = 0;
  for (const Chain& c : res.path.chains) v += c.pts.size();
  st.vertices = v;
  res.stats = st;
  return res;
}

}  // namespace millnet::pocket::adaptive
