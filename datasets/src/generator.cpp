#include "millnet/datasets/generator.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/rng.hpp"
#include "millnet/datasets/tolerances.hpp"
#include "millnet/ingest/mesh_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

namespace millnet::datasets {
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

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

// A rounded rectangle of half sizes (fx·a, fy·b) placed at random fully inside the footprint.
RRect random_rect(SplitMix64& rng, double a, double b, double fx_lo, double fx_hi, double fy_lo, double fy_hi) {
  RRect q{};
  q.hx = rng.uniform(fx_lo, fx_hi) * a;
  q.hy = rng.uniform(fy_lo, fy_hi) * b;
  const double m = tol::feature_margin_mm;
  q.cx = rng.uniform(m + q.hx, std::max(m + q.hx, a - m - q.hx));
  q.cy = rng.uniform(m + q.hy, std::max(m + q.hy, b - m - q.hy));
  q.r = rng.uniform(0.0, 0.6) * std::min(q.hx, q.hy);
  return q;
}

using HeightFn = std::function<double(double, double)>;

// Closed height-field solid over [0,a]×[0,b]: top grid (res×res, row-major, row = y), a ring of
// bottom vertices under the top's boundary, vertical sides, bottom fan at z = 0. Outward normals.
// The top is shifted so that its lowest point is at z = plinth. O(res²).
GeneratedMesh solid(double a, double b, int res, double plinth, const HeightFn& f) {
  GeneratedMesh g;
  g.res_x = g.res_y = res;
  g.a = a;
  g.b = b;
  const auto R = static_cast<std::size_t>(res);
  std::vector<double> z(R * R);
  double zmin = HUGE_VAL;
  for (std::size_t i = 0; i < R; ++i)
    for (std::size_t j = 0; j < R; ++j) {
      const double x = a * static_cast<double>(j) / static_cast<double>(res - 1);
      const double y = b * static_cast<double>(i) / static_cast<double>(res - 1);
      z[i * R + j] = f(x, y);
      zmin = std::min(zmin, z[i * R + j]);
    }
  // Boundary ring, counter-clockwise seen from +z: y = 0 (x up), x = a (y up), y = b (x down), x = 0.
  std::vector<std::size_t> ring;
  for (std::size_t j = 0; j + 1 < R; ++j) ring.push_back(j);
  for (std::size_t i = 0; i + 1 < R; ++i) ring.push_back(i * R + R - 1);
  for (std::size_t j = R - 1; j > 0; --j) ring.push_back((R - 1) * R + j);
  for (std::size_t i = R - 1; i > 0; --i) ring.push_back(i * R);
  const std::size_t nv = R * R + ring.size() + 1;
  const std::size_t nf = 2 * (R - 1) * (R - 1) + 3 * ring.size();
  g.mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  g.mesh.F.resize(static_cast<Eigen::Index>(nf), 3);
  auto setv = [&](std::size_t k, double x, double y, double zz) {
    const auto e = static_cast<Eigen::Index>(k);
    g.mesh.V(e, 0) = x;
    g.mesh.V(e, 1) = y;
    g.mesh.V(e, 2) = zz;
  };
  for (std::size_t i = 0; i < R; ++i)
    for (std::size_t j = 0; j < R; ++j)
      setv(i * R + j, a * static_cast<double>(j) / static_cast<double>(res - 1),
           b * static_cast<double>(i) / static_cast<double>(res - 1), plinth + z[i * R + j] - zmin);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const auto e = static_cast<Eigen::Index>(ring[k]);
    setv(R * R + k, g.mesh.V(e, 0), g.mesh.V(e, 1), 0.0);
  }
  const std::size_t centre = nv - 1;
  setv(centre, a / 2, b / 2, 0.0);
  std::size_t f_at = 0;
  auto tri = [&](std::size_t p, std::size_t q, std::size_t r) {
    const auto e = static_cast<Eigen::Index>(f_at++);
    g.mesh.F(e, 0) = static_cast<std::int32_t>(p);
    g.mesh.F(e, 1) = static_cast<std::int32_t>(q);
    g.mesh.F(e, 2) = static_cast<std::int32_t>(r);
  };
  for (std::size_t i = 0; i + 1 < R; ++i)
    for (std::size_t j = 0; j + 1 < R; ++j) {
      const std::size_t v00 = i * R + j, v01 = v00 + 1, v10 = v00 + R, v11 = v10 + 1;
      tri(v00, v01, v11);
      tri(v00, v11, v10);
    }
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const std::size_t k1 = (k + 1) % ring.size();
    const std::size_t t0 = ring[k], t1 = ring[k1], b0 = R * R + k, b1 = R * R + k1;
    tri(b0, b1, t1);
    tri(b0, t1, t0);
    tri(centre, b1, b0);
  }
  MILLNET_ASSERT(f_at == nf, "generated face count");
  return g;
}

// ---- the five families (parameters in mm and degrees; ranges are the README's) ----

