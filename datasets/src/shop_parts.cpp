#include "millnet/datasets/shop_parts.hpp"

#include "height_solid.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/rng.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace millnet::datasets {
namespace fs = std::filesystem;

namespace shop {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kAspectMax = 1.8;  // longer side / shorter side at most

// ---- planar shapes: signed distance in mm, positive inside ----

// Rounded rectangle centred at (cx, cy), half sides hx, hy, corner radius r, turned by yaw (rad).
struct Box {
  double cx, cy, hx, hy, r, yaw = 0;
  [[nodiscard]] double inside(double x, double y) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double u = c * (x - cx) + s * (y - cy), v = -s * (x - cx) + c * (y - cy);
    const double qx = std::abs(u) - (hx - r), qy = std::abs(v) - (hy - r);
    return -(std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0) - r);
  }
};

struct Disc {
  double cx, cy, r;
  [[nodiscard]] double inside(double x, double y) const { return r - std::hypot(x - cx, y - cy); }
};

// A straight rib of width w between (x0, y0) and (x1, y1), round-ended (a capsule).
struct Rib {
  double x0, y0, x1, y1, w;
  [[nodiscard]] double inside(double x, double y) const {
    const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    const double t = len2 > 0 ? std::clamp(((x - x0) * dx + (y - y0) * dy) / len2, 0.0, 1.0) : 0.0;
    return w / 2 - std::hypot(x - (x0 + t * dx), y - (y0 + t * dy));
  }
};

// A uniform bicubic B-spline height field over [x0,x1]×[y0,y1] (clamped outside): nx × ny control
// heights, nx, ny ≥ 4 (nx − 3 spans along x). C² everywhere.
struct BSpline {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  int nx = 4, ny = 4;
  std::vector<double> p;  // row-major, row = y

  static std::array<double, 4> basis(double s) {
    const double s2 = s * s, s3 = s2 * s, m = 1 - s;
    return {m * m * m / 6, (3 * s3 - 6 * s2 + 4) / 6, (-3 * s3 + 3 * s2 + 3 * s + 1) / 6, s3 / 6};
  }
  static void span(double v, double lo, double hi, int n, int& k, double& s) {
    const double t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0) * (n - 3);
    k = std::min(static_cast<int>(t), n - 4);
    s = t - k;
  }
  [[nodiscard]] double operator()(double x, double y) const {
    int kx = 0, ky = 0;
    double sx = 0, sy = 0;
    span(x, x0, x1, nx, kx, sx);
    span(y, y0, y1, ny, ky, sy);
    const auto bx = basis(sx), by = basis(sy);
    double z = 0;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j)
        z += by[i] * bx[j] *
             p[static_cast<std::size_t>(ky + static_cast<int>(i)) * static_cast<std::size_t>(nx) +
               static_cast<std::size_t>(kx) + j];
    return z;
  }
};

// Control heights uniform in [lo, hi]; the surface stays inside that range (convex hull property).
// Control heights drawn at random, then scaled so that the surface itself spans [lo, hi] (sampled on
// a 33 × 33 grid; a B-spline is affine-invariant in its control points).
BSpline random_bspline(SplitMix64& rng, double x0, double x1, double y0, double y1, int n_lo, int n_hi, double lo,
                       double hi) {
  BSpline f;
  f.x0 = x0, f.x1 = x1, f.y0 = y0, f.y1 = y1;
  f.nx = rng.uniform_int(n_lo, n_hi);
  f.ny = rng.uniform_int(n_lo, n_hi);
  f.p.resize(static_cast<std::size_t>(f.nx * f.ny));
  for (double& v : f.p) v = rng.uniform();
  double smin = HUGE_VAL, smax = -HUGE_VAL;
  for (int i = 0; i <= 32; ++i)  // O(33²)
    for (int j = 0; j <= 32; ++j) {
      const double v = f(x0 + (x1 - x0) * j / 32, y0 + (y1 - y0) * i / 32);
      smin = std::min(smin, v);
      smax = std::max(smax, v);
    }
  const double k = smax > smin ? (hi - lo) / (smax - smin) : 0.0;
  for (double& v : f.p) v = lo + (v - smin) * k;
  return f;
}

