#pragma once
// Private to the swept-cutter material removal (machine() in zmap.hpp): the kernels' form of the
// cutter and of a move, and the passes, one file each:
//   sweep.cpp             Sweeper::run, the table of contents; rows bucketed into chunks, the
//                         parallel sweep over them, each move's depth of cut
//   sweep_primitives.cpp  moves → swept primitives (lines, planar arcs, helix chords), link caps
//   sweep_shadow.cpp      the X spans of a row that a primitive's XY shadow covers
//   sweep_kernels.cpp     the exact envelopes per cutter shape and the choice of row kernel
//   sweep_vector_rows.cpp the branch-free (vectorised) rows of ball and flat lines
// The kernels of one primitive shape live in one translation unit with their helpers, as they did
// in one file before: the compiler's inlining (and so its FMA contraction) stays what it was, and
// with it the last bit of every height.
#include "millnet/simulate/tolerances.hpp"
#include "millnet/simulate/zmap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace millnet::simulate::sweep {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kTwoPi = 2 * std::numbers::pi;

/// The cutter as the kernels evaluate it (from a tooling::Cutter that passed its check()).
struct Profile {
  tooling::CutterType type = tooling::CutterType::Ball;  // the cutter's shape()
  double R = 1;                                          // radius
  double R2 = 1;
  double rc = 1;    // corner radius (ball: R, flat and drill: 0)
  double a = 0;     // flat part of the bottom: R − rc
  double cone = 0;  // drill: 1 / tan(point angle / 2)

  // f(r) for 0 ≤ r ≤ R (callers ensure r ≤ R).
  [[nodiscard]] double f(double r) const {
    switch (type) {
      case tooling::CutterType::Flat: return 0;
      case tooling::CutterType::Ball: return R - std::sqrt(std::max(0.0, R2 - r * r));
      case tooling::CutterType::Bull: {
        if (r <= a) return 0;
        const double u = r - a;
        return rc - std::sqrt(std::max(0.0, rc * rc - u * u));
      }
      case tooling::CutterType::Drill: return r * cone;
    }
    return 0;
  }
};

/// The kernels' form of a cutter; throws millnet::Error when the cutter fails its check().
Profile make_profile(const tooling::Cutter& c);

enum class SegType : std::uint8_t { Line, Arc };

/// A swept primitive: a line of the tool tip, or a planar arc (constant Z).
struct Seg {
  SegType type = SegType::Line;
  std::uint8_t kind = kLineKind;
  double ax = 0, ay = 0, az = 0, bx = 0, by = 0, bz = 0;
  // line: derived
  double dx = 0, dy = 0, dz = 0, L2 = 0, L = 0, ux = 0, uy = 0, m = 0, sq1m = 1, inv1m2 = 1;
  // The sphere at an end is applied by the neighbouring primitive (see link_caps).
  bool skip_start = false, skip_end = false;
  // planar arc
  double cx = 0, cy = 0, rho0 = 0, th0 = 0, sweep = 0, dir = 1;
  double zmin = 0;          // lowest tip height (no cell under it is lowered below it)
  double xlo = 0, xhi = 0;  // XY shadow bounding box
  double ylo = 0, yhi = 0;
  std::size_t item = 0;
  std::uint32_t serial = 0;
  std::size_t iy0 = 0, iy1 = 0;  // rows, inclusive
  std::size_t ix0 = 0, ix1 = 0;  // columns of the shadow box, inclusive
};

/// An X interval of a row, mm.
struct Span {
  double lo, hi;
};

