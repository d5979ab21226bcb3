#include "millnet/datasets/generator.hpp"

#include "height_solid.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/rng.hpp"
#include "millnet/datasets/shop_parts.hpp"
#include "millnet/datasets/tolerances.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

namespace millnet::datasets {
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kSideMinMm = 100.0, kSideMaxMm = 130.0;  // footprint sides a, b

// Rounded rectangle; inside(x, y) is the signed distance to its outline, positive inside (mm).
struct RRect {
  double cx, cy, hx, hy, r;
  [[nodiscard]] double inside(double x, double y) const {
    const double qx = std::abs(x - cx) - (hx - r);
    const double qy = std::abs(y - cy) - (hy - r);
    const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0) - r;
    return -outside;
  }
};

// 0 outside, rising linearly over a horizontal run w (the wall's draft), 1 inside.
double ramp(double d, double w) { return std::clamp(d / std::max(w, tol::min_wall_run_mm), 0.0, 1.0); }

double gauss(double dx, double dy, double sigma) { return std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma)); }

// Wall run of a wall of height h with draft angle `draft_deg` from the vertical.
double wall_run(double h, double draft_deg) { return h * std::tan(draft_deg * kDeg); }

using HeightFn = detail::HeightFn;

GeneratedMesh solid(double a, double b, int res, double plinth, const HeightFn& f) {
  return detail::height_field_solid(a, b, res, res, plinth, f);
}

// ---- the five families (parameters in mm and degrees; ranges are the README's) ----
// Within a family the characteristic feature keeps its place and topology (a centred plateau, a
// centred pocket, a ridge along x, …) while sizes, heights, drafts, radii and offsets vary: the
// classifier compares whole 15×15 grids, so a family whose features sat at random places would be
// farther from its own members than from a featureless plane (README, "Why the families are compact").

// Footprint sides (mm): one range for every family, so that size never tells the families apart.
double side(SplitMix64& rng) { return rng.uniform(kSideMinMm, kSideMaxMm); }

GeneratedMesh steep_plateaus(SplitMix64& rng, int index, int res) {
  const double a = side(rng), b = side(rng), plinth = rng.uniform(6, 10);
  struct Pad {
    RRect q;
    double h, w;
  };
  std::vector<Pad> pads;
  RRect q{a / 2 + rng.uniform(-0.08, 0.08) * a, b / 2 + rng.uniform(-0.08, 0.08) * b, rng.uniform(0.24, 0.32) * a,
          rng.uniform(0.24, 0.32) * b, 0};
  q.r = rng.uniform(0, 0.4) * std::min(q.hx, q.hy);
  const bool terraces = index % 2 == 1;
  if (!terraces) {  // one plateau with (near-)vertical walls on the flat base
    const double h = rng.uniform(14, 22);
    pads.push_back({q, h, wall_run(h, rng.uniform(0, 3))});
  } else {  // stepped terraces: a smaller level on top of the first
    const double h1 = rng.uniform(10, 14);
    pads.push_back({q, h1, wall_run(h1, rng.uniform(0, 3))});
    RRect inner = q;
    inner.hx = q.hx * rng.uniform(0.45, 0.6);
    inner.hy = q.hy * rng.uniform(0.45, 0.6);
    inner.cx = q.cx + rng.uniform(-1, 1) * 0.3 * (q.hx - inner.hx);
    inner.cy = q.cy + rng.uniform(-1, 1) * 0.3 * (q.hy - inner.hy);
    inner.r = std::min(q.r, std::min(inner.hx, inner.hy));
    const double h2 = rng.uniform(8, 12);
    pads.push_back({inner, h1 + h2, wall_run(h2, rng.uniform(0, 3))});
  }
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    double z = 0;
    for (const Pad& p : pads) z = std::max(z, p.h * ramp(p.q.inside(x, y), p.w));
    return z;
  });
  g.kind = terraces ? "terraces" : "plateau";
  return g;
}