// A drafted, filleted wall: its height and shape.
struct Wall {
  double h, draft_deg, r_foot, r_top;
  [[nodiscard]] double at(double d) const { return detail::filleted_step(d, h, draft_deg, r_foot, r_top); }
};

struct Frame {
  double a, b;       // footprint sides
  double L, margin;  // the shorter side; features keep this far from the edge
};

Frame footprint(SplitMix64& rng) {
  const double a = std::exp(rng.uniform(std::log(kShopSideMinMm), std::log(kShopSideMaxMm)));
  const double b = std::clamp(a * std::exp(rng.uniform(-std::log(kAspectMax), std::log(kAspectMax))), kShopSideMinMm,
                              kShopSideMaxMm);
  const double L = std::min(a, b);
  return {a, b, L, std::max(3.0, 0.08 * L)};
}

// A box roughly centred in the footprint, half sides a fraction of the footprint's.
Box centred_box(SplitMix64& rng, const Frame& fr, double lo, double hi, double shift = 0.05) {
  Box q{fr.a / 2 + rng.uniform(-shift, shift) * fr.a, fr.b / 2 + rng.uniform(-shift, shift) * fr.b,
        rng.uniform(lo, hi) * fr.a, rng.uniform(lo, hi) * fr.b, 0};
  q.r = std::max(1.0, rng.uniform(0.1, 1.0) * std::min(q.hx, q.hy));
  return q;
}

double scaled(SplitMix64& rng, const Frame& fr, double lo, double hi, double min_mm, double max_mm) {
  return std::clamp(rng.uniform(lo, hi) * fr.L, min_mm, max_mm);
}

using Height = detail::HeightFn;

struct Design {
  Frame fr;
  std::string kind;
  Height z;
};

// ---- the eight families (mm, degrees) ----

Design cavity(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const Box q = centred_box(rng, fr, 0.25, 0.4);
  const double depth = scaled(rng, fr, 0.15, 0.45, 4, 38);
  const Wall wall{depth, rng.uniform(1, 7), rng.uniform(0, 2), rng.uniform(1, std::clamp(depth / 3, 1.0, 6.0))};
  const bool freeform_floor = index % 2 == 1;
  const BSpline floor = random_bspline(rng, q.cx - q.hx, q.cx + q.hx, q.cy - q.hy, q.cy + q.hy, 4, 6, 0,
                                       freeform_floor ? 0.35 * depth : 0.0);
  const bool island = index % 3 == 2;
  Box core{q.cx + rng.uniform(-0.1, 0.1) * q.hx, q.cy + rng.uniform(-0.1, 0.1) * q.hy, rng.uniform(0.2, 0.4) * q.hx,
           rng.uniform(0.2, 0.4) * q.hy, 0};
  core.r = std::max(1.0, rng.uniform(0.2, 1.0) * std::min(core.hx, core.hy));
  const Wall core_wall{rng.uniform(0.3, 0.9) * depth, rng.uniform(1, 5), rng.uniform(0.5, 3), rng.uniform(0.5, 2)};
  std::string kind = freeform_floor ? "cavity_freeform_floor" : "cavity_flat_floor";
  if (island) kind += "_core";
  return {fr, kind, [=](double x, double y) {
            const double s = wall.at(q.inside(x, y));  // 0 on the top, depth on the floor
            double z = -s + floor(x, y) * s / depth;
            if (island) z = std::max(z, -depth + core_wall.at(core.inside(x, y)));
            return z;
          }};
}

