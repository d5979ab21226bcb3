// millnet dataset | train | predict: the learning pipeline's command-line contract.
#include "cli.hpp"
#include "learn.hpp"

#include "millnet/core/error.hpp"
#include "millnet/datasets/shop_parts.hpp"
#include "millnet/report/plots.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct DatasetOpts {
  Common common;
  std::string out;
  bool agreement = false;
  bool relabel = false;
  bool gallery = false;
};

struct TrainOpts {
  Common common;
  std::string dataset, out;
};

struct PredictOpts {
  Common common;
  std::string model, out;
  MeshFlags mesh_flags;
  std::vector<std::string> parts;
};

/// OUT/library.png: the first two parts of every family of the generated library, as reliefs.
void write_gallery(const datasets::GenerateParams& params, const fs::path& png) {
  std::vector<report::ReliefTile> tiles;
  for (const datasets::GalleryPart& p : datasets::library_gallery(params, 2)) {
    const Eigen::MatrixXd z = datasets::top_heights(p.part);
    char size[64];
    std::snprintf(size, sizeof size, " %.0f x %.0f mm, relief %.0f mm", p.part.a, p.part.b,
                  z.maxCoeff() - z.minCoeff());
    tiles.push_back({z, p.part.a, p.part.b, p.part.kind + size});
  }
  fs::create_directories(png.parent_path());
  const bool shop = params.library == datasets::Library::Shop;
  report::relief_sheet_png(png, tiles,
                           std::string(shop ? "the tool-shop library" : "the five textbook families") + " (seed " +
                               std::to_string(params.seed) + "): the first two parts of every family",
                           4);
  info("dataset: " + std::to_string(tiles.size()) + " parts → " + png.string());
}

/// millnet dataset: the config's recipe → vectors.csv + manifest.json (always rebuilt).
int run_dataset(const DatasetOpts& o) {
  const Json config = setup(o.common);
  if (o.gallery) {
    write_gallery(generate_params(config), fs::path(o.out) / "library.png");
    return 0;
  }
  datasets::Recipe recipe = recipe_from_config(config);
  recipe.relabel = o.relabel;
  (void)build_dataset(std::move(recipe), o.out, false, config, o.agreement);
  return 0;
}

/// millnet train: vectors.csv → model folder.
int run_train(const TrainOpts& o) {
  const Json config = setup(o.common);
  (void)train_model(o.dataset, config, o.out);
  return 0;
}

/// One line per predicted part; the failed ones are in predictions.json.
void report_predictions(const std::vector<PartPrediction>& res) {
  for (const auto& r : res) {
    if (!r.ok) continue;
    info("predict: " + r.name + ": strategy " + std::to_string(r.top) + " (" +
         r.strategies[static_cast<std::size_t>(r.top - 1)] + "), confidence " +
         std::to_string(static_cast<int>(100 * r.confidence + 0.5)) + " %, consistency " +
         std::to_string(static_cast<int>(100 * r.consistency + 0.5)) + " %");
  }
}

/// millnet predict: the config's and the command line's parts → predictions; exit 1 when a part
/// could not be read (the others are still predicted).
int run_predict(const PredictOpts& o) {
  const Json config = setup(o.common);
  std::vector<std::string> items = config["predict"]["parts"].get<std::vector<std::string>>();
  items.insert(items.end(), o.parts.begin(), o.parts.end());
  if (items.empty()) throw Error("no parts to predict: name files or folders, or set /predict/parts");
  std::vector<PredictInput> inputs;
  for (const auto& f : expand_inputs(items, ingest::mesh_extensions())) inputs.push_back({f, "", 0, nullptr});
  const auto res = predict_parts(load_model_folder(o.model, config), inputs,
                                 o.mesh_flags.prepare(&config["predict"], &config), o.out);
  report_predictions(res);
  const auto failed =
      static_cast<std::size_t>(std::count_if(res.begin(), res.end(), [](const auto& r) { return !r.ok; }));
  info("predict: " + std::to_string(res.size() - failed) + " of " + std::to_string(res.size()) + " parts predicted → " +
       (fs::path(o.out) / "predictions.json").string());
  if (failed) {
    std::cerr << "millnet predict: error: " << failed << " of " << res.size()
              << " parts could not be read (see predictions.json)\n";
    return 1;
  }
  return 0;
}

}  // namespace

Registered register_dataset(CLI::App& app) {
  auto o = std::make_shared<DatasetOpts>();
  CLI::App* sub = app.add_subcommand("dataset", "(re)generate the model-vector table from the config's recipe");
  sub->add_option("--out", o->out, "output folder (vectors.csv, manifest.json)")->check(output_path())->required();
  sub->add_flag("--agreement", o->agreement,
                "also plan and simulate the five finishing strategies on every part and report how often the "
                "simulated best agrees with the recipe's label (agreement.md; minutes per part)");
  sub->add_flag("--relabel", o->relabel,
                "simulate every part labelled by simulation, whatever /dataset/labels holds (the new labels "
                "go to OUT/labels.json)");
  sub->add_flag("--gallery", o->gallery,
                "only write OUT/library.png: shaded reliefs of the first two parts of every family of the "
                "generated library (/dataset/generate), no table");
  add_common(sub, o->common);
  sub->get_option("--config")->required();
  return {sub, [o]() { return run_dataset(*o); }};
}

Registered register_train(CLI::App& app) {
  auto o = std::make_shared<TrainOpts>();
  CLI::App* sub = app.add_subcommand("train", "store the vectors and choose α by leave-one-out");
  sub->add_option("--dataset", o->dataset, "vectors.csv of `millnet dataset`")->required();
  sub->add_option("--out", o->out, "output folder (model.json, loo_curve.csv, verification.csv, PNGs)")
      ->check(output_path())
      ->required();
  add_common(sub, o->common);
  return {sub, [o]() { return run_train(*o); }};
}

Registered register_predict(CLI::App& app) {
  auto o = std::make_shared<PredictOpts>();
  CLI::App* sub = app.add_subcommand("predict", "rank the finishing strategies of parts (files or folders)");
  sub->add_option("--model", o->model, "folder of `millnet train` (model.json, sampling.json)")
      ->required()
      ->check(CLI::ExistingDirectory);
  o->mesh_flags.add_to(sub, "part files");
  sub->add_option("--out", o->out, "output folder (predictions.json, predictions.csv, one PNG per part)")
      ->check(output_path())
      ->required();
  sub->add_option("parts", o->parts, "part files or folders (added to /predict/parts of the config)");
  add_common(sub, o->common);
  return {sub, [o]() { return run_predict(*o); }};
}

}  // namespace millnet::app
