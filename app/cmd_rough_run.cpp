// millnet rough --mesh FILE … --out DIR   (or a batch: /rough/meshes of the config)
// millnet run [FILE] [--out DIR]          (dataset → train → predict → rough on the test parts, summary page)
#include "cli.hpp"
#include "text.hpp"
#include "learn.hpp"
#include "rough.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <chrono>
#include <iostream>
#include <memory>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct RoughOutcome {
  std::string name, file, error;
  bool ok = false;
  Json metrics;
};

/// Roughs one prepared mesh (or reports `load_error` when it could not be read) into `out`.
RoughOutcome rough_prepared(const ingest::Mesh* mesh, const std::string& load_error, const fs::path& file,
                            const std::string& name, const rough::Params& params, const fs::path& out) {
  RoughOutcome o{name, file.string(), load_error, false, Json::object()};
  if (!mesh) return o;
  try {
    const rough::Result r = rough::rough_mesh(*mesh, params);
    o.metrics = write_rough_outputs(out, name, r, params);
    o.ok = r.machining.status == pocket::PlanStatus::Ok;
    if (!o.ok) o.error = file.string() + ": " + r.machining.message;
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  return o;
}

/// Reads and prepares a mesh; null and the reason when it cannot be read.
std::shared_ptr<const ingest::Mesh> load_prepared(const fs::path& file, const ingest::PrepareOptions& prep,
                                                  std::string* error) {
  try {
    ingest::MeshReport rep;
    return std::make_shared<const ingest::Mesh>(ingest::prepare(ingest::load_mesh(file, &rep), prep, &rep));
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
}

RoughOutcome rough_one(const fs::path& file, const std::string& name, const ingest::PrepareOptions& prep,
                       const rough::Params& params, const fs::path& out) {
  std::string error;
  const auto mesh = load_prepared(file, prep, &error);
  return rough_prepared(mesh.get(), error, file, name, params, out);
}
}  // namespace

Registered register_rough(CLI::App& app) {
  struct Opts {
    Common common;
    PocketFlags flags;
    std::vector<std::string> meshes;
    MeshFlags mesh_flags;
    std::string out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand("rough", "Z-level roughing of parts from their meshes → G-code, metrics, one PNG per level");
  sub->add_option("--mesh", o->meshes, "mesh file or folder (repeatable; added to /rough/meshes of the config)");
  o->mesh_flags.add_to(sub);
  sub->add_option("--out", o->out, "output folder")->required();
  o->flags.add_to(sub, true, false);
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            std::vector<std::string> items = config["rough"]["meshes"].get<std::vector<std::string>>();
            items.insert(items.end(), o->meshes.begin(), o->meshes.end());
            if (items.empty()) throw Error("no mesh to rough: give --mesh FILE or set /rough/meshes in the config");
            const auto files = expand_inputs(items, ingest::mesh_extensions());
            const rough::Params params = rough_params(config, explicit_pocket_section(o->common.config), o->flags);
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"]);
            std::vector<RoughOutcome> done;
            Progress progress("rough", files.size());
            for (const auto& f : files) {
              done.push_back(rough_one(f, f.stem().string(), prep, params, o->out));
              progress.tick();
            }
            progress.finish();
            std::size_t failed = 0;
            Json summary = Json::array();
            for (const auto& d : done) {
              if (!d.ok) {
                ++failed;
                std::cerr << "millnet rough: error: " << d.error << "\n";
                summary.push_back({{"part", d.name}, {"file", d.file}, {"status", "error"}, {"error", d.error}});
                continue;
              }
              summary.push_back({{"part", d.name}, {"file", d.file}, {"status", "ok"},
                                 {"levels", d.metrics["levels"]}, {"retractions", d.metrics["retractions"]},
                                 {"cut_length_mm", d.metrics["cut_length_mm"]},
                                 {"time_adjusted_min", d.metrics["time_adjusted_min"]}});
              info("rough: " + d.name + ": " + d.metrics["levels"].dump() + " levels, cut " +
                   fixed(d.metrics["cut_length_mm"].get<double>(), 0) + " mm, " +
                   fixed(d.metrics["retractions"].get<double>(), 0) + " retractions, " +
                   fixed(d.metrics["time_adjusted_min"].get<double>(), 1) + " min → " +
                   (fs::path(o->out) / (d.name + ".nc")).string());
            }
            if (files.size() > 1) write_file_atomic(fs::path(o->out) / "rough_summary.json", summary.dump(2) + "\n");
            return failed ? 1 : 0;
          }};
}