Design core(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const Box q = centred_box(rng, fr, 0.2, 0.36);
  const double h = scaled(rng, fr, 0.12, 0.4, 4, 36);
  const Wall wall{h, rng.uniform(1, 8), rng.uniform(1, 5), rng.uniform(0.5, 4)};
  const int top = index % 3;  // 0 flat, 1 domed, 2 a shallow pocket in the top
  const BSpline dome =
      random_bspline(rng, q.cx - q.hx, q.cx + q.hx, q.cy - q.hy, q.cy + q.hy, 4, 5, 0, std::min(0.25 * h, 38 - h));
  Box pocket{q.cx, q.cy, rng.uniform(0.4, 0.65) * q.hx, rng.uniform(0.4, 0.65) * q.hy, 0};
  pocket.r = std::max(1.0, rng.uniform(0.3, 1.0) * std::min(pocket.hx, pocket.hy));
  const Wall pocket_wall{rng.uniform(0.2, 0.5) * h, rng.uniform(1, 5), rng.uniform(0, 1), rng.uniform(0.5, 2)};
  const bool second = index % 5 >= 3;
  const double sx = rng.uniform() < 0.5 ? fr.margin : fr.a - fr.margin,
               sy = rng.uniform() < 0.5 ? fr.margin : fr.b - fr.margin;
  const double sr = rng.uniform(0.06, 0.1) * fr.L;
  const Disc boss{sx + (sx < fr.a / 2 ? sr : -sr), sy + (sy < fr.b / 2 ? sr : -sr), sr};
  const Wall boss_wall{rng.uniform(0.3, 0.8) * h, rng.uniform(1, 5), rng.uniform(0.5, 2), rng.uniform(0.3, 1)};
  static const char* const kinds[] = {"core_flat_top", "core_domed", "core_pocketed_top"};
  return {fr, std::string(kinds[top]) + (second ? "_second_boss" : ""), [=](double x, double y) {
            const double s = wall.at(q.inside(x, y));
            double z = s;
            if (top == 1) z += dome(x, y) * s / h;
            if (top == 2) z -= pocket_wall.at(pocket.inside(x, y));
            if (second) z = std::max(z, boss_wall.at(boss.inside(x, y)));
            return z;
          }};
}

Design ribbed_plate(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const double w = rng.uniform(2.5, 6), h = scaled(rng, fr, 0.08, 0.25, 4, 25);
  const bool rounded = rng.uniform() < 0.5;
  const Wall wall{h, rng.uniform(0.5, 2), rng.uniform(0.5, 2), rounded ? w / 2 : 0.3};
  std::vector<Rib> ribs;
  const double m = fr.margin + w;
  const bool grid = index % 2 == 1;
  // Ribs at least a rib's width, its walls and fillets and 6 mm of floor apart (room for the cutter).
  const double pitch = w + 2 * (h * std::tan(wall.draft_deg * kDegree) + wall.r_foot) + 6;
  const int room = std::max(1, static_cast<int>((fr.L - 2 * m) / pitch) - 1);
  const int n = std::min(rng.uniform_int(2, 5), room);
  const bool along_x = rng.uniform() < 0.5;
  for (int k = 0; k < n; ++k) {
    const double t = (k + 1.0) / (n + 1.0);
    if (along_x || grid) ribs.push_back({m, m + t * (fr.b - 2 * m), fr.a - m, m + t * (fr.b - 2 * m), w});
    if (!along_x || grid) ribs.push_back({m + t * (fr.a - 2 * m), m, m + t * (fr.a - 2 * m), fr.b - m, w});
  }
  const bool frame = index % 3 == 0;
  const Box outline{fr.a / 2, fr.b / 2, fr.a / 2 - fr.margin, fr.b / 2 - fr.margin, std::min(fr.margin, 0.2 * fr.L)};
  return {fr, std::string(grid ? "ribs_grid" : "ribs_parallel") + (frame ? "_frame" : ""), [=](double x, double y) {
            double d = -HUGE_VAL;
            for (const Rib& r : ribs) d = std::max(d, r.inside(x, y));
            if (frame) d = std::max(d, w / 2 - std::abs(outline.inside(x, y)));
            return wall.at(d);
          }};
}

