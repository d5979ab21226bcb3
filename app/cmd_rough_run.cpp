// millnet rough --mesh FILE … --out DIR   (or a batch: /rough/meshes of the config)
// millnet run [FILE] [--out DIR]          (dataset → train → predict → rough → finish on the test parts, summary page)
#include "cli.hpp"
#include "preview.hpp"
#include "finish_job.hpp"
#include "text.hpp"
#include "learn.hpp"
#include "rough.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/classifier/rank.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
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
};

/// Roughs one loaded part (or reports `load_error` when it could not be read) into `out`.
RoughOutcome rough_prepared(const job::Part* part, const std::string& load_error, const fs::path& file,
                            const std::string& name, const rough::Params& params, const fs::path& out,
                            const CuttingRecord& cutting, const gcode::Dialect& post) {
  RoughOutcome o{name, file.string(), load_error, false, Json::object()};
  if (!part) return o;
  try {
    // The holder must stay above the stock: the levels reach from the stock top to the part's base.
    const job::Frame frame = job::frame_of(part->mesh, params.top_allowance_mm);
    try {
      job::check_reach(cutting.tool.cutter(), cutting.tool.label(), frame.depth_below_top(frame.part_bottom),
                       "the part");
    } catch (const Error& e) {
      throw Error(file.string() + ": " + e.what());
    }
    OutputSet files;  // this part's files complete, or none of them (core/output_set.hpp)
    const rough::Result r = rough::rough_mesh(part->mesh, params);
    o.metrics = write_rough_outputs(out, name, r, params, cutting.tool.cutter(), post, cutting.to_json(), &part->mesh,
                                    cad_metrics(*part));
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
  std::vector<int> slots;            ///< the strategies simulated, ascending
  std::vector<int> network_rank;     ///< per slot: 1-based rank by the network's totals
  std::vector<int> simulated_rank;   ///< per slot: 1-based rank by the simulation under the aim
  std::vector<double> ra_median_um;  ///< per slot
  double spearman = 0;
  bool chained = false;  ///< rough + top strategy simulated on one z-map
  Json chain;            ///< <name>.rough_finish.sim.json
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
FinishOutcome finish_test_part(const job::Part& part, const std::string& name, const PartPrediction& pr,
                               const RoughOutcome* rough, const FinishSettings& settings,
                               const tooling::Cutter& rough_cutter, const fs::path& dir) {
  FinishOutcome fo;
  try {
    job::Part named = part;
    named.name = name;
    const PartFinish pf = finish_part(named, settings, dir / "finish");
    for (const auto& o : pf.outcomes) {
      fo.slots.push_back(static_cast<int>(o.strategy));
      fo.simulated_rank.push_back(o.rank);
      fo.ra_median_um.push_back(o.score.ra_median_um);
    }
    if (pr.ok) {
      fo.network_rank = classifier::slot_ranks(pr.totals, fo.slots);  // the paper's Figure 8 totals
      fo.spearman = simulate::spearman(fo.network_rank, fo.simulated_rank);
    }
    const auto top = std::find(fo.slots.begin(), fo.slots.end(), pr.top);
    if (pr.ok && rough != nullptr && rough->ok && top != fo.slots.end()) {
      const fs::path finish_nc = dir / "finish" / (name + ".s" + std::to_string(pr.top) + ".nc");
      fo.chain = simulate_programs(
          named, name + ".rough_finish",
          {read_chain_program(dir / (name + ".nc"), rough_cutter), read_chain_program(finish_nc, settings.params.tool)},
          "flat", settings, dir, false, pf.design ? &*pf.design : nullptr);
      fo.chained = true;
    }
    fo.ok = true;
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
      if (named.part)
        po.finishes.push_back(finish_test_part(*named.part, name, preds.back(),
                                               roughs.empty() ? nullptr : &roughs.back(), fset,
                                               rough_cutting.tool.cutter(), dir));
      else
        po.finishes.push_back(FinishOutcome{false, load_error, {}, {}, {}, {}, 0, false, Json()});
      po.finish_s += std::chrono::duration<double>(clock::now() - t0).count();
    }
    progress.tick();
  }
  progress.finish();
  return po;
}

/// Per part: both rankings (slot order, best first), ρ, and the rough + top chain's figures.
Json finishing_json(const PartOutcomes& po) {
  Json out = Json::array();
  for (std::size_t i = 0; i < po.finishes.size() && i < po.preds.size(); ++i) {
    const auto& f = po.finishes[i];
    Json j{{"part", po.preds[i].name}, {"status", f.ok ? "ok" : "error"}};
    if (!f.ok) {
      j["error"] = f.error;
      out.push_back(j);
      continue;
    }
    j["simulated_ranking"] = simulate::slots_by_rank(f.slots, f.simulated_rank);
    j["ra_median_um"] = f.ra_median_um;
    if (!f.network_rank.empty()) {
      j["network_ranking"] = simulate::slots_by_rank(f.slots, f.network_rank);
      j["spearman"] = f.spearman;
    }
    if (f.chained) {
      const Json& c = f.chain;
      j["rough_then_top"] = {{"strategy", po.preds[i].top},
                             {"finisher_max_depth_of_cut_mm", c["programs"][1]["max_depth_of_cut_mm"]},
                             {"ra_median_um", c["ra_median_um"]},
                             {"uncut_area_mm2", c["uncut_area_mm2"]},
                             {"rest_area_mm2", c["rest_area_mm2"]},
                             {"scallop_max_mm", c["scallop_max_mm"]},
                             {"max_gouge_mm", c["max_gouge_mm"]}};
    }
    out.push_back(j);
  }
  return out;
}

/// summary.md and run_report.json; 1 when a part failed.
int write_run_summary(const std::string& config_file, const TrainSummary& ts, const PartOutcomes& po,
                      const Json& timing, const fs::path& out) {
  const auto& preds = po.preds;
  const auto& roughs = po.roughs;
  std::ostringstream md;
  md << "# millnet run: " << fs::path(config_file).filename().string() << "\n\n"
     << "Training set: " << ts.vectors << " vectors from " << ts.parts
     << " parts. Penalty coefficient α = " << fixed(ts.alpha, 4) << " chosen by leave-one-" << ts.mode << "-out"
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
  if (!po.finishes.empty()) {
    md << "\n## Finishing: the network's ranking beside the simulated one\n\n"
       << "Every part finished with the five strategies (" << po.finish_settings_note << "), each program read back "
       << "and machined on a z-map from the design + finishing stock, ranked by the aim (" << po.aim << "); the "
       << "network ranks them by its totals over the variants (the paper's Figure 8 beside its Figure 9). ρ is "
       << "Spearman's rank correlation of the two rankings (1 = same order, −1 = reversed). Then the roughing "
       << "program and the network's top strategy machined one after the other on one z-map from flat stock. "
       << "Material left above the design by more than the tolerance (along the surface normal) is a scallop "
       << "when it lies between passes that reached the design within the tool's radius on both sides, rest "
       << "material when the finishing tool cannot reach the design there (a concave corner tighter than it: "
       << "the same for every strategy), and uncut otherwise.\n\n"
       << "| part | network ranking | simulated ranking | ρ | top strategy's simulated rank | Ra median of the "
          "top (µm) | best Ra median (µm) | rough + top: deepest cut of the finisher (mm) | rough + top: Ra median "
          "(µm) | rough + top: uncut (mm²) | rough + top: rest material (mm²) | rough + top: gouge (mm) |\n"
       << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    auto order_text = [](const std::vector<int>& slots, const std::vector<int>& rank) {
      const std::vector<int> by = simulate::slots_by_rank(slots, rank);
      std::string t;
      for (std::size_t r = 0; r < by.size(); ++r) t += (r ? " > " : "") + std::to_string(by[r]);
      return t;
    };
    double rho_sum = 0;
    std::size_t rho_n = 0;
    for (std::size_t i = 0; i < po.finishes.size() && i < preds.size(); ++i) {
      const auto& f = po.finishes[i];
      const auto& pr = preds[i];
      md << "| " << pr.name << " | ";
      if (!f.ok) {
        ++failures;
        md << "error: " << f.error << " | | | | | | | | | |\n";
        continue;
      }
      const double best = *std::min_element(f.ra_median_um.begin(), f.ra_median_um.end());
      const auto top = std::find(f.slots.begin(), f.slots.end(), pr.top);
      const std::size_t ti = static_cast<std::size_t>(top - f.slots.begin());
      md << (f.network_rank.empty() ? "-" : order_text(f.slots, f.network_rank)) << " | "
         << order_text(f.slots, f.simulated_rank) << " | " << (f.network_rank.empty() ? "-" : fixed(f.spearman, 2))
         << " | " << (top != f.slots.end() ? std::to_string(f.simulated_rank[ti]) : "-") << " | "
         << (top != f.slots.end() ? fixed(f.ra_median_um[ti], 2) : "-") << " | " << fixed(best, 2) << " | ";
      if (!f.network_rank.empty()) rho_sum += f.spearman, ++rho_n;
      if (f.chained) {
        const Json& c = f.chain;
        md << fixed(c["programs"][1]["max_depth_of_cut_mm"].get<double>(), 2) << " | "
           << fixed(c["ra_median_um"].get<double>(), 2) << " | " << fixed(c["uncut_area_mm2"].get<double>(), 1) << " | "
           << fixed(c["rest_area_mm2"].get<double>(), 1) << " | " << fixed(c["max_gouge_mm"].get<double>(), 4)
           << " |\n";
      } else {
        md << "- | - | - | - | - |\n";
      }
    }
    if (rho_n) md << "\nMean ρ over " << rho_n << " parts: " << fixed(rho_sum / static_cast<double>(rho_n), 2) << ".\n";
  }
  md << "\n## Parts\n";
  for (std::size_t i = 0; i < preds.size(); ++i) {
    const auto& pr = preds[i];
    md << "\n### " << pr.name << "\n\n";
    if (pr.ok) md << "![prediction](parts/" << pr.name << "/" << pr.name << ".png)\n";
    if (i < roughs.size() && roughs[i].ok) {
      const std::size_t levels = roughs[i].metrics["levels"].get<std::size_t>();
      md << "\nRoughing: [G-code](parts/" << pr.name << "/" << pr.name << ".nc), [metrics](parts/" << pr.name << "/"
         << pr.name << ".metrics.json). Top and bottom levels:\n\n"
         << "![level 1](parts/" << pr.name << "/" << pr.name << ".level_1.png)\n";
      if (levels > 1)
        md << "![level " << levels << "](parts/" << pr.name << "/" << pr.name << ".level_" << levels << ".png)\n";
    }
    if (i < po.finishes.size() && po.finishes[i].ok) {
      const std::string d = "parts/" + pr.name + "/";
      md << "\nFinishing: [the five strategies ranked](" << d << "finish/" << pr.name << ".strategies.md); share of "
         << "the surface per Ra bin, per strategy:\n\n![Ra per strategy](" << d << "finish/" << pr.name
         << ".strategies.png)\n";
      if (po.finishes[i].chained)
        md << "\nRoughing, then strategy " << pr.top << ", on one z-map ([figures](" << d << pr.name
           << ".rough_finish.sim.json)):\n\n![Ra](" << d << pr.name << ".rough_finish.ra.png) ![machined − design]("
           << d << pr.name << ".rough_finish.deviation.png)\n";
    }
  }
  md << "\n## Time per stage\n\n| stage | seconds |\n|---|---:|\n";
  for (auto it = timing.begin(); it != timing.end(); ++it)
    md << "| " << it.key() << " | " << fixed(it.value().get<double>(), 2) << " |\n";
  write_file_atomic(out / "summary.md", md.str());
  if (preview_settings().enabled) {  // summary.html: the table, each part's 3D pages, charts (issue 16)
    report::SummaryPage page;
    page.title = "millnet run: " + fs::path(config_file).filename().string();
    page.header = {"part",
                   "expected",
                   "predicted strategy",
                   "confidence",
                   "roughing time (min)",
                   "retractions",
                   "cut length (mm)",
                   "levels",
                   "3D preview"};
    report::SummaryChart time_chart{"roughing time per part", "min", {}, {{"roughing time (min)", {}}}};
    report::SummaryChart ra_chart{"finishing: simulated Ra median per strategy", "Ra median (µm)", {}, {}};
    for (std::size_t i = 0; i < preds.size(); ++i) {
      const auto& pr = preds[i];
      std::vector<std::string> row{pr.name, pr.expected ? std::to_string(pr.expected) : "-"};
      if (pr.ok)
        row.insert(row.end(), {std::to_string(pr.top) + " " + pr.strategies[static_cast<std::size_t>(pr.top - 1)],
                               fixed(100 * pr.confidence, 0) + " %"});
      else
        row.insert(row.end(), {"error: " + pr.error, ""});
      if (i < roughs.size() && roughs[i].ok) {
        const Json& m = roughs[i].metrics;
        row.insert(row.end(), {fixed(m["time_adjusted_min"].get<double>(), 1), fixed(m["retractions"].get<double>(), 0),
                               fixed(m["cut_length_mm"].get<double>(), 0), m["levels"].dump(),
                               "link:roughing|parts/" + pr.name + "/" + pr.name + ".html"});
        time_chart.labels.push_back(pr.name);
        time_chart.series[0].second.push_back(m["time_adjusted_min"].get<double>());
        page.previews.emplace_back(pr.name + ": roughing", "parts/" + pr.name + "/" + pr.name + ".html");
      } else {
        row.insert(row.end(), {"", "", "", "", ""});
      }
      page.rows.push_back(row);
      if (i < po.finishes.size() && po.finishes[i].ok) {
        const auto& f = po.finishes[i];
        ra_chart.labels.push_back(pr.name);
        for (std::size_t k = 0; k < f.slots.size(); ++k) {
          const std::string sname = "strategy " + std::to_string(f.slots[k]);
          auto it = std::find_if(ra_chart.series.begin(), ra_chart.series.end(),
                                 [&](const auto& x) { return x.first == sname; });
          if (it == ra_chart.series.end()) {
            ra_chart.series.emplace_back(sname, std::vector<double>(ra_chart.labels.size() - 1, std::nan("")));
            it = ra_chart.series.end() - 1;
          }
          it->second.push_back(f.ra_median_um[k]);
          page.previews.emplace_back(
              pr.name + ": finishing, " + sname,
              "parts/" + pr.name + "/finish/" + pr.name + ".s" + std::to_string(f.slots[k]) + ".html");
        }
        for (auto& sr : ra_chart.series) sr.second.resize(ra_chart.labels.size(), std::nan(""));
        if (f.chained)
          page.previews.emplace_back(pr.name + ": roughing + top strategy, simulated",
                                     "parts/" + pr.name + "/" + pr.name + ".rough_finish.html");
      }
    }
    if (!time_chart.labels.empty()) page.charts.push_back(time_chart);
    if (!ra_chart.labels.empty()) page.charts.push_back(ra_chart);
    report::write_summary_html(out / "summary.html", page);
  }
  write_file_atomic(out / "run_report.json", Json{{"timing", timing},
                                                  {"parts", preds.size()},
                                                  {"correct", correct},
                                                  {"labelled", labelled},
                                                  {"failures", failures},
                                                  {"alpha", ts.alpha},
                                                  {"accuracy_part", ts.accuracy_part},
                                                  {"accuracy_vector", ts.accuracy_vector},
                                                  {"finishing", finishing_json(po)}}
                                                     .dump(2) +
                                                 "\n");
  info("run: " + std::to_string(preds.size()) + " parts; summary → " + (out / "summary.md").string());
  return failures ? 1 : 0;
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
  stage("dataset_s", [&] { (void)build_dataset(recipe_from_config(config), ds_dir, true, config); });
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
  return write_run_summary(o.config_file, ts, po, timing, out);
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
