// Issue 39 §3's feature ablation: does an input beside the paper's 15×15 height grid lower the
// network's leave-one-part-out regret on a library labelled by simulation?
//
//   build/bench/feature_ablation OUT_DIR PARTS_DIR [COPIES…]
//
// OUT_DIR is a `millnet dataset` output (vectors.csv with every strategy's score as outputs),
// PARTS_DIR holds each part's <source>.stl. Per part, from its mesh (upward facets, area-weighted):
// the share of walls (slope > 60°), of flats (< 5°), the mean slope, the footprint's size
// (log √(x·y)) and the relief over that size. Each feature is appended to every vector of its part
// as `copies` identical columns (the normalizer z-scores each column, so c copies weigh √c against
// one height); the network is trained with α chosen by leave-one-part-out regret, as `millnet
// train` does, and the table prints top-1, mean / median / p90 regret against the baseline of
// always the same strategy. O(configurations · N² · D).
#include "millnet/classifier/network.hpp"
#include "millnet/classifier/regret.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace millnet;

namespace {

constexpr int kFeatures = 5;
const char* const kNames[kFeatures] = {"wall share", "flat share", "mean slope", "size", "relief / size"};

std::array<double, kFeatures> part_features(const ingest::Mesh& m) {
  double area = 0, wall = 0, flat = 0, slope = 0, zlo = HUGE_VAL, zhi = -HUGE_VAL;
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {  // O(triangles)
    const Eigen::Vector3d a = m.V.row(m.F(t, 0)), b = m.V.row(m.F(t, 1)), c = m.V.row(m.F(t, 2));
    const Eigen::Vector3d e1 = b - a, e2 = c - a;
    const Eigen::Vector3d n(e1.y() * e2.z() - e1.z() * e2.y(), e1.z() * e2.x() - e1.x() * e2.z(),
                            e1.x() * e2.y() - e1.y() * e2.x());
    const double len = n.norm();
    if (!(len > 0) || n.z() / len < 1e-3) continue;  // the sides and the bottom are not machined
    const double A = len / 2, deg = std::acos(std::clamp(n.z() / len, -1.0, 1.0)) * 180 / std::numbers::pi;
    area += A;
    wall += deg > 60 ? A : 0;
    flat += deg < 5 ? A : 0;
    slope += A * deg;
    for (const auto* p : {&a, &b, &c}) {
      zlo = std::min(zlo, p->z());
      zhi = std::max(zhi, p->z());
    }
  }
  const double fx = m.V.col(0).maxCoeff() - m.V.col(0).minCoeff(), fy = m.V.col(1).maxCoeff() - m.V.col(1).minCoeff();
  const double size = std::sqrt(fx * fy);
  return {wall / area, flat / area, slope / area, std::log(size), (zhi - zlo) / size};
}

struct Figures {
  classifier::RegretSummary net, base;
  double alpha = 0, seconds = 0;
};

Figures evaluate(const classifier::TrainingSet& set) {
  const auto t0 = std::chrono::steady_clock::now();
  classifier::TrainParams p;
  p.criterion = classifier::Criterion::Regret;
  p.limits.max_pairs = 1e13;
  const classifier::Model model = classifier::train(set, p);
  const auto picks = classifier::part_picks(model.loo.verification, set.outputs, set.groups, model.loo.nearest_d2);
  Figures f;
  f.net = classifier::summarize(picks);
  f.base = classifier::always_the_same(picks).figures;
  f.alpha = model.alpha;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

/// The network trained on regret utilities instead of scores (u = 1 − min(1, regret): 1 for the
/// best, 0 for a strategy twice as long or one that misses), so that its conditional average is
/// one minus the expected (capped) regret and its argmax the pick of least expected regret; judged
/// on the parts' scores like every other row, at a fixed α (the search judges by the outputs it is
/// given).
Figures evaluate_utility(const classifier::TrainingSet& set, double alpha) {
  const auto t0 = std::chrono::steady_clock::now();
  classifier::TrainingSet u = set;
  for (Eigen::Index i = 0; i < u.outputs.rows(); ++i) {
    const double top = set.outputs.row(i).maxCoeff();
    for (Eigen::Index k = 0; k < u.outputs.cols(); ++k) {
      const double y = set.outputs(i, k);
      u.outputs(i, k) = top > 0 && y > 0 ? std::max(0.0, 1.0 - (top / y - 1.0)) : 0.0;
    }
  }
  classifier::TrainParams p;
  p.criterion = classifier::Criterion::Regret;
  p.limits.max_pairs = 1e13;
  p.fixed_alpha = alpha;
  const classifier::Model model = classifier::train(u, p);
  const auto picks = classifier::part_picks(model.loo.verification, set.outputs, set.groups, model.loo.nearest_d2);
  Figures f;
  f.net = classifier::summarize(picks);
  f.base = classifier::always_the_same(picks).figures;
  f.alpha = alpha;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

void print(const std::string& name, const Figures& f) {
  std::printf("| %s | %.1f %% | %.3g %% | %.3g %% | %.3g %% | %zu | %.3g | %.1f |\n", name.c_str(), 100 * f.net.top1,
              100 * f.net.mean, 100 * f.net.median, 100 * f.net.p90, f.net.misses, f.alpha, f.seconds);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s DATASET_OUT_DIR PARTS_DIR [COPIES…]\n", argv[0]);
    return 2;
  }
  try {
    const datasets::Table table = datasets::read_table(fs::path(argv[1]) / "vectors.csv");
    std::vector<int> copies;
    for (int k = 3; k < argc; ++k) copies.push_back(std::stoi(argv[k]));
    if (copies.empty()) copies = {9, 25};
    classifier::TrainingSet base;
    base.inputs = table.inputs_matrix();
    base.outputs = table.outputs_matrix();
    base.groups = table.row_sources();
    base.strategies.assign(table.strategies.begin(), table.strategies.end());
    std::map<std::string, std::array<double, kFeatures>> features;
    for (const std::string& g : base.groups)
      if (!features.count(g)) features[g] = part_features(ingest::load_mesh(fs::path(argv[2]) / (g + ".stl")));
    std::printf("%zu vectors of %zu parts\n\n", base.groups.size(), features.size());
    std::printf(
        "| inputs | top-1 | mean regret | median | p90 | misses | alpha | s "
        "|\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
    const Figures heights = evaluate(base);
    print("15x15 heights (the paper's)", heights);
    std::printf("| always strategy the most often best | %.1f %% | %.3g %% | %.3g %% | %.3g %% | %zu | | |\n",
                100 * heights.base.top1, 100 * heights.base.mean, 100 * heights.base.median, 100 * heights.base.p90,
                heights.base.misses);
    const auto with = [&](const std::vector<int>& which, int c) {
      classifier::TrainingSet s = base;
      s.inputs.conservativeResize(Eigen::NoChange, base.inputs.cols() + static_cast<Eigen::Index>(which.size()) * c);
      for (Eigen::Index r = 0; r < s.inputs.rows(); ++r) {
        const auto& f = features.at(base.groups[static_cast<std::size_t>(r)]);
        Eigen::Index col = base.inputs.cols();
        for (const int w : which)
          for (int k = 0; k < c; ++k) s.inputs(r, col++) = f[static_cast<std::size_t>(w)];
      }
      return evaluate(s);
    };
    if (std::getenv("ABLATION_UTILITY") != nullptr) {  // the regret-utility targets over an α scan
      for (int k = -2; k <= 8; ++k) {
        const double a = std::pow(2.0, 0.5 * k);
        char name[64];
        std::snprintf(name, sizeof name, "heights, regret utility, alpha %.3g", a);
        print(name, evaluate_utility(base, a));
        std::fflush(stdout);
      }
      return 0;
    }
    for (const int c : copies) {
      for (int w = 0; w < kFeatures; ++w) print("+ " + std::string(kNames[w]) + " ×" + std::to_string(c), with({w}, c));
      print("+ all five ×" + std::to_string(c), with({0, 1, 2, 3, 4}, c));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "feature_ablation: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