Design bored_plate(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  struct Bore {
    Disc hole;
    Wall wall;
    Disc counter;
    Wall counter_wall;
    bool counterbored;
  };
  std::vector<Disc> taken;  // every round feature placed, with its clearance
  auto place = [&](double r, Disc& out) {
    for (int attempt = 0; attempt < 64; ++attempt) {
      const Disc c{rng.uniform(fr.margin + r, fr.a - fr.margin - r), rng.uniform(fr.margin + r, fr.b - fr.margin - r),
                   r};
      const bool clear = std::none_of(taken.begin(), taken.end(), [&](const Disc& t) {
        return std::hypot(c.cx - t.cx, c.cy - t.cy) < c.r + t.r + 3;
      });
      if (clear) {
        taken.push_back(c);
        out = c;
        return true;
      }
    }
    return false;
  };
  const bool with_pocket = index % 2 == 0;
  Box pocket{fr.a * rng.uniform(0.35, 0.65), fr.b * rng.uniform(0.35, 0.65), rng.uniform(0.12, 0.22) * fr.a,
             rng.uniform(0.12, 0.22) * fr.b, 0};
  pocket.r = std::max(1.0, rng.uniform(0.2, 1.0) * std::min(pocket.hx, pocket.hy));
  const Wall pocket_wall{rng.uniform(3, 12), rng.uniform(0.5, 3), rng.uniform(0, 1), rng.uniform(0.5, 3)};
  if (with_pocket) taken.push_back({pocket.cx, pocket.cy, std::hypot(pocket.hx, pocket.hy)});
  std::vector<Bore> bores;
  const int n_bores = rng.uniform_int(2, 8);
  for (int k = 0; k < n_bores; ++k) {
    const double r = rng.uniform(2, std::min(10.0, 0.06 * fr.L + 2));
    const double depth = rng.uniform(4, std::min(30.0, 0.3 * fr.L + 6));
    Bore b{{}, {depth, 0.5, rng.uniform(0.3, 1.0), rng.uniform(0, 0.5)}, {}, {}, rng.uniform() < 0.4};
    const double outer = b.counterbored ? rng.uniform(1.6, 1.8) * r : r;
    if (!place(outer, b.counter)) continue;
    b.hole = {b.counter.cx, b.counter.cy, r};
    b.counter_wall = {rng.uniform(0.25, 0.4) * depth, 0.5, b.wall.r_foot, 0};
    bores.push_back(b);
  }
  std::vector<std::pair<Disc, Wall>> bosses;
  const int n_bosses = index % 5 < 2 ? rng.uniform_int(1, 2) : 0;
  for (int k = 0; k < n_bosses; ++k) {
    Disc d{};
    if (place(rng.uniform(0.05, 0.09) * fr.L + 2, d))
      bosses.emplace_back(d, Wall{rng.uniform(3, 10), rng.uniform(1, 5), rng.uniform(0.5, 2), rng.uniform(0.3, 1.5)});
  }
  return {fr, std::string(with_pocket ? "bores_pocket" : "bores") + (bosses.empty() ? "" : "_bosses"),
          [=](double x, double y) {
            // The deepest cut (pocket, bore) where there is one; elsewhere the plate and its bosses.
            double cut = with_pocket ? pocket_wall.at(pocket.inside(x, y)) : 0.0;
            for (const Bore& b : bores) {
              if (b.counterbored) {  // the counterbore's step, and the bore below it (inside the counterbore)
                const Wall below{b.wall.h - b.counter_wall.h, 0.5, 0.2, b.wall.r_top};
                cut = std::max(cut, b.counter_wall.at(b.counter.inside(x, y)) + below.at(b.hole.inside(x, y)));
              } else {
                cut = std::max(cut, b.wall.at(b.hole.inside(x, y)));
              }
            }
            if (cut > 0) return -cut;
            double z = 0;
            for (const auto& [disc, wall] : bosses) z = std::max(z, wall.at(disc.inside(x, y)));
            return z;
          }};
}

