// millnet dataset | train | predict: the learning pipeline's command-line contract.
#include "cli.hpp"
#include "learn.hpp"

#include "millnet/core/error.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <iostream>

namespace millnet::app {
namespace fs = std::filesystem;

Registered register_dataset(CLI::App& app) {
  struct Opts {
    Common common;
    std::string out;
    bool agreement = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand("dataset", "(re)generate the model-vector table from the config's recipe");
  sub->add_option("--out", o->out, "output folder (vectors.csv, manifest.json)")->required();
  sub->add_flag("--agreement", o->agreement,
                "also plan and simulate the five finishing strategies on every part and report how often the "
                "simulated best agrees with the recipe's label (agreement.md; minutes per part)");
  add_common(sub, o->common);
  sub->get_option("--config")->required();
  return {sub, [o]() {
            const Json config = setup(o->common);
            (void)build_dataset(recipe_from_config(config), o->out, false, config, o->agreement);
            return 0;
          }};
}

Registered register_train(CLI::App& app) {
  struct Opts {
    Common common;
    std::string dataset, out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand("train", "store the vectors and choose α by leave-one-out");
  sub->add_option("--dataset", o->dataset, "vectors.csv of `millnet dataset`")->required();
  sub->add_option("--out", o->out, "output folder (model.json, loo_curve.csv, verification.csv, PNGs)")->required();
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            (void)train_model(o->dataset, config, o->out);
            return 0;
          }};
}

Registered register_predict(CLI::App& app) {
  struct Opts {
    Common common;
    std::string model, out;
    MeshFlags mesh_flags;
    std::vector<std::string> parts;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand("predict", "rank the finishing strategies of parts (files or folders)");
  sub->add_option("--model", o->model, "folder of `millnet train` (model.json, sampling.json)")->required()
      ->check(CLI::ExistingDirectory);
  o->mesh_flags.add_to(sub, "part files");
  sub->add_option("--out", o->out, "output folder (predictions.json, predictions.csv, one PNG per part)")->required();
  sub->add_option("parts", o->parts, "part files or folders (added to /predict/parts of the config)");
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            std::vector<std::string> items = config["predict"]["parts"].get<std::vector<std::string>>();
            items.insert(items.end(), o->parts.begin(), o->parts.end());
            if (items.empty()) throw Error("no parts to predict: name files or folders, or set /predict/parts");
            std::vector<PredictInput> inputs;
            for (const auto& f : expand_inputs(items, ingest::mesh_extensions()))
              inputs.push_back({f, "", 0, nullptr});
            const auto res = predict_parts(load_model_folder(o->model, config), inputs,
                                           o->mesh_flags.prepare(&config["predict"]),
                                           o->out);
            std::size_t failed = 0;
            for (const auto& r : res) {
              if (!r.ok) {
                ++failed;
                continue;
              }
              info("predict: " + r.name + ": strategy " + std::to_string(r.top) + " (" +
                   r.strategies[static_cast<std::size_t>(r.top - 1)] + "), confidence " +
                   std::to_string(static_cast<int>(100 * r.confidence + 0.5)) + " %, consistency " +
                   std::to_string(static_cast<int>(100 * r.consistency + 0.5)) + " %");
            }
            info("predict: " + std::to_string(res.size() - failed) + " of " + std::to_string(res.size()) +
                 " parts predicted → " + (fs::path(o->out) / "predictions.json").string());
            if (failed) {
              std::cerr << "millnet predict: error: " << failed << " of " << res.size()
                        << " parts could not be read (see predictions.json)\n";
              return 1;
            }
            return 0;
          }};
}

}  // namespace millnet::app