GeneratedMesh gentle_freeform(SplitMix64& rng, int index, int res) {
  const double a = side(rng), b = side(rng), plinth = rng.uniform(8, 12);
  const bool saddle = index % 2 == 1;
  const double cx = a / 2 + rng.uniform(-0.08, 0.08) * a, cy = b / 2 + rng.uniform(-0.08, 0.08) * b;
  const double sx = rng.uniform(0.26, 0.34) * a, sy = rng.uniform(0.26, 0.34) * b;
  const double amp = saddle ? rng.uniform(7, 10) : rng.uniform(10, 15);
  // A small secondary bump anywhere: free-form parts are never perfectly symmetric.
  const double bx = rng.uniform(0.2, 0.8) * a, by = rng.uniform(0.2, 0.8) * b, bs = rng.uniform(15, 25);
  const double bh = rng.uniform(2, 4) * rng.sign();
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    const double u = (x - cx) / (a / 2), v = (y - cy) / (b / 2);
    const double main =
        saddle ? amp * (u * u - v * v)
               : amp * std::exp(-0.5 * ((x - cx) * (x - cx) / (sx * sx) + (y - cy) * (y - cy) / (sy * sy)));
    return main + bh * gauss(x - bx, y - by, bs);
  });
  g.kind = saddle ? "saddle" : "dome";
  return g;
}

GeneratedMesh varying_curvature(SplitMix64& rng, int index, int res) {
  const double a = side(rng), b = side(rng), plinth = rng.uniform(6, 10);
  // The sharp end at x = 0 or x = a: the augmentation's 180° flip maps one onto the other.
  const bool sharp_first = rng.uniform() < 0.5;
  const double y0 = b / 2 + rng.uniform(-0.06, 0.06) * b, bend = rng.uniform(-0.06, 0.06) * b;
  const double w_sharp = rng.uniform(2.5, 4.0), w_flat = rng.uniform(20, 28), h = rng.uniform(22, 32);
  const bool twin = index % 2 == 1;  // a second, lower ridge of constant medium width beside it
  const double y1 = b * (rng.uniform() < 0.5 ? 0.22 : 0.78), h1 = rng.uniform(8, 12), w1 = rng.uniform(6, 10);
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    const double s = x / a;
    const double t = sharp_first ? s : 1 - s;
    const double w = w_sharp + (w_flat - w_sharp) * t;  // cross-section radius grows along the ridge
    const double d = y - (y0 + bend * std::sin(std::numbers::pi * s));
    double z = h * std::exp(-d * d / (2 * w * w));
    if (twin) z = std::max(z, h1 * std::exp(-(y - y1) * (y - y1) / (2 * w1 * w1)));
    return z;
  });
  g.kind = twin ? "ridge_pair" : "ridge";
  return g;
}

GeneratedMesh deep_cavity(SplitMix64& rng, int index, int res) {
  const double a = side(rng), b = side(rng), plinth = rng.uniform(5, 8);
  const double top = rng.uniform(38, 50);
  std::vector<std::pair<RRect, double>> pockets;  // outline, depth
  const bool twin = index % 2 == 1;
  if (!twin) {
    RRect q{a / 2 + rng.uniform(-0.06, 0.06) * a, b / 2 + rng.uniform(-0.06, 0.06) * b, rng.uniform(0.28, 0.36) * a,
            rng.uniform(0.28, 0.36) * b, 0};
    q.r = rng.uniform(0.2, 1.0) * std::min(q.hx, q.hy);
    pockets.emplace_back(q, rng.uniform(0.65, 0.85) * top);
  } else {  // two pockets side by side along x, separated by a thin rib
    for (int p = 0; p < 2; ++p) {
      RRect q{(p == 0 ? 0.28 : 0.72) * a, b / 2 + rng.uniform(-0.05, 0.05) * b, rng.uniform(0.15, 0.18) * a,
              rng.uniform(0.28, 0.36) * b, 0};
      q.r = rng.uniform(0.2, 1.0) * std::min(q.hx, q.hy);
      pockets.emplace_back(q, rng.uniform(0.65, 0.85) * top);
    }
  }
  std::vector<double> runs;
  for (const auto& p : pockets) runs.push_back(wall_run(p.second, rng.uniform(3, 10)));
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    double z = top;
    for (std::size_t p = 0; p < pockets.size(); ++p)
      z = std::min(z, top - pockets[p].second * ramp(pockets[p].first.inside(x, y), runs[p]));
    return z;
  });
  g.kind = twin ? "twin_pockets" : "pocket";
  return g;
}

GeneratedMesh shallow_slopes(SplitMix64& rng, int index, int res) {
  const double a = side(rng), b = side(rng), plinth = rng.uniform(6, 10);
  const double slope = std::tan(rng.uniform(8, 14) * kDeg);
  // Either way along x (the 180° flip maps one onto the other) or along y (the tilt about x then
  // changes the apparent slope, like a part clamped at an angle).
  const bool along_y = index % 2 == 1;
  const double yaw = (along_y ? 90 : 0) * kDeg + rng.uniform(-8, 8) * kDeg;  // never exactly axis-parallel
  const double dir = rng.sign();
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    return dir * slope * ((x - a / 2) * std::cos(yaw) + (y - b / 2) * std::sin(yaw));
  });
  g.kind = along_y ? "plane_y" : "plane_x";
  return g;
}

}  // namespace