/// Angle in [0, 2π).
inline double wrap(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

/// Whether the direction phi (rad) lies in the planar arc's sweep.
inline bool in_sweep(const Seg& g, double phi) { return wrap(g.dir * (phi - g.th0)) <= g.sweep; }

inline std::size_t clamp_index(double v, std::size_t n) {
  if (v < 0) return 0;
  if (v >= static_cast<double>(n)) return n;  // caller treats n as "past the end"
  return static_cast<std::size_t>(v);
}

/// Index range [first, last] of the cell centres within [lo, hi] (mm) of an axis starting at
/// `origin` with n cells of `cell` mm; false when empty.
inline bool cell_range(double lo, double hi, double origin, double cell, std::size_t n, std::size_t& first,
                       std::size_t& last) {
  const double a = std::ceil((lo - origin) / cell - 0.5 - tol::cell_range_slack_cells);
  const double b = std::floor((hi - origin) / cell - 0.5 + tol::cell_range_slack_cells);
  if (b < 0 || a > static_cast<double>(n) - 1 || a > b) return false;
  first = clamp_index(a, n);
  last = std::min(clamp_index(b, n), n - 1);
  return first <= last;
}

inline std::uint8_t kind_of(gcode::Motion m) {
  switch (m) {
    case gcode::Motion::Rapid: return kRapidKind;
    case gcode::Motion::Line: return kLineKind;
    default: return kArcKind;
  }
}

// ---- the passes -------------------------------------------------------------------------------

/// Pass 1 (sweep_primitives.cpp): the program's moves as swept primitives in program order, each
/// stamped with serial first_serial + item; fills `across` (per item, see ZMap::Pass) and the
/// move counts and path lengths of `res`. Throws millnet::Error on a non-finite coordinate or arc
/// centre, or an arc of zero radius.
std::vector<Seg> primitives(const gcode::Program& program, const Profile& P, const SweepOptions& opt,
                            std::uint32_t first_serial, std::vector<std::array<double, 3>>& across, SweepResult& res);

/// Hands the cutter at each joint of two consecutive primitives to one of them
/// (sweep_primitives.cpp).
void link_caps(std::vector<Seg>& segs);

/// Up to two X intervals of the row y covered by the primitive's shadow (a superset for arcs) for
/// a cutter of radius R (sweep_shadow.cpp).
int row_spans(const Seg& g, double R, double y, Span out[2]);

/// Upper bounds of the heights of a chunk of rows, one per block of kCells cells of a row
/// (sweep_vector_rows.cpp). A ball line leaves a row at once where no block under its shadow
/// stands above its floor there: most rows of a finishing pass, which the pass before has already
/// lowered below the next one's reach (s4's label: 124 M of 161 M row spans). Any kernel may lower
/// cells without telling (the bounds stay bounds); the ball line's kernel tightens the blocks it
/// lowers, so the bounds follow a pass.
struct RowTops {
  static constexpr std::size_t kCells = 32;
  std::vector<double> top;  // (row − row0) · blocks + block
  std::size_t row0 = 0, blocks = 0;
  std::uint64_t rows_left = 0;  // rows a ball line left at once
  /// The bounds of rows [r0, r1] from the heights z: each block's highest cell.
  void fill(const double* z, const GridSpec& spec, std::size_t r0, std::size_t r1);
  [[nodiscard]] double* row(std::size_t iy) { return top.data() + (iy - row0) * blocks; }
};

/// Lowers the cells of rows [row0, row1] (inclusive) under primitive g to its envelope, with the
/// kernel of its shape (sweep_kernels.cpp): stamps each lowered cell with g.serial, raises
/// item_cut to the largest height removed at a cell and item_engage to the largest axial
/// engagement (SweepResult::item_max_engage_mm), adds the cells evaluated to `visited`. `tops`
/// (nullable) bounds those rows' heights.
void sweep_rows(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t row0, std::size_t row1, double* z,
                std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited, RowTops* tops);

/// One row iy of a ball line with an XY direction, branch-free (sweep_vector_rows.cpp); `tops`
/// (nullable) bounds the row's heights and is kept a bound.
void ball_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited, RowTops* tops);

/// One row iy of a flat line with an XY direction, branch-free (sweep_vector_rows.cpp).
void flat_line_row(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, double* z,
                   std::uint32_t* stamp, double& item_cut, double& item_engage, std::uint64_t& visited);

/// The axial engagement of a line g (with an XY direction) over the cells [i0, i1] of row iy, whose
/// heights were `old` before it and are z now (sweep_vector_rows.cpp). O(cells).
double line_engagement(const Seg& g, const Profile& P, const GridSpec& spec, std::size_t iy, std::size_t i0,
                       std::size_t i1, const double* old, const double* z);

}  // namespace millnet::simulate::sweep
