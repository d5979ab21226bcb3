#pragma once
// Internal to finish/: CL sampling shared by the strategies (drop-cutter with a floor, adaptive
// sampling of a straight XY segment, one-sided simplification, the surface slope at a contact).
#include "millnet/finish/dropcutter.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/finish/tolerances.hpp"

#include <Eigen/Core>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstddef>
#include <vector>

namespace millnet::finish::detail {

/// A CL point with the slope of the surface under its contact (degrees from horizontal).
struct Sample {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double slope_deg = 0;
};

/// The machining box of tool-axis positions (mesh frame).
struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  [[nodiscard]] bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

/// The drop-cutter with the machine's floor under the part: where nothing lies under the cutter
/// (or the part is lower than its own lowest point, which cannot happen), the tip rests on
/// floor_z (the part's lowest z: the table the part stands on). Counts queries.
class Sampler {
public:
  Sampler(const ingest::Mesh& mesh, const DropCutter& dropper);
  [[nodiscard]] Sample sample(double x, double y) const;
  /// sample(x, y).p.z() without the slope.
  [[nodiscard]] double z(double x, double y) const;
  [[nodiscard]] const tooling::Cutter& cutter() const { return dropper_.cutter(); }
  [[nodiscard]] double floor_z() const { return floor_z_; }
  [[nodiscard]] double top_z() const { return top_z_; }
  /// Points asked for so far (read between parallel sections: the sum of the shards), those the
  /// memo answered included.
  [[nodiscard]] std::size_t drops() const;

private:
  [[nodiscard]] CLPoint drop(double x, double y) const;  // counted
  const ingest::Mesh& mesh_;
  const DropCutter& dropper_;
  double floor_z_ = 0, top_z_ = 0;
  std::uint64_t id_ = 0;  // this sampler's, unique in the process: its answers in the threads' memos
  // Counted in shards, one cache line each, a thread always in the same one: one shared counter
  // next to floor_z_ made every query of one thread evict the line the other was reading.
  struct alignas(64) Shard {
    std::atomic<std::size_t> n{0};
  };
  static constexpr std::size_t kShards = 16;
  mutable std::array<Shard, kShards> drops_{};
};

/// CL heights (floor applied) at the nodes x0 + j·step, y0 + i·step clamped to (x1, y1), rows = y;
/// parallel, deterministic.
[[nodiscard]] std::vector<double> cl_heights(const Sampler& s, double x0, double y0, double x1, double y1, double step,
                                             int nx, int ny);

/// CL points along the straight XY segment a→b (both ends included): first every ≤ h0, then each
/// interval halved while its midpoint (and, where the interval climbs more than 1 in 10 or the
/// contact slope turns by more than 5°, its quarter points) lies above the chord by more than
/// half of tol::chord_below_mm or
/// below it by more than `tol` (down to tol::min_sample_mm).
[[nodiscard]] std::vector<Sample> sample_segment(const Sampler& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                 double h0, double tol);

/// sample_segment along a chord a→b starting every |b − a| clamped to [0.001, 0.25] mm.
[[nodiscard]] std::vector<Sample> sample_chord(const Sampler& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                               double tol);

/// The polyline `line` (CL points) sampled between its points (sample_chord), split where a chord
/// rises: where a drop between two neighbours stands more than `rise` above the higher of them, the
/// chord has left the path the points trace (a pencil chain's crease, or aimed placements either
/// side of a ridge) onto the surface above — a pass there would climb it and come down again (seen
/// on test part s1's steep slopes: 2 mm up and down every tenth of a mm); that chord is left out.
/// O(points · samples per chord) drops.
[[nodiscard]] std::vector<std::vector<Sample>> rising_chords_split(const std::vector<Eigen::Vector3d>& line,
                                                                   const Sampler& s, double chord_tolerance_mm,
                                                                   double rise);

/// Drops interior points of a polyline whose removal keeps every dropped point within the
/// one-sided band [chord − tol, chord + tol::chord_below_mm] of the chord that replaces it
/// (vertical deviation for points on a straight XY line; 3D distance ≤ chord_below otherwise).
[[nodiscard]] std::vector<Sample> simplify(const std::vector<Sample>& pts, double tol, bool straight_xy);

/// Splits a polyline into the runs whose points satisfy keep(); runs shorter than
/// tol::min_pass_mm are dropped.
template <class Keep>
[[nodiscard]] std::vector<std::vector<Sample>> runs(const std::vector<Sample>& pts, Keep keep);

[[nodiscard]] double polyline_length(const std::vector<Sample>& pts);

/// 3D distance between neighbouring passes that keeps the scallop of the cutter on a plane at h:
/// flat bottom width 2(R − rc) plus the chord of the corner circle at depth h. Scallop mode's
/// passes start at this spacing (and its work estimate counts them at it, work.cpp).
[[nodiscard]] double scallop_spacing(const tooling::Cutter& c, double h);

/// The five strategies' pass generators (sampling.cpp, raster.cpp, waterline.cpp, equidistant.cpp).
std::vector<Pass> to_passes(std::vector<std::vector<Sample>> lines);
[[nodiscard]] std::vector<std::vector<Sample>> raster_lines(const Sampler& s, const Box& box, const FinishParams& p,
                                                            bool adaptive_spacing);
/// `into_corners`: chords that cut across an inside corner of the level (a concave crease of a wall,
/// where the contour turns into the material between two crossings) are split too, by a refined
/// point, until none lies more than the chord tolerance off the contour on the air side (rest
/// finishing's Z-levels: the material left in such a corner is what they are for).
[[nodiscard]] std::vector<std::vector<std::vector<Sample>>> waterline_loops(const Sampler& s, const Box& box,
                                                                            const FinishParams& p,
                                                                            bool into_corners = false);
/// `from_polygons`: the distance is measured from p.boundary's polygons too (nodes outside them are
/// sources), so that the loops run along a region's outline (rest finishing's corner passes).
[[nodiscard]] std::vector<std::vector<std::vector<Sample>>> equidistant_loops(const Sampler& s, const Box& box,
                                                                              const FinishParams& p,
                                                                              bool from_polygons = false);
/// Strategy 1's steep pieces: of each Z-level loop, the runs steeper than the boundary angle less
/// the overlap (a closed loop started at a shallow point so that no piece wraps).
[[nodiscard]] std::vector<std::vector<std::vector<Sample>>> steep_pieces(
    std::vector<std::vector<std::vector<Sample>>> levels, const FinishParams& p);
/// Orders loops grouped by level (outer index: level, top-down / outside-in): after a loop, the
/// nearest loop of the next level within `near_mm`, else the nearest loop of the highest level
/// left; closed loops (last point = first point) start at their point nearest to the tool, open
/// passes keep their start (and so their cutting direction).
[[nodiscard]] std::vector<std::vector<Sample>> order_by_level(std::vector<std::vector<std::vector<Sample>>> levels,
                                                              double near_mm);
[[nodiscard]] inline bool is_closed(const std::vector<Sample>& c) {
  return c.size() > 2 && (c.front().p - c.back().p).norm() < 1e-12;
}

class Fence;
/// The linked program (linking.cpp); fills plan.program, path_length_mm, lifts, cl_points. A short
/// link stays down only when every point of it is inside the fence.
void link_passes(const Sampler& s, const FinishParams& p, const Fence& fence, FinishPlan& plan);

template <class Keep>
std::vector<std::vector<Sample>> runs(const std::vector<Sample>& pts, Keep keep) {
  std::vector<std::vector<Sample>> out;
  std::vector<Sample> cur;
  auto flush = [&] {
    if (cur.size() >= 2 && polyline_length(cur) >= tol::min_pass_mm) out.push_back(std::move(cur));
    cur.clear();
  };
  for (const Sample& q : pts) {
    if (keep(q)) {
      cur.push_back(q);
    } else {
      flush();
    }
  }
  flush();
  return out;
}

}  // namespace millnet::finish::detail
