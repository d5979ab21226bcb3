// The dataset stage's settings (settings.hpp): the generated library's parameters and the recipe a
// config describes — its parts, augmentation, grid and the settings a simulated label depends on.
#include "settings.hpp"

#include "cli.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace millnet::app {
namespace fs = std::filesystem;

datasets::GenerateParams generate_params(const Json& config) {
  const Json& gen = config["dataset"]["generate"];
  datasets::GenerateParams g;
  g.seed = gen["seed"].get<std::uint64_t>();
  g.per_family = gen["per_family"].get<int>();
  g.resolution = gen["resolution"].get<int>();
  g.library = gen["library"].get<std::string>() == "shop" ? datasets::Library::Shop : datasets::Library::Families;
  g.count = gen["count"].get<int>();
  g.spacing_mm = gen["spacing_mm"].get<double>();
  return g;
}

datasets::Recipe recipe_from_config(const Json& config) {
  const Json& d = config["dataset"];
  datasets::Recipe r;
  r.units = ingest::parse_units(d["units"].get<std::string>());
  r.units_explicit = d["units"].get<std::string>() != "mm";
  r.cad = cad_options(config);
  r.up = ingest::parse_up(d["up"].get<std::string>());
  r.raster_mm = d["raster_mm"].get<double>();
  r.grid = d["grid"].get<int>();
  r.limits = work_limits();
  r.augment = augment_from(d["augment"]);
  r.aspect_feature = d["aspect_feature"].get<bool>();
  r.wall_share_feature = d["wall_share_feature"].get<bool>();
  const auto names = d["strategies"].get<std::vector<std::string>>();
  if (names.size() != datasets::kStrategySlots)
    throw Error("/dataset/strategies: expected exactly " + std::to_string(datasets::kStrategySlots) + " names, got " +
                std::to_string(names.size()));
  std::copy(names.begin(), names.end(), r.strategies.begin());
  if (d["parts"].empty()) {
    const Json& gen = d["generate"];
    const datasets::GenerateParams g = generate_params(config);
    const bool shop = g.library == datasets::Library::Shop;
    if (shop && gen["label"].get<std::string>() != "simulate")
      throw Error(
          "/dataset/generate/label: the shop library's parts have no family label; expected \"simulate\", got \"" +
          gen["label"].get<std::string>() + "\"");
    const fs::path dir = d["parts_dir"].get<std::string>();
    info(shop ? "dataset: generating the tool-shop library (" + std::to_string(g.count) + " parts, seed " +
                    std::to_string(g.seed) + ") into " + dir.string()
              : "dataset: generating the default training parts (" + std::to_string(g.per_family) +
                    " per family, seed " + std::to_string(g.seed) + ") into " + dir.string());
    r.parts = datasets::to_part_specs(datasets::generate_library(dir, g));
    if (gen["label"].get<std::string>() == "simulate")
      for (datasets::PartSpec& p : r.parts) p.label_by_simulation = true;
    r.generate = g;
  } else {
    for (const auto& p : d["parts"]) {
      datasets::PartSpec s;
      s.file = p["file"].get<std::string>();
      if (p["label"].is_string()) {  // "simulate" (the schema allows nothing else)
        s.label_by_simulation = true;
      } else {
        s.label = p["label"].get<int>();
      }
      s.name = p.value("name", std::string());
      r.parts.push_back(std::move(s));
    }
  }
  r.labels_file = d["labels"].get<std::string>();
  {
    Json f = config["finish"];
    f.erase("meshes");
    f.erase("strategy");
    f.erase("rest");  // a job's rest operation: no label plans it
    // Everything a simulated label depends on: the strategies' settings, the simulator's, and the
    // cutting data and machine that set the programs' feeds (the "time" aims rank by them).
    Json m = config["machine"];
    m.erase("max_depth_of_cut_mm");  // a job's limit on its operations: no label's finishing checks it
    r.simulation_settings_json =
        Json{{"finish", f}, {"simulate", config["simulate"]}, {"cutting", config["cutting"]}, {"machine", m}}.dump();
  }
  return r;
}

}  // namespace millnet::app
