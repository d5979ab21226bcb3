// millnet rough --mesh FILE … --out DIR   (or a batch: /rough/meshes of the config)
// millnet run [FILE] [--out DIR]          (dataset → train → predict → rough → finish on the test parts, summary page)
#include "cli.hpp"
#include "preview.hpp"
#include "finish_job.hpp"
#include "text.hpp"
#include "learn.hpp"
#include "rough.hpp"
#include "run_job.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/classifier/rank.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/report/run_summary.hpp"
#include "millnet/simulate/aim.hpp"

#include <chrono>
#include <iostream>
#include <memory>
#include <new>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct RoughOutcome {
  std::string name, file, error;
  bool ok = false;
  Json metrics;
  std::shared_ptr<const rough::Result> result;  ///< for the part's job
};

/// Roughs one loaded part (or reports `load_error` when it could not be read) into `out`.
RoughOutcome rough_prepared(const job::Part* part, const std::string& load_error, const fs::path& file,
                            const std::string& name, const rough::Params& params, const fs::path& out,
                            const CuttingRecord& cutting, const gcode::Dialect& post) {
  RoughOutcome o{name, file.string(), load_error, false, Json::object(), nullptr};
  if (!part) return o;
  try {
    // The holder must stay above the stock: the levels reach from the stock top to the last level,
    // /rough/floor_allowance_mm above the part's base (issue 38: the check ignored the allowance).
    const job::Frame frame = job::frame_of(part->mesh, params.top_allowance_mm);
    try {
      job::check_reach(cutting.tool.cutter(), cutting.tool.label(),
                       frame.depth_below_top(frame.part_bottom + params.floor_allowance_mm),
                       params.floor_allowance_mm > 0 ? "the last level" : "the part");
    } catch (const Error& e) {
      throw Error(file.string() + ": " + e.what());
    }
    OutputSet files;  // this part's files complete, or none of them (core/output_set.hpp)
    const auto result = std::make_shared<const rough::Result>(rough::rough_mesh(part->mesh, params));
    const rough::Result& r = *result;
    o.result = result;
    o.metrics = write_rough_outputs(out, name, r, params, post, cutting.to_json(), &part->mesh, cad_metrics(*part));
    files.commit();
    o.ok = r.machining.status == pocket::PlanStatus::Ok;
    if (!o.ok) o.error = file.string() + ": " + r.machining.message;
  } catch (const std::bad_alloc&) {
    o.error = file.string() + ": out of memory while roughing this part";
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  return o;
}

/// Reads and prepares a part; null and the reason when it cannot be read.
std::shared_ptr<const job::Part> load_prepared(const fs::path& file, const ingest::PrepareOptions& prep,
                                               std::string* error) {
  try {
    return std::make_shared<const job::Part>(load_part(file, prep));
  } catch (const std::bad_alloc&) {
    *error = file.string() + ": out of memory while reading this mesh";
    return nullptr;
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
}

RoughOutcome rough_one(const fs::path& file, const std::string& name, const ingest::PrepareOptions& prep,
                       const rough::Params& params, const fs::path& out, const CuttingRecord& cutting,
                       const gcode::Dialect& post) {
  std::string error;
  const auto part = load_prepared(file, prep, &error);
  return rough_prepared(part.get(), error, file, name, params, out, cutting, post);
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
  CLI::App* sub =
      app.add_subcommand("rough", "Z-level roughing of parts from their meshes → G-code, metrics, one PNG per level");
  sub->add_option("--mesh", o->meshes, "mesh file or folder (repeatable; added to /rough/meshes of the config)");
  o->mesh_flags.add_to(sub);
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  o->flags.add_to(sub, true, false);
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            std::vector<std::string> items = config["rough"]["meshes"].get<std::vector<std::string>>();
            items.insert(items.end(), o->meshes.begin(), o->meshes.end());
            if (items.empty()) throw Error("no mesh to rough: give --mesh FILE or set /rough/meshes in the config");
            const auto files = expand_inputs(items, ingest::mesh_extensions());
            CuttingRecord cutting;
            const rough::Params params =
                rough_params(config, explicit_pocket_section(o->common.config), o->flags, &cutting);
            if (!config["rough"]["stock_squared"].get<bool>())
              warn(
                  "/rough/stock_squared false: facing the sawn top is an operation of `millnet job`; `rough` "
                  "plans from the squared top Z 0");
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"], &config);
            const gcode::Dialect post = post_dialect(config, o->flags.post);
            std::vector<RoughOutcome> done;
            Progress progress("rough", files.size());
            for (const auto& f : files) {
              done.push_back(rough_one(f, f.stem().string(), prep, params, o->out, cutting, post));
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
              summary.push_back({{"part", d.name},
                                 {"file", d.file},
                                 {"status", "ok"},
                                 {"levels", d.metrics["levels"]},
                                 {"retractions", d.metrics["retractions"]},
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
  std::optional<std::string> post;  ///< --post (/machine/post)
  std::string config_file = "configs/default.json";
  std::string out;
};

/// The held-out parts: the config's list, or parts generated with their own seed.
std::vector<PredictInput> run_test_parts(const RunSettings& run) {
  std::vector<PredictInput> parts;
  for (const auto& p : run.test_parts) parts.push_back({p.file, p.name, p.label, nullptr});
  if (parts.empty())
    for (const auto& gp : datasets::generate_default_parts(run.generate_dir, run.generate))
      parts.push_back({gp.file, "test_" + gp.name, gp.label, nullptr});
  return parts;
}

/// One test part finished with every strategy (simulated), and its roughing + the network's top
/// strategy machined one after the other on one z-map.
struct FinishOutcome {
  bool ok = false;
  std::string error;
  std::vector<int> slots;                            ///< the strategies simulated, ascending
  std::vector<int> network_rank;                     ///< per slot: 1-based rank by the network's totals
  std::vector<int> simulated_rank;                   ///< per slot: 1-based rank by the simulation under the aim
  std::vector<double> ra_median_um;                  ///< per slot
  std::vector<double> time_min, regret, spec_share;  ///< per slot (job::OutcomeColumns)
  std::vector<int> meets_spec;                       ///< per slot
  double spearman = 0;
  bool chained = false;  ///< rough + top strategy simulated on one z-map
  Json chain;            ///< <name>.rough_finish.sim.json
  bool jobbed = false;   ///< /run/job: the part's job was attempted
  std::string job_error;
  RunJobResult job;
};

struct PartOutcomes {
  std::vector<PartPrediction> preds;
  std::vector<RoughOutcome> roughs;
  std::vector<FinishOutcome> finishes;
  double predict_s = 0, rough_s = 0, finish_s = 0;
  std::string finish_settings_note, aim;  ///< for the summary
};

/// Finishes the prepared part with every strategy (simulated, files in dir/finish/), then machines
/// the roughing program dir/<name>.nc and the top strategy's program one after the other on one
/// z-map from flat stock (dir/<name>.rough_finish.sim.json and its pictures).
/// With a `job` (/run/job), the part's job into dir/job/ (write_run_job), from the same roughing and
/// strategies.
struct RunJobRequest {
  const Json* config = nullptr;
  std::string config_file, mesh_file;
};
FinishOutcome finish_test_part(const job::Part& part, const std::string& name, const PartPrediction& pr,
                               const RoughOutcome* rough, const FinishSettings& configured,
                               const tooling::Cutter& rough_cutter, const fs::path& dir, const RunJobRequest& job) {
  FinishOutcome fo;
  try {
    const FinishSettings settings = for_part(configured, part);
    job::Part named = part;
    named.name = name;
    const PartFinish pf = finish_part(named, settings, dir / "finish");
    const job::OutcomeColumns cols = job::outcome_columns(pf.outcomes);
    fo.slots = cols.slots;
    fo.simulated_rank = cols.ranks;
    fo.ra_median_um = cols.ra_median_um;
    fo.time_min = cols.time_min;
    fo.regret = cols.regret;
    fo.spec_share = cols.spec_share;
    fo.meets_spec = cols.meets_spec;
    if (pr.ok) {
      fo.network_rank = classifier::slot_ranks(pr.totals, fo.slots);  // the paper's Figure 8 totals
      fo.spearman = simulate::spearman(fo.network_rank, fo.simulated_rank);
    }
    const auto top = std::find(fo.slots.begin(), fo.slots.end(), pr.top);
    if (pr.ok && rough != nullptr && rough->ok && top != fo.slots.end()) {
      const fs::path finish_nc = dir / "finish" / (name + ".s" + std::to_string(pr.top) + ".nc");
      fo.chain =
          simulate_programs(named, name + ".rough_finish",
                            {read_chain_program(dir / (name + ".nc"), rough_cutter, pf.frame.post(settings.post)),
                             read_chain_program(finish_nc, settings.params.tool, pf.frame.post(settings.post))},
                            "flat", settings, dir, false, pf.design ? &*pf.design : nullptr);
      fo.chained = true;
    }
    fo.ok = true;
    if (job.config != nullptr) {
      fo.jobbed = true;
      try {
        const RunJobInput in{&named, &pf, dir / "finish",
                             rough != nullptr && rough->ok ? rough->result.get() : nullptr};
        fo.job = write_run_job(*job.config, job.config_file, job.mesh_file, in, dir / "job");
      } catch (const std::exception& e) {
        fo.job_error = e.what();
      }
    }
  } catch (const std::exception& e) {
    fo.error = e.what();
  }
  return fo;
}

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
  CuttingRecord rough_cutting;
  const rough::Params rp = rough_params(config, explicit_pocket, PocketFlags{}, &rough_cutting);
  const RunSettings run = run_settings(config);
  const FinishSettings fset = simulated_finish_settings(config);
  po.finish_settings_note = fset.params.tool.describe() + ", p_f " + fixed(fset.params.stepover_mm, 2) + " mm, a_a " +
                            fixed(fset.params.step_down_mm, 2) + " mm, " + fixed(fset.params.feed_mm_min, 0) +
                            " mm/min";
  po.aim = simulate::to_string(fset.aim.aim);
  const ModelFolder model = load_model_folder(out / "model", config);  // read once for all parts
  ingest::PrepareOptions prep = prepare_options(config["predict"]["units"], config["predict"]["up"]);
  prep.units_explicit = config["predict"]["units"].get<std::string>() != "mm";
  prep.cad = cad_options(config);
  Progress progress("run: parts", parts.size());
  for (const auto& p : parts) {
    const std::string name = p.name.empty() ? p.file.stem().string() : p.name;
    const fs::path dir = out / "parts" / name;
    auto t0 = clock::now();
    std::string load_error;
    PredictInput named = p;
    named.name = name;
    named.part = load_prepared(p.file, prep, &load_error);  // each part read once, for both steps
    auto pr = predict_parts(model, {named}, prep, dir);
    preds.push_back(pr.front());
    predict_s += std::chrono::duration<double>(clock::now() - t0).count();
    if (run.rough) {
      t0 = clock::now();
      roughs.push_back(rough_prepared(named.part.get(), load_error, p.file, name, rp, dir, rough_cutting, fset.post));
      rough_s += std::chrono::duration<double>(clock::now() - t0).count();
    }
    if (run.finish) {
      t0 = clock::now();
      if (named.part) {
        const RunJobRequest job{run.job ? &config : nullptr, config_file, p.file.string()};
        po.finishes.push_back(finish_test_part(*named.part, name, preds.back(),
                                               roughs.empty() ? nullptr : &roughs.back(), fset, rp.cut.tool, dir, job));
      } else {
        FinishOutcome failed;
        failed.error = load_error;
        po.finishes.push_back(std::move(failed));
      }
      po.finish_s += std::chrono::duration<double>(clock::now() - t0).count();
    }
    progress.tick();
  }
  progress.finish();
  return po;
}

/// The summary's values of the run: the training's, then per part what each stage gave.
report::RunSummary run_summary(const std::string& config_file, const TrainSummary& ts, const PartOutcomes& po,
                               const Json& timing) {
  report::RunSummary s;
  s.config_name = fs::path(config_file).filename().string();
  s.vectors = ts.vectors;
  s.training_parts = ts.parts;
  s.alpha = ts.alpha;
  s.loo_mode = ts.mode;
  s.alpha_edge = ts.edge;
  s.accuracy_part = ts.accuracy_part;
  s.accuracy_vector = ts.accuracy_vector;
  s.scores = ts.scores;
  s.criterion = ts.criterion == "regret" ? "mean regret of the parts' picks" : "RMS error of the outputs";
  s.lopo_parts = ts.regret.parts;
  s.lopo_misses = ts.regret.misses;
  s.lopo_top1 = ts.regret.top1;
  s.lopo_mean = ts.regret.mean;
  s.lopo_median = ts.regret.median;
  s.lopo_p90 = ts.regret.p90;
  s.baseline_slot = static_cast<int>(ts.baseline.slot) + 1;
  s.baseline_top1 = ts.baseline.figures.top1;
  s.baseline_mean = ts.baseline.figures.mean;
  s.baseline_median = ts.baseline.figures.median;
  s.baseline_p90 = ts.baseline.figures.p90;
  s.finish_settings_note = po.finish_settings_note;
  s.aim = po.aim;
  for (auto it = timing.begin(); it != timing.end(); ++it) s.timing_s.emplace_back(it.key(), it.value().get<double>());
  for (std::size_t i = 0; i < po.preds.size(); ++i) {  // O(parts)
    const PartPrediction& pr = po.preds[i];
    report::RunPart p;
    p.name = pr.name;
    p.expected = pr.expected;
    p.predicted = pr.ok;
    p.predict_error = pr.error;
    p.top = pr.top;
    if (pr.ok) p.top_name = pr.strategies[static_cast<std::size_t>(pr.top - 1)];
    p.confidence = pr.confidence;
    p.consistency = pr.consistency;
    p.unfamiliar = pr.unfamiliar;
    if (i < po.roughs.size()) {
      const RoughOutcome& r = po.roughs[i];
      p.roughed = true;
      p.rough_ok = r.ok;
      p.rough_error = r.error;
      if (r.ok) {
        p.rough_time_min = r.metrics["time_adjusted_min"].get<double>();
        p.retractions = r.metrics["retractions"].get<double>();
        p.cut_length_mm = r.metrics["cut_length_mm"].get<double>();
        p.levels = r.metrics["levels"].get<std::size_t>();
      }
    }
    if (i < po.finishes.size()) {
      const FinishOutcome& f = po.finishes[i];
      p.finished = true;
      p.finish_ok = f.ok;
      p.finish_error = f.error;
      p.slots = f.slots;
      p.network_rank = f.network_rank;
      p.simulated_rank = f.simulated_rank;
      p.ra_median_um = f.ra_median_um;
      p.time_min = f.time_min;
      p.regret = f.regret;
      p.spec_share = f.spec_share;
      p.meets_spec = f.meets_spec;
      p.spearman = f.spearman;
      p.chained = f.chained;
      if (f.chained) {
        const Json& c = f.chain;
        p.chain_finisher_depth_of_cut_mm = c["programs"][1]["max_depth_of_cut_mm"].get<double>();
        p.chain_ra_median_um = c["ra_median_um"].get<double>();
        p.chain_uncut_mm2 = c["uncut_area_mm2"].get<double>();
        p.chain_rest_mm2 = c["rest_area_mm2"].get<double>();
        p.chain_gouge_mm = c["max_gouge_mm"].get<double>();
        p.chain_scallop_max_mm = c["scallop_max_mm"].get<double>();
      }
      p.jobbed = f.jobbed;
      if (f.jobbed) {
        p.job_error = f.job_error;
        p.job_ok = f.job_error.empty() && !f.job.gouged;
        if (f.job_error.empty()) {
          p.job_program = f.job.program.filename().string();
          if (f.job.gouged) p.job_error = f.job.program.string() + " gouges the part";
        }
        p.job_strategy = f.job.strategy;
        p.job_operations = f.job.operations;
        p.job_tool_changes = f.job.tool_changes;
        p.job_time_min = f.job.cycle_time_min;
        p.job_gouge_mm = f.job.max_gouge_mm;
      }
    }
    s.parts.push_back(std::move(p));
  }
  return s;
}

/// Per part: both rankings (slot order, best first), ρ, and the rough + top chain's figures.
Json finishing_json(const report::RunSummary& s) {
  Json out = Json::array();
  for (const report::RunPart& p : s.parts) {  // O(parts)
    if (!p.finished) continue;
    Json j{{"part", p.name}, {"status", p.finish_ok ? "ok" : "error"}};
    if (!p.finish_ok) {
      j["error"] = p.finish_error;
      out.push_back(j);
      continue;
    }
    j["simulated_ranking"] = simulate::slots_by_rank(p.slots, p.simulated_rank);
    j["ra_median_um"] = p.ra_median_um;
    j["time_kinematic_min"] = p.time_min;
    auto or_null = [](const std::vector<double>& v) {  // NaN (unmeasured) as null
      Json a = Json::array();
      for (const double x : v) a.push_back(std::isnan(x) ? Json(nullptr) : Json(x));
      return a;
    };
    j["regret"] = or_null(p.regret);
    j["share_in_spec"] = or_null(p.spec_share);
    j["meets_spec"] = p.meets_spec;
    if (!p.network_rank.empty()) {
      j["network_ranking"] = simulate::slots_by_rank(p.slots, p.network_rank);
      j["spearman"] = p.spearman;
      const double r = report::pick_regret(p);
      j["network_pick_regret"] = std::isnan(r) ? Json(nullptr) : Json(r);
    }
    if (p.chained)
      j["rough_then_top"] = {{"strategy", p.top},
                             {"finisher_max_depth_of_cut_mm", p.chain_finisher_depth_of_cut_mm},
                             {"ra_median_um", p.chain_ra_median_um},
                             {"uncut_area_mm2", p.chain_uncut_mm2},
                             {"rest_area_mm2", p.chain_rest_mm2},
                             {"scallop_max_mm", p.chain_scallop_max_mm},
                             {"max_gouge_mm", p.chain_gouge_mm}};
    if (p.jobbed)
      j["job"] = p.job_program.empty()
                     ? Json{{"status", "error"}, {"error", p.job_error}}
                     : Json{{"status", p.job_ok ? "ok" : "error"}, {"program", "job/" + p.job_program},
                            {"strategy", p.job_strategy},          {"operations", p.job_operations},
                            {"tool_changes", p.job_tool_changes},  {"total_time_min", p.job_time_min},
                            {"max_gouge_mm", p.job_gouge_mm}};
    out.push_back(j);
  }
  return out;
}

/// summary.md, summary.html and run_report.json; 1 when a part failed.
/// The network judged by its regret leaving out each training part (issue 39), beside always one strategy.
Json training_regret_json(const TrainSummary& ts) {
  if (!ts.scores) return nullptr;
  const auto fig = [](const classifier::RegretSummary& r) {
    return Json{{"parts", r.parts},          {"top1", r.top1},      {"mean_regret", r.mean},
                {"median_regret", r.median}, {"p90_regret", r.p90}, {"misses", r.misses}};
  };
  Json b = fig(ts.baseline.figures);
  b["strategy"] = ts.baseline.slot + 1;
  return Json{{"criterion", ts.criterion}, {"network", fig(ts.regret)}, {"always_the_same_strategy", b}};
}

int write_run_summary(const std::string& config_file, const TrainSummary& ts, const PartOutcomes& po,
                      const Json& timing, const fs::path& out, const std::string& labels_file) {
  report::RunSummary s = run_summary(config_file, ts, po, timing);
  s.labels_file = labels_file;
  const report::RunCounts c = report::run_counts(s);
  write_file_atomic(out / "summary.md", report::run_summary_md(s));
  if (preview_settings().enabled)  // summary.html: the table, each part's 3D pages, charts (issue 16)
    report::write_summary_html(out / "summary.html", report::run_summary_page(s));
  write_file_atomic(out / "run_report.json", Json{{"timing", timing},
                                                  {"parts", s.parts.size()},
                                                  {"correct", c.correct},
                                                  {"labelled", c.labelled},
                                                  {"failures", c.failures},
                                                  {"alpha", ts.alpha},
                                                  {"accuracy_part", ts.accuracy_part},
                                                  {"accuracy_vector", ts.accuracy_vector},
                                                  {"training_regret", training_regret_json(ts)},
                                                  {"finishing", finishing_json(s)}}
                                                     .dump(2) +
                                                 "\n");
  info("run: " + std::to_string(s.parts.size()) + " parts; summary → " + (out / "summary.md").string());
  return c.failures ? 1 : 0;
}

/// millnet run: dataset → train → test parts → predict and rough → summary.
int run_run(const RunOpts& o) {
  Common c = o.common;
  c.config = o.config_file;
  Json config = setup(c);
  if (o.post) config["machine"]["post"] = *o.post;  // --post wins over /machine/post for every program
  const fs::path out = o.out.empty() ? fs::path(config["output"].get<std::string>()) : fs::path(o.out);
  // Every setting of every stage is checked before the first stage writes anything (issue 15: a
  // seed clash was found after nine files were written; tests/corpus/cli/run_seed_clash.args).
  try {
    (void)run_settings(config);
    (void)rough_params(config, explicit_pocket_section(o.config_file), PocketFlags{});
    (void)simulated_finish_settings(config);
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.find(o.config_file) != std::string::npos) throw;
    throw file_error(o.config_file, what);
  }
  Json timing = Json::object();
  auto stage = [&](const char* name, auto&& fn) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    timing[name] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // 1. dataset (rebuilt only when the recipe or a part file changed)
  const fs::path ds_dir =
      config["dataset"].contains("output") ? fs::path(config["dataset"]["output"].get<std::string>()) : out / "dataset";
  const auto recipe = recipe_from_config(config);
  stage("dataset_s", [&] { (void)build_dataset(recipe, ds_dir, true, config); });
  // 2. train
  TrainSummary ts;
  stage("train_s", [&] { ts = train_model(ds_dir / "vectors.csv", config, out / "model"); });
  // 3. test parts
  std::vector<PredictInput> parts;
  stage("test_parts_s", [&] { parts = run_test_parts(run_settings(config)); });
  // 4. predict and 5. rough, a folder per part
  const PartOutcomes po = predict_and_rough(config, o.config_file, parts, out);
  timing["predict_s"] = po.predict_s;
  timing["rough_s"] = po.rough_s;
  if (!po.finishes.empty()) timing["finish_s"] = po.finish_s;
  // 6. summary page
  return write_run_summary(o.config_file, ts, po, timing, out, fs::path(recipe.labels_file).filename().string());
}

}  // namespace

Registered register_run(CLI::App& app) {
  auto o = std::make_shared<RunOpts>();
  CLI::App* sub = app.add_subcommand(
      "run", "the whole pipeline: dataset → train → predict → rough → finish (simulated), with a summary page");
  sub->add_option("config", o->config_file, "config file (default configs/default.json)")->check(CLI::ExistingFile);
  sub->add_option("--out", o->out, "output folder (default: /output of the config)")->check(output_path());
  add_common(sub, o->common, false);
  add_post_flag(sub, o->post);
  return {sub, [o]() { return run_run(*o); }};
}

}  // namespace millnet::app