GeneratedMesh steep_plateaus(SplitMix64& rng, int index, int res) {
  const double a = rng.uniform(80, 150), b = rng.uniform(80, 150), plinth = rng.uniform(6, 10);
  struct Pad {
    RRect q;
    double h, w;
  };
  std::vector<Pad> pads;
  std::string kind;
  if (index % 2 == 0) {  // separate pads on the flat base
    kind = "pads";
    const int k = rng.uniform_int(2, 3);
    for (int p = 0; p < k; ++p) {
      const RRect q = random_rect(rng, a, b, 0.10, 0.2, 0.10, 0.2);
      const double h = rng.uniform(8, 20);
      pads.push_back({q, h, wall_run(h, rng.uniform(0, 4))});
    }
  } else {  // stepped terraces: each level a smaller rectangle on the previous one
    kind = "terraces";
    const int k = rng.uniform_int(2, 3);
    RRect q = random_rect(rng, a, b, 0.25, 0.33, 0.25, 0.33);
    double level = 0;
    for (int p = 0; p < k; ++p) {
      const double step = rng.uniform(7, 12);
      level += step;
      pads.push_back({q, level, wall_run(step, rng.uniform(0, 4))});
      RRect inner = q;
      inner.hx = q.hx * rng.uniform(0.45, 0.65);
      inner.hy = q.hy * rng.uniform(0.45, 0.65);
      inner.cx = q.cx + rng.uniform(-1, 1) * (q.hx - inner.hx - 4);
      inner.cy = q.cy + rng.uniform(-1, 1) * (q.hy - inner.hy - 4);
      inner.r = std::min(q.r, std::min(inner.hx, inner.hy));
      q = inner;
    }
  }
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    double z = 0;
    for (const Pad& p : pads) z = std::max(z, p.h * ramp(p.q.inside(x, y), p.w));
    return z;
  });
  g.kind = kind;
  return g;
}

GeneratedMesh gentle_freeform(SplitMix64& rng, int index, int res) {
  const double a = rng.uniform(80, 150), b = rng.uniform(80, 150), plinth = rng.uniform(8, 12);
  struct Bump {
    double cx, cy, s, h;
  };
  std::vector<Bump> bumps;
  const bool saddle = index % 2 == 1;
  const int k = saddle ? 1 : rng.uniform_int(2, 4);
  for (int p = 0; p < k; ++p) {
    Bump u{rng.uniform(0.2, 0.8) * a, rng.uniform(0.2, 0.8) * b, rng.uniform(22, 40), rng.uniform(4, 9)};
    if (p > 0 && rng.uniform() < 0.3) u.h = -u.h;  // an occasional shallow dip
    bumps.push_back(u);
  }
  const double s_amp = saddle ? rng.uniform(5, 8) * rng.sign() : 0.0;
  const double xc = rng.uniform(0.4, 0.6) * a, yc = rng.uniform(0.4, 0.6) * b;
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    double z = 0;
    for (const Bump& u : bumps) z += u.h * gauss(x - u.cx, y - u.cy, u.s);
    const double su = (x - xc) / (a / 2), sv = (y - yc) / (b / 2);
    return z + s_amp * (su * su - sv * sv);
  });
  g.kind = saddle ? "saddle" : "bumps";
  return g;
}

GeneratedMesh varying_curvature(SplitMix64& rng, int index, int res) {
  const double a = rng.uniform(80, 150), b = rng.uniform(80, 150), plinth = rng.uniform(6, 10);
  const bool along_x = rng.uniform() < 0.5;  // ridge runs along x (else along y)
  const bool sharp_first = rng.uniform() < 0.5;
  const double len = along_x ? a : b, wid = along_x ? b : a;
  const double u0 = rng.uniform(0.35, 0.65) * wid, bend = rng.uniform(-0.12, 0.12) * wid;
  const double w_sharp = rng.uniform(2.5, 4.5), w_flat = rng.uniform(18, 28), h = rng.uniform(18, 30);
  struct Peak {
    double cx, cy, s, h;
  };
  std::vector<Peak> peaks;
  const bool with_peaks = index % 2 == 1;
  if (with_peaks) {  // one sharp and one broad peak beside the ridge: curvature varies over the part
    peaks.push_back({rng.uniform(0.2, 0.8) * a, rng.uniform(0.2, 0.8) * b, rng.uniform(3, 5), rng.uniform(8, 15)});
    peaks.push_back({rng.uniform(0.2, 0.8) * a, rng.uniform(0.2, 0.8) * b, rng.uniform(15, 25), rng.uniform(8, 15)});
  }
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    const double s = (along_x ? x : y) / len, u = along_x ? y : x;
    const double t = sharp_first ? s : 1 - s;
    const double w = w_sharp + (w_flat - w_sharp) * t;  // cross-section radius grows along the ridge
    const double d = u - (u0 + bend * std::sin(std::numbers::pi * s));
    double z = h * std::exp(-d * d / (2 * w * w));
    for (const Peak& p : peaks) z = std::max(z, p.h * gauss(x - p.cx, y - p.cy, p.s));
    return z;
  });
  g.kind = with_peaks ? "ridge_and_peaks" : "ridge";
  return g;
}