std::string family_name(Family f) {
  switch (f) {
    case Family::SteepPlateaus: return "steep_plateaus";
    case Family::GentleFreeForm: return "gentle_freeform";
    case Family::VaryingCurvature: return "varying_curvature";
    case Family::DeepCavity: return "deep_cavity";
    case Family::ShallowSlopes: return "shallow_slopes";
  }
  throw Error("unknown part family " + std::to_string(static_cast<int>(f)));
}

GeneratedMesh make_part(Family family, int index, std::uint64_t seed, int resolution) {
  if (resolution < 8) throw Error("part generator: resolution must be ≥ 8, got " + std::to_string(resolution));
  if (index < 0) throw Error("part generator: index must be ≥ 0, got " + std::to_string(index));
  // Independent stream per (family, index): changing per_family never changes earlier parts.
  const auto key = (static_cast<std::uint64_t>(family) << 32) | static_cast<std::uint64_t>(index);
  SplitMix64 rng(SplitMix64::mix(seed ^ SplitMix64::mix(key + 0x51ED270B27F5A3C1ULL)));
  switch (family) {
    case Family::SteepPlateaus: return steep_plateaus(rng, index, resolution);
    case Family::GentleFreeForm: return gentle_freeform(rng, index, resolution);
    case Family::VaryingCurvature: return varying_curvature(rng, index, resolution);
    case Family::DeepCavity: return deep_cavity(rng, index, resolution);
    case Family::ShallowSlopes: return shallow_slopes(rng, index, resolution);
  }
  throw Error("unknown part family " + std::to_string(static_cast<int>(family)));
}

std::vector<GeneratedPart> generate_default_parts(const fs::path& dir, const GenerateParams& params) {
  if (params.per_family < 1)
    throw Error("part generator: per_family must be ≥ 1, got " + std::to_string(params.per_family));
  std::vector<GeneratedPart> parts;
  std::string list = "name,file,label\n";
  for (int f = 1; f <= kFamilies; ++f)
    for (int k = 0; k < params.per_family; ++k) {  // O(families · per_family · resolution²)
      const auto fam = static_cast<Family>(f);
      char name[96];
      std::snprintf(name, sizeof name, "s%d_%s_%02d", f, family_name(fam).c_str(), k + 1);
      const GeneratedMesh g = make_part(fam, k, params.seed, params.resolution);
      const fs::path file = dir / (std::string(name) + ".stl");
      ingest::save_stl_binary(
          g.mesh, file, "millnet default training part " + std::string(name) + " seed " + std::to_string(params.seed));
      parts.push_back({name, file, f});
      list += std::string(name) + "," + name + ".stl," + std::to_string(f) + "\n";
    }
  write_file_atomic(dir / "parts.csv", list);
  return parts;
}

std::vector<GeneratedPart> generate_library(const fs::path& dir, const GenerateParams& params) {
  if (params.library == Library::Shop) return generate_shop_parts(dir, params.seed, params.count, params.spacing_mm);
  return generate_default_parts(dir, params);
}

Eigen::MatrixXd top_heights(const GeneratedMesh& g) {
  Eigen::MatrixXd z(g.res_y, g.res_x);
  for (Eigen::Index i = 0; i < g.res_y; ++i)  // O(res_x · res_y)
    for (Eigen::Index j = 0; j < g.res_x; ++j) z(i, j) = g.mesh.V(i * g.res_x + j, 2);
  return z;
}

std::vector<GalleryPart> library_gallery(const GenerateParams& params, int per_family) {
  std::vector<GalleryPart> out;
  char name[96];
  if (params.library == Library::Shop) {
    for (int f = 0; f < kShopFamilies; ++f)
      for (int i = 0; i < per_family; ++i) {
        const int k = f + i * kShopFamilies;
        std::snprintf(name, sizeof name, "shop_%04d_%s", k + 1, shop_family_name(shop_family_of(k)).c_str());
        out.push_back({name, make_shop_part(k, params.seed, params.spacing_mm)});
      }
    return out;
  }
  for (int f = 1; f <= kFamilies; ++f)
    for (int i = 0; i < per_family; ++i) {
      std::snprintf(name, sizeof name, "s%d_%s_%02d", f, family_name(static_cast<Family>(f)).c_str(), i + 1);
      out.push_back({name, make_part(static_cast<Family>(f), i, params.seed, params.resolution)});
    }
  return out;
}

}  // namespace millnet::datasets