Design freeform_surface(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const double amp = scaled(rng, fr, 0.08, 0.3, 3, 30);
  const int lo = index % 2 == 0 ? 4 : 5, hi = index % 2 == 0 ? 5 : 7;
  const BSpline f = random_bspline(rng, 0, fr.a, 0, fr.b, lo, hi, 0, amp);
  return {fr, index % 2 == 0 ? "freeform_smooth" : "freeform_wavy", [=](double x, double y) { return f(x, y); }};
}

Design freeform_pocket(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const int n = 1 + index % 3;
  const bool along_x = fr.a >= fr.b;
  struct Pocket {
    Box q;
    Wall wall;
    BSpline floor;
  };
  std::vector<Pocket> pockets;
  const double span = (along_x ? fr.a : fr.b) - 2 * fr.margin;
  for (int k = 0; k < n; ++k) {
    const double c = fr.margin + span * (k + 0.5) / n;
    const double h_along = (span / n) * rng.uniform(0.3, 0.42);
    const double h_across = ((along_x ? fr.b : fr.a) / 2 - fr.margin) * rng.uniform(0.6, 0.95);
    Box q = along_x ? Box{c, fr.b / 2, h_along, h_across, 0} : Box{fr.a / 2, c, h_across, h_along, 0};
    q.r = std::max(1.0, rng.uniform(0.15, 1.0) * std::min(q.hx, q.hy));
    const double depth = scaled(rng, fr, 0.15, 0.4, 4, 30);
    const Wall wall{depth, rng.uniform(1, 5), rng.uniform(0, 1.5), rng.uniform(1, std::clamp(depth / 3, 1.0, 4.0))};
    pockets.push_back({q, wall,
                       random_bspline(rng, q.cx - q.hx, q.cx + q.hx, q.cy - q.hy, q.cy + q.hy, 4, 6, 0,
                                      rng.uniform(0.2, 0.6) * depth)});
  }
  return {fr, "freeform_pockets_" + std::to_string(n), [=](double x, double y) {
            double z = 0;
            for (const Pocket& p : pockets) {
              const double s = p.wall.at(p.q.inside(x, y));
              z = std::min(z, -s + p.floor(x, y) * s / p.wall.h);
            }
            return z;
          }};
}

Design steep_shallow_blend(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const BSpline base = random_bspline(rng, 0, fr.a, 0, fr.b, 4, 5, 0, std::clamp(0.1 * fr.L, 2.0, 10.0));
  const double h = scaled(rng, fr, 0.1, 0.3, 5, 24);
  const Wall scarp{h, rng.uniform(2, 20), rng.uniform(2, 8), rng.uniform(2, 8)};
  const BSpline top = random_bspline(rng, 0, fr.a, 0, fr.b, 4, 5, 0, std::min(5.0, 0.05 * fr.L + 1));
  // The scarp: a wavy line across the part (index even) or a closed rounded outline (odd).
  const double yaw = rng.uniform(0, 2 * std::numbers::pi);
  const double nx = std::cos(yaw), ny = std::sin(yaw);
  const double offset = rng.uniform(-0.15, 0.15) * fr.L, wave = rng.uniform(0.02, 0.06) * fr.L,
               lambda = rng.uniform(0.5, 1.0) * fr.L, phase = rng.uniform(0, 2 * std::numbers::pi);
  const bool closed = index % 2 == 1;
  Box island = centred_box(rng, fr, 0.22, 0.36, 0.12);
  island.r = std::min(island.hx, island.hy) * rng.uniform(0.6, 1.0);
  return {fr, closed ? "blend_raised_island" : "blend_scarp", [=](double x, double y) {
            const double u = (x - fr.a / 2) * nx + (y - fr.b / 2) * ny, v = -(x - fr.a / 2) * ny + (y - fr.b / 2) * nx;
            const double d =
                closed ? island.inside(x, y) : u - offset + wave * std::sin(2 * std::numbers::pi * v / lambda + phase);
            const double s = scarp.at(d);
            return base(x, y) + s + top(x, y) * s / h;
          }};
}