GeneratedMesh deep_cavity(SplitMix64& rng, int index, int res) {
  const double a = rng.uniform(80, 150), b = rng.uniform(80, 150), plinth = rng.uniform(5, 8);
  const double top = rng.uniform(35, 50);
  std::vector<std::pair<RRect, double>> pockets;  // outline, depth
  std::vector<double> runs;
  std::string kind;
  const int kind_i = index % 3;
  if (kind_i == 0) {
    kind = "pocket";
    RRect q{a / 2 + rng.uniform(-5, 5), b / 2 + rng.uniform(-5, 5), rng.uniform(0.3, 0.38) * a, rng.uniform(0.3, 0.38) * b, 0};
    q.r = rng.uniform(0.2, 1.0) * std::min(q.hx, q.hy);
    pockets.emplace_back(q, rng.uniform(0.65, 0.85) * top);
  } else if (kind_i == 1) {
    kind = "twin_pockets";
    const bool split_x = a >= b;
    for (int p = 0; p < 2; ++p) {
      RRect q{};
      q.hx = (split_x ? rng.uniform(0.15, 0.19) : rng.uniform(0.3, 0.38)) * a;
      q.hy = (split_x ? rng.uniform(0.3, 0.38) : rng.uniform(0.15, 0.19)) * b;
      q.cx = split_x ? (p == 0 ? 0.27 : 0.73) * a : a / 2;
      q.cy = split_x ? b / 2 : (p == 0 ? 0.27 : 0.73) * b;
      q.r = rng.uniform(0.2, 1.0) * std::min(q.hx, q.hy);
      pockets.emplace_back(q, rng.uniform(0.65, 0.85) * top);
    }
  } else {
    kind = "boss";
  }
  for (const auto& p : pockets) runs.push_back(wall_run(p.second, rng.uniform(3, 10)));
  RRect boss{a / 2 + rng.uniform(-5, 5), b / 2 + rng.uniform(-5, 5), rng.uniform(0.22, 0.3) * a, rng.uniform(0.22, 0.3) * b, 0};
  boss.r = rng.uniform(0.2, 1.0) * std::min(boss.hx, boss.hy);
  const double boss_run = wall_run(top, rng.uniform(3, 10));
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    if (pockets.empty()) return top * ramp(boss.inside(x, y), boss_run);
    double z = top;
    for (std::size_t p = 0; p < pockets.size(); ++p)
      z = std::min(z, top - pockets[p].second * ramp(pockets[p].first.inside(x, y), runs[p]));
    return z;
  });
  g.kind = kind;
  return g;
}

GeneratedMesh shallow_slopes(SplitMix64& rng, int index, int res) {
  const double a = rng.uniform(80, 150), b = rng.uniform(80, 150), plinth = rng.uniform(6, 10);
  const double slope = std::tan(rng.uniform(6, 14) * kDeg);
  const double phi = rng.uniform(0, 2 * std::numbers::pi);
  const double c = std::cos(phi), s = std::sin(phi);
  const double px = rng.uniform(0.35, 0.65) * a, py = rng.uniform(0.35, 0.65) * b;
  const int kind_i = index % 3;
  GeneratedMesh g = solid(a, b, res, plinth, [&](double x, double y) {
    const double dx = x - px, dy = y - py;
    switch (kind_i) {
      case 0: return slope * (dx * c + dy * s);                // inclined plane
      case 1: return -slope * std::abs(-dx * s + dy * c);      // roof: two planes, ridge through p
      default: return -slope * std::hypot(dx, dy);             // gentle cone, apex at p
    }
  });
  g.kind = kind_i == 0 ? "plane" : kind_i == 1 ? "roof" : "cone";
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
  if (params.per_family < 1) throw Error("part generator: per_family must be ≥ 1, got " + std::to_string(params.per_family));
  std::vector<GeneratedPart> parts;
  std::string list = "name,file,label\n";
  for (int f = 1; f <= kFamilies; ++f)
    for (int k = 0; k < params.per_family; ++k) {  // O(families · per_family · resolution²)
      const auto fam = static_cast<Family>(f);
      char name[96];
      std::snprintf(name, sizeof name, "s%d_%s_%02d", f, family_name(fam).c_str(), k + 1);
      const GeneratedMesh g = make_part(fam, k, params.seed, params.resolution);
      const fs::path file = dir / (std::string(name) + ".stl");
      ingest::save_stl_binary(g.mesh, file,
                              "millnet default training part " + std::string(name) + " seed " + std::to_string(params.seed));
      parts.push_back({name, file, f});
      list += std::string(name) + "," + name + ".stl," + std::to_string(f) + "\n";
    }
  write_file_atomic(dir / "parts.csv", list);
  return parts;
}

}  // namespace millnet::datasets