namespace {

struct RunOpts {
  Common common;
  std::string config_file = "configs/default.json";
  std::string out;
};

/// The held-out parts: the config's list, or parts generated with their own seed.
std::vector<PredictInput> run_test_parts(const Json& config) {
  std::vector<PredictInput> parts;
  const Json& run = config["run"];
  if (!run["test_parts"].empty()) {
    for (const auto& p : run["test_parts"])
      parts.push_back({p["file"].get<std::string>(), p.value("name", std::string()), p["label"].get<int>(), nullptr});
  } else {
    datasets::GenerateParams g;
    g.seed = run["generate_test_parts"]["seed"].get<std::uint64_t>();
    g.per_family = run["generate_test_parts"]["per_family"].get<int>();
    g.resolution = config["dataset"]["generate"]["resolution"].get<int>();
    if (config["dataset"]["parts"].empty() && g.seed == config["dataset"]["generate"]["seed"].get<std::uint64_t>())
      throw Error("/run/generate_test_parts/seed equals /dataset/generate/seed: the test parts would be training parts");
    for (const auto& gp : datasets::generate_default_parts(run["test_parts_dir"].get<std::string>(), g))
      parts.push_back({gp.file, "test_" + gp.name, gp.label, nullptr});
  }
  return parts;
}

struct PartOutcomes {
  std::vector<PartPrediction> preds;
  std::vector<RoughOutcome> roughs;
  double predict_s = 0, rough_s = 0;
};

/// Predicts (and roughs, when /run/rough) every part into out/parts/<name>/: the model is read
/// once, each mesh once.
PartOutcomes predict_and_rough(const Json& config, const std::string& config_file,
                               const std::vector<PredictInput>& parts, const fs::path& out) {
  using clock = std::chrono::steady_clock;
  PartOutcomes po;
  auto& preds = po.preds;
  auto& roughs = po.roughs;
  auto& predict_s = po.predict_s;
  auto& rough_s = po.rough_s;
const Json explicit_pocket = explicit_pocket_section(config_file);
const rough::Params rp = rough_params(config, explicit_pocket, PocketFlags{});
const ModelFolder model = load_model_folder(out / "model", config);  // read once for all parts
const ingest::PrepareOptions prep = prepare_options(config["predict"]["units"], config["predict"]["up"]);
Progress progress("run: parts", parts.size());
for (const auto& p : parts) {
  const std::string name = p.name.empty() ? p.file.stem().string() : p.name;
  const fs::path dir = out / "parts" / name;
  auto t0 = clock::now();
  std::string load_error;
  PredictInput named = p;
  named.name = name;
  named.mesh = load_prepared(p.file, prep, &load_error);  // each mesh read once, for both steps
  auto pr = predict_parts(model, {named}, prep, dir);
  preds.push_back(pr.front());
  predict_s += std::chrono::duration<double>(clock::now() - t0).count();
  if (config["run"]["rough"].get<bool>()) {
    t0 = clock::now();
    roughs.push_back(rough_prepared(named.mesh.get(), load_error, p.file, name, rp, dir));
    rough_s += std::chrono::duration<double>(clock::now() - t0).count();
  }
  progress.tick();
}
progress.finish();
  return po;
}

/// summary.md and run_report.json; 1 when a part failed.
int write_run_summary(const std::string& config_file, const TrainSummary& ts, const PartOutcomes& po, const Json& timing,
                      const fs::path& out) {
  const auto& preds = po.preds;
  const auto& roughs = po.roughs;
std::ostringstream md;
md << "# millnet run: " << fs::path(config_file).filename().string() << "\n\n"
   << "Training set: " << ts.vectors << " vectors from " << ts.parts << " parts. Penalty coefficient α = "
   << fixed(ts.alpha, 4) << " chosen by leave-one-" << ts.mode << "-out"
   << (ts.edge != "none" ? " (at the " + ts.edge + " edge of the scan)" : std::string()) << ".\n"
   << "Verification accuracy: " << fixed(100 * ts.accuracy_part, 1) << " % leaving out whole parts, "
   << fixed(100 * ts.accuracy_vector, 1) << " % leaving out single vectors (the paper's LOO; optimistic, "
   << "since a vector's rotated siblings stay in).\n\n"
   << "![leave-one-out curve](model/loo_curve.png)\n\n"
   << "| part | expected | predicted strategy | confidence | consistency | unfamiliar | roughing time (min) | "
      "retractions | cut length (mm) | levels |\n|---|---:|---|---:|---:|---|---:|---:|---:|---:|\n";
std::size_t correct = 0, labelled = 0, failures = 0;
for (std::size_t i = 0; i < preds.size(); ++i) {
  const auto& pr = preds[i];
  md << "| [" << pr.name << "](parts/" << pr.name << "/) | " << (pr.expected ? std::to_string(pr.expected) : "-")
     << " | ";
  if (pr.ok) {
    md << pr.top << " " << pr.strategies[static_cast<std::size_t>(pr.top - 1)] << " | "
       << fixed(100 * pr.confidence, 0) << " % | " << fixed(100 * pr.consistency, 0) << " % | "
       << (pr.unfamiliar ? "yes" : "no") << " | ";
    if (pr.expected) {
      ++labelled;
      correct += pr.top == pr.expected ? 1 : 0;
    }
  } else {
    ++failures;
    md << "error: " << pr.error << " | | | | ";
  }
  if (i < roughs.size() && roughs[i].ok) {
    const Json& m = roughs[i].metrics;
    md << fixed(m["time_adjusted_min"].get<double>(), 1) << " | " << fixed(m["retractions"].get<double>(), 0) << " | "
       << fixed(m["cut_length_mm"].get<double>(), 0) << " | " << m["levels"].dump() << " |\n";
  } else if (i < roughs.size()) {
    ++failures;
    md << "error: " << roughs[i].error << " | | | |\n";
  } else {
    md << "- | - | - | - |\n";
  }
}
if (labelled)
  md << "\nHeld-out test parts predicted as their family's strategy: " << correct << " of " << labelled << ".\n";
md << "\n## Parts\n";
for (std::size_t i = 0; i < preds.size(); ++i) {
  const auto& pr = preds[i];
  md << "\n### " << pr.name << "\n\n";
  if (pr.ok) md << "![prediction](parts/" << pr.name << "/" << pr.name << ".png)\n";
  if (i < roughs.size() && roughs[i].ok) {
    const std::size_t levels = roughs[i].metrics["levels"].get<std::size_t>();
    md << "\nRoughing: [G-code](parts/" << pr.name << "/" << pr.name << ".nc), [metrics](parts/" << pr.name
       << "/" << pr.name << ".metrics.json). Top and bottom levels:\n\n"
       << "![level 1](parts/" << pr.name << "/" << pr.name << ".level_1.png)\n";
    if (levels > 1)
      md << "![level " << levels << "](parts/" << pr.name << "/" << pr.name << ".level_" << levels << ".png)\n";
  }
}
md << "\n## Time per stage\n\n| stage | seconds |\n|---|---:|\n";
for (auto it = timing.begin(); it != timing.end(); ++it) md << "| " << it.key() << " | " << fixed(it.value().get<double>(), 2) << " |\n";
write_file_atomic(out / "summary.md", md.str());
write_file_atomic(out / "run_report.json",
                  Json{{"timing", timing}, {"parts", preds.size()}, {"correct", correct}, {"labelled", labelled},
                       {"failures", failures}, {"alpha", ts.alpha}, {"accuracy_part", ts.accuracy_part},
                       {"accuracy_vector", ts.accuracy_vector}}
                          .dump(2) + "\n");
info("run: " + std::to_string(preds.size()) + " parts; summary → " + (out / "summary.md").string());
  return failures ? 1 : 0;
}

/// millnet run: dataset → train → test parts → predict and rough → summary.
int run_run(const RunOpts& o) {
  Common c = o.common;
  c.config = o.config_file;
  const Json config = setup(c);
  const fs::path out = o.out.empty() ? fs::path(config["output"].get<std::string>()) : fs::path(o.out);
  Json timing = Json::object();
  auto stage = [&](const char* name, auto&& fn) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    timing[name] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // 1. dataset (rebuilt only when the recipe or a part file changed)
  const fs::path ds_dir =
      config["dataset"].contains("output") ? fs::path(config["dataset"]["output"].get<std::string>()) : out / "dataset";
  stage("dataset_s", [&] { (void)build_dataset(recipe_from_config(config), ds_dir, true); });
  // 2. train
  TrainSummary ts;
  stage("train_s", [&] { ts = train_model(ds_dir / "vectors.csv", config, out / "model"); });
  // 3. test parts
  std::vector<PredictInput> parts;
  stage("test_parts_s", [&] { parts = run_test_parts(config); });
  // 4. predict and 5. rough, a folder per part
  const PartOutcomes po = predict_and_rough(config, o.config_file, parts, out);
  timing["predict_s"] = po.predict_s;
  timing["rough_s"] = po.rough_s;
  // 6. summary page
  return write_run_summary(o.config_file, ts, po, timing, out);
}

}  // namespace

Registered register_run(CLI::App& app) {
  auto o = std::make_shared<RunOpts>();
  CLI::App* sub = app.add_subcommand("run", "the whole pipeline: dataset → train → predict → rough, with a summary page");
  sub->add_option("config", o->config_file, "config file (default configs/default.json)")->check(CLI::ExistingFile);
  sub->add_option("--out", o->out, "output folder (default: /output of the config)");
  add_common(sub, o->common, false);
  return {sub, [o]() { return run_run(*o); }};
}

}  // namespace millnet::app