Design terraced_core(SplitMix64& rng, int index) {
  const Frame fr = footprint(rng);
  const int wanted = 2 + index % 3;
  const double budget = std::clamp(0.35 * fr.L, 8.0, 36.0);
  std::vector<Wall> walls;
  for (int k = 0; k < wanted; ++k)
    walls.push_back({std::min(budget / wanted * rng.uniform(0.6, 1.0), 12.0), rng.uniform(1, 10), rng.uniform(0.5, 3),
                     rng.uniform(0.3, 2)});
  std::vector<std::pair<Box, Wall>> steps;
  Box q = centred_box(rng, fr, 0.3, 0.42);
  steps.emplace_back(q, walls[0]);
  for (std::size_t k = 1; k < walls.size(); ++k) {
    // A flat ring of ≥ 1.5 mm between the level below's top fillet and this level's foot fillet.
    const Wall& below = walls[k - 1];
    const double gap = below.h * std::tan(below.draft_deg * kDegree) + below.r_top + walls[k].r_foot + 1.5;
    Box inner = q;
    inner.hx = std::min(q.hx * rng.uniform(0.55, 0.8), q.hx - gap);
    inner.hy = std::min(q.hy * rng.uniform(0.55, 0.8), q.hy - gap);
    if (std::min(inner.hx, inner.hy) < 3) break;  // no room for another level
    inner.cx = q.cx + rng.uniform(-1, 1) * 0.3 * (q.hx - gap - inner.hx);
    inner.cy = q.cy + rng.uniform(-1, 1) * 0.3 * (q.hy - gap - inner.hy);
    inner.r = std::max(1.0, std::min(q.r, std::min(inner.hx, inner.hy)) * rng.uniform(0.5, 1.0));
    q = inner;
    steps.emplace_back(q, walls[k]);
  }
  const auto levels = steps.size();
  return {fr, "terraces_" + std::to_string(levels), [=](double x, double y) {
            double z = 0, below = 0;
            for (const auto& [box, wall] : steps) {  // a level stands on the one below, inside its outline only
              const double s = wall.at(box.inside(x, y));
              if (s > 0) z = std::max(z, below + s);
              below += wall.h;
            }
            return z;
          }};
}

}  // namespace
}  // namespace shop

namespace detail {

double filleted_step(double d, double h, double draft_deg, double r_foot, double r_top) {
  const double phi = (90.0 - std::clamp(draft_deg, 0.5, 89.0)) * shop::kDegree;  // the wall's angle to the horizontal
  const double slope = std::tan(phi), run = h / slope, half = std::tan(phi / 2);
  double t1 = std::max(r_foot, 0.0) * half, t2 = std::max(r_top, 0.0) * half;
  const double wall_len = h / std::sin(phi);
  if (t1 + t2 > wall_len) {  // both fillets cannot fit: shrink them together
    const double k = wall_len / (t1 + t2);
    t1 *= k;
    t2 *= k;
  }
  const double r1 = t1 / half, r2 = t2 / half, c = std::cos(phi);
  if (d <= -t1) return 0;
  if (d < t1 * c) return r1 - std::sqrt(std::max(r1 * r1 - (d + t1) * (d + t1), 0.0));
  if (d <= run - t2 * c) return d * slope;
  if (d < run + t2) return h - r2 + std::sqrt(std::max(r2 * r2 - (d - run - t2) * (d - run - t2), 0.0));
  return h;
}

}  // namespace detail

