// Z-level (waterline) contours, strategy 4 and the steep half of strategy 1.
//
// Per level z: the CL height grid (drop-cutter, ≤ R/2 apart) gives the topology by marching
// squares of {CL ≥ z}; every crossing is then refined on its grid edge by the drop-cutter
// (Illinois regula falsi, bracket ≤ chord tolerance, the point returned on the air side, where
// the cutter at z does not touch); chords that would cut into the part anywhere along them
// (sampled ≤ min(0.1 mm, R/4) apart) are split by a further refined point; a chord whose splits
// run out of their budget (the level set finer than they can follow) rides over the material on
// the drop-cutter instead. Loops are reversed to keep the material on the right (climb milling
// with M3) and cut open where they run along the machining boundary.
#include "contours.hpp"
#include "sampling.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/finish/tolerances.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>

namespace millnet::finish::detail {
namespace {

/// Point on [in, out] where CL crosses z, within `tol` of it on the air side; also the slope of
/// the contact on the material side of the final bracket.
std::pair<Eigen::Vector2d, double> refine_crossing(const Sampler& s, Eigen::Vector2d in, Eigen::Vector2d out,
                                                   double f_in, double f_out, double z, double tol) {
  Sample s_in = s.sample(in.x(), in.y());
  f_in = s_in.p.z() - z;
  int side = 0;
  for (int it = 0; it < 60 && (out - in).norm() > tol; ++it) {
    double t = f_in / (f_in - f_out);      // f_in ≥ 0 > f_out
    if (!(t > 0.02 && t < 0.98)) t = 0.5;  // discontinuities (walls): bisection
    const Eigen::Vector2d m = in + t * (out - in);
    const Sample sm = s.sample(m.x(), m.y());
    const double fm = sm.p.z() - z;
    if (fm >= 0) {
      in = m, f_in = fm, s_in = sm;
      if (side == 1) f_out *= 0.5;  // Illinois: keep the far end from sticking
      side = 1;
    } else {
      out = m, f_out = fm;
      if (side == -1) f_in *= 0.5;
      side = -1;
    }
  }
  return {out, s_in.slope_deg};
}

/// What a chord's check says: keep it, split it at `mid`, or (the budget spent on a chord that
/// still needs a split) give up on it.
struct Verdict {
  enum Kind { Keep, Split, Exhausted } kind = Keep;
  ContourPoint mid{};
};

/// The depth-first split both chord checks share: each chord a→b of the loop is asked of
/// `check(a, b, budget_left)` and, where it is split, its two halves in turn (in order), with a
/// budget of splits per original chord (not a depth: a split near one end leaves the other
/// sub-chord almost as long, and the next split there is one level deeper). A chord whose check
/// gives up is replaced by `ride(a, b)`: the points after a, up to and including b.
template <class Check, class Ride>
void split_chords(std::vector<ContourPoint>& loop, Check&& check, Ride&& ride) {
  constexpr int kMaxSplits = 64;
  struct Item {
    ContourPoint a, b;
  };
  std::vector<ContourPoint> out;
  out.reserve(loop.size());
  for (std::size_t i = 0; i + 1 < loop.size(); ++i) {  // O(chords · (len / h + splits · log))
    out.push_back(loop[i]);
    std::vector<Item> stack{{loop[i], loop[i + 1]}};
    std::vector<ContourPoint> seq;  // the ends of the sub-chords in order; the last is loop[i + 1]
    int splits = 0;
    while (!stack.empty()) {
      const Item it = stack.back();
      stack.pop_back();
      const Verdict v = check(it.a, it.b, splits < kMaxSplits);
      if (v.kind == Verdict::Exhausted) {
        seq = ride(loop[i], loop[i + 1]);
        break;
      }
      if (v.kind == Verdict::Keep) {
        seq.push_back(it.b);
        continue;
      }
      ++splits;
      stack.push_back({v.mid, it.b});
      stack.push_back({it.a, v.mid});
    }
    for (std::size_t k = 0; k + 1 < seq.size(); ++k) out.push_back(seq[k]);
  }
  out.push_back(loop.back());
  loop = std::move(out);
}

/// Splits chords P→Q that pass through the material (checked every ≤ min(0.1 mm, R/4) along the
/// chord; the straight move would cut into the part) at their deepest point, by a refined contour
/// point found along the chord's air-side normal (the material is on the left of the contour as
/// traced, so the air is on the right). With `fresh_only`, only chords with an end another split
/// made (ContourPoint::fresh) are checked: the others passed this check before.
void split_gouging_chords(const Sampler& s, std::vector<ContourPoint>& loop, double z, double tol,
                          bool fresh_only = false) {
  const double h = std::min(tol::initial_sample_mm, s.cutter().radius() / 4);
  auto check = [&](const ContourPoint& a, const ContourPoint& b, bool budget_left) -> Verdict {
    if (a.on_boundary || b.on_boundary || (fresh_only && !a.fresh && !b.fresh)) return {};
    const Eigen::Vector2d d = b.xy - a.xy;
    const double len = d.norm();
    if (!(len > 2 * tol::min_sample_mm)) return {};
    // The chord's interior every ≤ h (at least its midpoint): the worst point decides, since a
    // narrow feature can cut a long chord off its middle.
    const int pieces = std::max(2, static_cast<int>(std::ceil(len / h)));
    Eigen::Vector2d m = 0.5 * (a.xy + b.xy);
    double worst = -std::numeric_limits<double>::infinity();
    for (int k = 1; k < pieces; ++k) {
      const Eigen::Vector2d q = a.xy + (static_cast<double>(k) / pieces) * d;
      const double f = s.z(q.x(), q.y()) - z;
      if (f > worst) worst = f, m = q;
    }
    if (worst <= 0.5 * tol::chord_below_mm) return {};
    if (!budget_left) return {Verdict::Exhausted};
    // Inside on the left of a→b: the air is on the right, normal (dy, −dx).
    // March out along the normal, on both sides (the air side first on ties), to the NEAREST
    // air point: reach grows from the tolerance, doubling up to h, then in steps of h. A far
    // probe can land on another branch of the level set, and on a thin sliver of material the
    // air can be nearer on the left than on the right.
    const Eigen::Vector2d n(d.y() / len, -d.x() / len);
    const double max_reach = std::max(2 * len, 4 * s.cutter().radius());
    Eigen::Vector2d near = m, far = m;
    double f_far = worst;
    double prev = 0;
    for (double reach = std::min(tol, h); reach <= max_reach + 1e-12 && f_far >= 0;
         reach = reach < h ? std::min(2 * reach, h) : reach + h) {
      for (const double side : {1.0, -1.0}) {
        const Eigen::Vector2d q = m + side * reach * n;
        const double fq = s.z(q.x(), q.y()) - z;
        if (fq < 0) {
          near = m + side * prev * n;
          far = q;
          f_far = fq;
          break;
        }
      }
      prev = reach;
    }
    if (f_far >= 0) return {};  // no air found nearby: keep the chord (cannot happen on a closed contour)
    const auto [xy, slope] = refine_crossing(s, near, far, 0, f_far, z, tol);
    return {Verdict::Split, ContourPoint{xy, slope, false, 0, fresh_only}};
  };
  // The level set here is finer than the splits can follow (a sliver of material a hair above the
  // level, crossed again and again): the chord keeps its ends and rides over the material on the
  // drop-cutter instead — never below it, a lift of at most the sliver's height.
  auto ride = [&](const ContourPoint& a, const ContourPoint& b) {
    std::vector<ContourPoint> seq;
    const std::vector<Sample> over = sample_segment(s, a.xy, b.xy, h, tol);
    for (std::size_t k = 1; k < over.size(); ++k) {
      const Sample& q = over[k];
      seq.push_back(ContourPoint{q.p.head<2>(), q.slope_deg, false, std::max(0.0, q.p.z() - z)});
    }
    return seq;
  };
  split_chords(loop, check, ride);
}

/// Splits chords P→Q that pass through the air by more than `tol` / 2 off the contour (an inside
/// corner of the level cut across: the cutter at z along the chord stands off the wall there) at
/// their farthest point, by a refined contour point found along the chord's material-side normal.
/// The material is on the left of the contour as traced. The points it adds are marked fresh.
void split_air_chords(const Sampler& s, std::vector<ContourPoint>& loop, double z, double tol) {
  const double h = std::min(tol::initial_sample_mm, s.cutter().radius() / 4);
  auto check = [&](const ContourPoint& a, const ContourPoint& b, bool budget_left) -> Verdict {
    const Eigen::Vector2d d = b.xy - a.xy;
    const double len = d.norm();
    if (a.on_boundary || b.on_boundary || a.lift > 0 || b.lift > 0 || !(len > 2 * tol) || !budget_left) return {};
    // The chord's interior every ≤ h: the point standing farthest below the level.
    const int pieces = std::max(2, static_cast<int>(std::ceil(len / h)));
    Eigen::Vector2d m = 0.5 * (a.xy + b.xy);
    double airiest = 0;
    for (int k = 1; k < pieces; ++k) {
      const Eigen::Vector2d q = a.xy + (static_cast<double>(k) / pieces) * d;
      const double f = s.z(q.x(), q.y()) - z;
      if (f < airiest) airiest = f, m = q;
    }
    // Into the material (the left, normal (−dy, dx)) up to the chord's length: the contour found
    // there, more than tol off the chord, splits it.
    const Eigen::Vector2d n(-d.y() / len, d.x() / len);
    Eigen::Vector2d air = m, in = m;
    double f_air = airiest;
    bool found = false;
    for (double reach = tol; airiest < 0; reach = std::min(2 * reach, len)) {  // O(log(len / tol)) drops
      const Eigen::Vector2d q = m + reach * n;
      const double fq = s.z(q.x(), q.y()) - z;
      if (fq >= 0) {
        in = q, found = true;
        break;
      }
      air = q, f_air = fq;
      if (reach >= len) break;
    }
    if (!found) return {};
    // Refined to half the tolerance, and split where that is half of it off: the corner is then
    // cut by no more than the tolerance.
    const auto [xy, slope] = refine_crossing(s, in, air, 0, f_air, z, 0.5 * tol);
    if (std::abs((xy - m).dot(n)) <= 0.5 * tol) return {};
    return {Verdict::Split, ContourPoint{xy, slope, false, 0, true}};
  };
  split_chords(loop, check, [](const ContourPoint&, const ContourPoint&) { return std::vector<ContourPoint>{}; });
}

}  // namespace

std::vector<std::vector<std::vector<Sample>>> waterline_loops(const Sampler& s, const Box& box, const FinishParams& p,
                                                              bool into_corners) {
  const double g = std::min(tol::waterline_grid_mm, s.cutter().radius() / 2);
  const GridSpec grid = GridSpec::over(box.x0, box.y0, box.x1, box.y1, g);
  const std::vector<double> cl = cl_heights(s, grid.x0, grid.y0, grid.x1, grid.y1, grid.step, grid.nx, grid.ny);
  const double top = *std::max_element(cl.begin(), cl.end());
  std::vector<double> levels;
  const double estimate = std::floor((top - s.floor_z()) / p.step_down_mm);
  if (!(estimate <= tol::max_waterline_levels))
    throw Error("--step-down / /finish/step_down_mm: step-down " + format_double(p.step_down_mm) +
                " over a height of " + format_double(top - s.floor_z()) + " mm makes " + format_double(estimate) +
                " Z levels; at most " + format_double(tol::max_waterline_levels) + " (raise the step-down)");
  for (std::int64_t k = 1;; ++k) {
    const double z = top - static_cast<double>(k) * p.step_down_mm;
    if (!(z > s.floor_z() + tol::min_sample_mm)) break;
    levels.push_back(z);
  }
  const double tol = p.chord_tolerance_mm;
  std::vector<std::vector<std::vector<Sample>>> out(levels.size());
  const IsoField field(grid, cl);
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(levels.size()); ++k) {
    const double z = levels[static_cast<std::size_t>(k)];
    auto place = [&](const Eigen::Vector2d& in, const Eigen::Vector2d& outp, double v_in, double v_out, bool pad) {
      if (pad) return std::pair<Eigen::Vector2d, double>(in, 90.0);  // clipped at the boundary
      return refine_crossing(s, in, outp, v_in - z, v_out - z, z, tol);
    };
    auto loops = field.contours(z, place);
    auto& level_out = out[static_cast<std::size_t>(k)];
    for (auto& loop : loops) {
      split_gouging_chords(s, loop, z, tol);
      if (into_corners) {  // and the chords that makes checked again
        split_air_chords(s, loop, z, tol);
        split_gouging_chords(s, loop, z, tol, true);
      }
      std::reverse(loop.begin(), loop.end());  // material on the right: climb milling
      // Cut the loop open where it runs along the machining boundary.
      const auto first_pad =
          std::find_if(loop.begin(), loop.end(), [](const ContourPoint& c) { return c.on_boundary; });
      std::vector<Sample> pts;
      auto to_sample = [z](const ContourPoint& c) {
        Sample q;
        q.p = Eigen::Vector3d(c.xy.x(), c.xy.y(), z + c.lift);
        q.slope_deg = c.aux;
        return q;
      };
      if (first_pad == loop.end()) {
        for (const auto& c : loop) pts.push_back(to_sample(c));
        level_out.push_back(std::move(pts));
        continue;
      }
      loop.pop_back();  // open the ring, start at a boundary point
      std::rotate(loop.begin(), first_pad, loop.end());
      loop.push_back(loop.front());
      std::vector<Sample> piece;
      for (const auto& c : loop) {
        if (c.on_boundary) {
          if (piece.size() >= 2 && polyline_length(piece) >= tol::min_pass_mm) level_out.push_back(std::move(piece));
          piece.clear();
        } else {
          piece.push_back(to_sample(c));
        }
      }
    }
  }
  return out;
}

}  // namespace millnet::finish::detail