std::string shop_family_name(ShopFamily f) {
  switch (f) {
    case ShopFamily::Cavity: return "cavity";
    case ShopFamily::Core: return "core";
    case ShopFamily::RibbedPlate: return "ribbed_plate";
    case ShopFamily::BoredPlate: return "bored_plate";
    case ShopFamily::FreeformSurface: return "freeform_surface";
    case ShopFamily::FreeformPocket: return "freeform_pocket";
    case ShopFamily::SteepShallowBlend: return "steep_shallow_blend";
    case ShopFamily::TerracedCore: return "terraced_core";
  }
  throw Error("unknown shop part family " + std::to_string(static_cast<int>(f)));
}

ShopFamily shop_family_of(int k) { return static_cast<ShopFamily>(k % kShopFamilies); }

GeneratedMesh make_shop_part(int k, std::uint64_t seed, double spacing_mm) {
  if (k < 0) throw Error("shop part generator: part index must be ≥ 0, got " + std::to_string(k));
  if (!(spacing_mm >= 0.1 && spacing_mm <= 5))
    throw Error("shop part generator: spacing must be in [0.1, 5] mm, got " + std::to_string(spacing_mm));
  SplitMix64 rng(
      SplitMix64::mix(seed ^ SplitMix64::mix(static_cast<std::uint64_t>(k) + std::uint64_t{0x5B0F9A77C3D2E611})));
  const int index = k / kShopFamilies;
  shop::Design d;
  switch (shop_family_of(k)) {
    case ShopFamily::Cavity: d = shop::cavity(rng, index); break;
    case ShopFamily::Core: d = shop::core(rng, index); break;
    case ShopFamily::RibbedPlate: d = shop::ribbed_plate(rng, index); break;
    case ShopFamily::BoredPlate: d = shop::bored_plate(rng, index); break;
    case ShopFamily::FreeformSurface: d = shop::freeform_surface(rng, index); break;
    case ShopFamily::FreeformPocket: d = shop::freeform_pocket(rng, index); break;
    case ShopFamily::SteepShallowBlend: d = shop::steep_shallow_blend(rng, index); break;
    case ShopFamily::TerracedCore: d = shop::terraced_core(rng, index); break;
  }
  const double plinth = rng.uniform(5, 10);
  const int res_x = std::max(8, static_cast<int>(std::lround(d.fr.a / spacing_mm)) + 1);
  const int res_y = std::max(8, static_cast<int>(std::lround(d.fr.b / spacing_mm)) + 1);
  GeneratedMesh g = detail::height_field_solid(d.fr.a, d.fr.b, res_x, res_y, plinth, d.z);
  g.kind = d.kind;
  return g;
}

std::vector<GeneratedPart> generate_shop_parts(const fs::path& dir, std::uint64_t seed, int count, double spacing_mm) {
  if (count < 1) throw Error("shop part generator: count must be ≥ 1, got " + std::to_string(count));
  std::vector<GeneratedPart> parts;
  std::string list = "name,file,label\n";
  for (int k = 0; k < count; ++k) {  // O(count · a·b / spacing²)
    char name[96];
    std::snprintf(name, sizeof name, "shop_%04d_%s", k + 1, shop_family_name(shop_family_of(k)).c_str());
    const GeneratedMesh g = make_shop_part(k, seed, spacing_mm);
    const fs::path file = dir / (std::string(name) + ".stl");
    ingest::save_stl_binary(
        g.mesh, file, "millnet tool-shop part " + std::string(name) + " seed " + std::to_string(seed) + " " + g.kind);
    parts.push_back({name, file, 0});
    list += std::string(name) + "," + name + ".stl,0\n";
  }
  write_file_atomic(dir / "parts.csv", list);
  return parts;
}

}  // namespace millnet::datasets
