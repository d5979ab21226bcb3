#include "learn.hpp"

#include "cli.hpp"
#include "finish_job.hpp"
#include "mpi_cluster.hpp"
#include "text.hpp"
#include "report_util.hpp"

#include "millnet/augment/variants.hpp"
#include "millnet/classifier/rank.hpp"
#include "millnet/classifier/io/model_file.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/datasets/agreement.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/datasets/io/manifest.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/report/plots.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

/// A number as the manifest's writer (format_double) spells it once parsed: integral values as
/// JSON integers ("1", not "1.0"), so that sampling.json keeps its bytes.
Json number_json(double v) {
  if (std::isfinite(v) && std::abs(v) < 9007199254740992.0 && v == std::trunc(v)) return Json(static_cast<std::int64_t>(v));
  return Json(v);
}

std::string strategy_name(const std::vector<std::string>& names, int slot) {
  return slot >= 1 && static_cast<std::size_t>(slot) <= names.size() ? names[static_cast<std::size_t>(slot - 1)]
                                                                       : std::string("?");
}

}  // namespace

namespace {

/// One part's strategies as the simulation ranked them.
struct SimulatedLabel {
  std::string name;
  int recipe_label = 0;  ///< the recipe's label (0 for a part labelled by simulation)
  int best = 0;          ///< the slot ranked first
  Json figures;          ///< per strategy
};

/// Plans and simulates the five strategies on recipe part k (files in dir/<name>/). Throws
/// millnet::Error naming the part.
SimulatedLabel simulate_label(const datasets::Recipe& recipe, std::size_t k, const FinishSettings& settings,
                              const fs::path& dir) {
  ingest::PrepareOptions prep;
  prep.units = recipe.units;
  prep.units_explicit = recipe.units_explicit;
  prep.cad = recipe.cad;
  prep.up = recipe.up;
  const datasets::PartSpec& p = recipe.parts[k];
  const std::string name = p.name.empty() ? p.file.stem().string() : p.name;
  SimulatedLabel sl{name, p.label_by_simulation ? 0 : p.label, 0, Json::array()};
  try {
    const ingest::Mesh mesh = load_part(p.file, prep);
    for (const StrategyOutcome& o : finish_part(mesh, name, settings, dir / name, cad_metrics(p.file))) {
      if (o.rank == 1) sl.best = static_cast<int>(o.strategy);
      sl.figures.push_back(Json{{"strategy", static_cast<int>(o.strategy)},
                                {"rank", o.rank},
                                {"ra_median_um", o.score.ra_median_um},
                                {"ra_p90_um", o.score.ra_p90_um},
                                {"uncut_area_mm2", o.score.uncut_area_mm2},
                                {"max_gouge_mm", o.score.max_gouge_mm},
                                {"time_kinematic_min", o.score.time_min}});
    }
  } catch (const std::exception& e) {
    throw Error("dataset: part '" + name + "' (" + p.file.string() + "): labelling by simulation: " + e.what());
  }
  return sl;
}

/// Plans and simulates the five strategies on each part (files in dir/<name>/) and returns the
/// slot the aim ranks first. A part that fails stops the build (all-or-nothing, as the table).
/// Under MPI the work unit is a part: its programs, metrics and pictures come back to rank 0 as
/// bytes and are written there, in part order, as soon as the parts before them are in.
std::vector<SimulatedLabel> simulate_labels(const datasets::Recipe& recipe, const std::vector<std::size_t>& which,
                                            const FinishSettings& settings, const fs::path& dir) {
  std::vector<SimulatedLabel> out;
  if (cluster_size() == 1) {
    Progress progress("dataset: labels by simulation", which.size());
    for (const std::size_t k : which) {
      out.push_back(simulate_label(recipe, k, settings, dir));
      progress.tick();
    }
    progress.finish();
    return out;
  }
  const auto work = [&](std::size_t i) {
    SimulatedLabel sl;
    std::string files = write_and_pack([&](const std::string& scratch) { sl = simulate_label(recipe, which[i], settings, scratch); });
    const std::vector<std::uint8_t> cbor =
        Json::to_cbor(Json{{"name", sl.name}, {"recipe_label", sl.recipe_label}, {"best", sl.best}, {"figures", sl.figures}});
    std::string msg;
    put_bytes(msg, std::string(cbor.begin(), cbor.end()));
    put_bytes(msg, files);
    return msg;
  };
  const auto take = [&](std::size_t, bool ok, std::string&& bytes) {
    if (!ok) throw Error(bytes);  // the part's own message (simulate_label names it)
    std::size_t pos = 0;
    const Json j = Json::from_cbor(get_bytes(bytes, pos));
    unpack_files(get_bytes(bytes, pos), dir.string());
    out.push_back(SimulatedLabel{j["name"].get<std::string>(), j["recipe_label"].get<int>(), j["best"].get<int>(),
                                 j["figures"]});
  };
  const DistributeStats st = distribute(which.size(), work, take, true, "dataset: labels by simulation");
  log_distribution("dataset: labels by simulation", st);
  return out;
}

/// The agreement of the simulated best with the recipe's labels, per label: JSON and a Markdown table.
std::pair<Json, std::string> agreement(const std::vector<SimulatedLabel>& labels, const datasets::Recipe& recipe) {
  std::vector<datasets::LabelledBest> parts;
  for (const auto& l : labels) parts.push_back({l.recipe_label, l.best});
  Json j = Json::array();
  std::ostringstream md;
  md << "| label (recipe) | parts | simulated best = label | simulated best (parts) |\n|---|---:|---:|---|\n";
  int total = 0, total_agree = 0;
  for (const datasets::LabelAgreement& a : datasets::label_agreement(parts)) {
    std::string dist;
    Json bj = Json::object();
    for (const auto& [b, n] : a.simulated_best) {
      dist += (dist.empty() ? "" : ", ") + std::to_string(b) + ": " + std::to_string(n);
      bj[std::to_string(b)] = n;
    }
    j.push_back(Json{{"label", a.label}, {"parts", a.parts}, {"agree", a.agree}, {"simulated_best", bj}});
    md << "| " << a.label << " " << strategy_name({recipe.strategies.begin(), recipe.strategies.end()}, a.label)
       << " | " << a.parts << " | " << a.agree << " | " << dist << " |\n";
    total += a.parts;
    total_agree += a.agree;
  }
  md << "| all | " << total << " | " << total_agree << " | |\n";
  return {j, md.str()};
}

}  // namespace

bool build_dataset(datasets::Recipe recipe, const fs::path& out_dir, bool reuse, const Json& config,
                   bool with_agreement) {
  if (reuse && !with_agreement && datasets_io::table_up_to_date(out_dir, recipe)) {
    info("dataset: " + (out_dir / "vectors.csv").string() + " is up to date (same recipe and part files)");
    return false;
  }
  std::vector<std::size_t> which;
  for (std::size_t k = 0; k < recipe.parts.size(); ++k)
    if (recipe.parts[k].label_by_simulation || with_agreement) which.push_back(k);
  std::string labelling;
  if (!which.empty()) {
    const FinishSettings fs_ = simulated_finish_settings(config);
    const std::vector<SimulatedLabel> labels = simulate_labels(recipe, which, fs_, out_dir / "labelling");
    if (!cluster_root()) return false;  // rank 0 writes the table; the others only simulated
    Json parts = Json::array();
    for (std::size_t i = 0; i < which.size(); ++i) {
      datasets::PartSpec& p = recipe.parts[which[i]];
      if (p.label_by_simulation) p.label = labels[i].best;
      parts.push_back(Json{{"name", labels[i].name},
                           {"label_by_simulation", p.label_by_simulation},
                           {"recipe_label", labels[i].recipe_label},
                           {"simulated_best", labels[i].best},
                           {"strategies", labels[i].figures}});
    }
    Json lj{{"aim", simulate::to_string(fs_.aim.aim)}, {"parts", parts}};
    if (with_agreement) {
      auto [aj, md] = agreement(labels, recipe);
      lj["agreement"] = aj;
      write_file_atomic(out_dir / "agreement.md",
                        "# How often the simulated best strategy agrees with the recipe's label\n\nAim: " +
                            std::string(simulate::to_string(fs_.aim.aim)) + "; five strategies planned and "
                            "simulated per part (millnet finish --strategy all --simulate; figures per part in "
                            "manifest.json under labelling, files in labelling/).\n\n" + md);
      info("dataset: agreement of the simulated best with the labels → " + (out_dir / "agreement.md").string() + "\n" +
           md);
    }
    labelling = lj.dump();
  }
  if (!cluster_root()) return false;
  Progress progress("dataset", 0);
  datasets::Table table = datasets::build_table(recipe, progress.callback());
  progress.finish();
  table.labelling_json = labelling;
  {
    OutputSet table_files;  // vectors.csv and manifest.json together or neither (core/output_set.hpp)
    datasets_io::write_table(table, out_dir);
    table_files.commit();
  }
  info("dataset: " + std::to_string(table.rows.size()) + " vectors from " + std::to_string(recipe.parts.size()) +
       " parts → " + (out_dir / "vectors.csv").string());
  return true;
}

TrainSummary train_model(const fs::path& dataset_csv, const Json& config, const fs::path& out_dir) {
  const datasets::Table table = datasets::read_table(dataset_csv);
  classifier::TrainingSet set;
  set.inputs = table.inputs_matrix();
  set.outputs = table.outputs_matrix();
  set.groups = table.row_sources();
  // Strategy names live in the manifest beside the CSV; the config's names otherwise.
  std::vector<std::string> names = config["dataset"]["strategies"].get<std::vector<std::string>>();
  const fs::path manifest_path = dataset_csv.parent_path() / "manifest.json";
  const datasets_io::Manifest manifest =
      fs::exists(manifest_path) ? datasets_io::read_manifest(manifest_path) : datasets_io::Manifest{};
  if (!manifest.strategies.empty()) names = manifest.strategies;
  set.strategies = names;

  classifier::TrainParams tp = train_params(config);
  Progress progress("train (leave-one-out)", 0);
  tp.search.progress = progress.callback();
  classifier::Model model = classifier::train(set, tp);
  progress.finish();
  const classifier::LooReport& loo = model.loo;

  // The model describes its own inputs (model.json "features"): the table's raster and grid; the
  // classifier learns from the n² heights only (Table::inputs_matrix), never from an aspect column.
  const double raster_mm = manifest.raster_mm ? *manifest.raster_mm : config["dataset"]["raster_mm"].get<double>();
  model.input_spec = classifier::InputSpec{raster_mm, table.grid_n, false};
  classifier_io::save_model(model, out_dir / "model.json");
  // sampling.json: the same spec for readers of model folders from before "features".
  const Json sampling = {{"grid", table.grid_n},
                         {"raster_mm", manifest.raster_mm ? number_json(raster_mm) : Json(raster_mm)},
                         {"inputs", table.inputs_per_row()},
                         {"dataset", fs::absolute(dataset_csv).string()}};
  write_file_atomic(out_dir / "sampling.json", sampling.dump(2) + "\n");

  // LOO curve: alpha,rms (the chosen mode's) + both modes' figures.
  std::ostringstream curve;
  curve << "alpha,rms,rms_part,rms_vector,accuracy_part,accuracy_vector\n";
  std::vector<double> xs, part_rms, vec_rms;
  const bool part_mode = loo.mode == classifier::LooMode::PartOut;
  for (const auto& c : loo.curve) {
    curve << format_double(c.alpha) << "," << format_double(part_mode ? c.rms_part : c.rms_vector) << ","
          << format_double(c.rms_part) << "," << format_double(c.rms_vector) << "," << format_double(c.accuracy_part)
          << "," << format_double(c.accuracy_vector) << "\n";
    xs.push_back(c.alpha);
    part_rms.push_back(c.rms_part);
    vec_rms.push_back(c.rms_vector);
  }
  write_file_atomic(out_dir / "loo_curve.csv", curve.str());
  if (xs.empty()) {  // /train/fixed_alpha: no scan, the one point at the given α (the chart failed on "no points")
    xs = {model.alpha};
    part_rms = {loo.rms_part_at_alpha};
    vec_rms = {loo.rms_vector_at_alpha};
  }
  report::LinePlotOptions lo;
  lo.log_x = true;
  lo.show_points = true;
  lo.marker = report::Marker{model.alpha, "chosen alpha = " + fixed(model.alpha, 3) + " (" +
                                              classifier::to_string(loo.mode) + " LOO)"};
  (void)report::line_plot_png(out_dir / "loo_curve.png",
                              {{"leave-one-part-out", xs, part_rms}, {"leave-one-vector-out (paper)", xs, vec_rms}},
                              "Leave-one-out RMS error against the penalty coefficient alpha", "alpha (log scale)",
                              "RMS error of the outputs", lo);

  // Filtration (self included) and verification (chosen mode's exclusion), the paper's Fig. 6.
  std::ostringstream ver;
  ver << "id,source";
  const auto K = loo.filtration.cols();
  for (Eigen::Index k = 1; k <= K; ++k) ver << ",filtration_" << k;
  for (Eigen::Index k = 1; k <= K; ++k) ver << ",verification_" << k;
  ver << "\n";
  std::vector<double> fil_true, ver_true;
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    ver << table.rows[i].id << "," << table.rows[i].source;
    for (Eigen::Index k = 0; k < K; ++k) ver << "," << format_double(loo.filtration(r, k));
    for (Eigen::Index k = 0; k < K; ++k) ver << "," << format_double(loo.verification(r, k));
    ver << "\n";
    const int label = table.rows[i].label;
    if (label >= 1) {
      fil_true.push_back(loo.filtration(r, label - 1));
      ver_true.push_back(loo.verification(r, label - 1));
    }
  }
  write_file_atomic(out_dir / "verification.csv", ver.str());
  if (!fil_true.empty())
    (void)report::multi_line_png(out_dir / "verification.png",
                                 {{"filtration (self included)", fil_true},
                                  {std::string("verification (") + (part_mode ? "part" : "vector") + " left out)", ver_true}},
                                 "Output of the true strategy for every stored vector (paper Fig. 6)",
                                 "stored vector", "output of the labelled strategy");

  TrainSummary s;
  s.alpha = model.alpha;
  s.mode = classifier::to_string(loo.mode);
  s.edge = classifier::to_string(part_mode ? loo.part.edge : loo.vector.edge);
  s.rms_part = loo.rms_part_at_alpha;
  s.rms_vector = loo.rms_vector_at_alpha;
  s.accuracy_part = loo.accuracy_part_at_alpha;
  s.accuracy_vector = loo.accuracy_vector_at_alpha;
  s.vectors = table.rows.size();
  std::vector<std::string> g = set.groups;
  std::sort(g.begin(), g.end());
  s.parts = static_cast<std::size_t>(std::unique(g.begin(), g.end()) - g.begin());
  Json rep = {{"alpha", s.alpha},
              {"loo_mode", s.mode},
              {"alpha_at_scan_edge", s.edge},
              {"rms_part_at_alpha", s.rms_part},
              {"rms_vector_at_alpha", s.rms_vector},
              {"accuracy_part_at_alpha", s.accuracy_part},
              {"accuracy_vector_at_alpha", s.accuracy_vector},
              {"alpha_part_optimum", loo.part.alpha},
              {"alpha_vector_optimum", loo.vector.alpha},
              {"rms_part_optimum", loo.part.rms},
              {"rms_vector_optimum", loo.vector.rms},
              {"vectors", s.vectors},
              {"parts", s.parts},
              {"unfamiliar_threshold_d2", model.unfamiliar_threshold}};
  write_file_atomic(out_dir / "train_report.json", rep.dump(2) + "\n");
  if (s.edge != "none")
    warn("train: the optimum α lies at the " + s.edge + " edge of the scan; widen /train/range_low or /train/range_high");
  info("train: α = " + fixed(s.alpha, 4) + " (" + s.mode + " LOO); verification accuracy " +
       fixed(100 * s.accuracy_part, 1) + " % leaving out parts, " + fixed(100 * s.accuracy_vector, 1) +
       " % leaving out single vectors → " + (out_dir / "model.json").string());
  return s;
}

ModelFolder load_model_folder(const fs::path& dir, const Json& config) {
  ModelFolder m;
  m.dir = dir;
  m.model = classifier_io::load_model(dir / "model.json");
  if (const auto& s = m.model.input_spec) {
    if (s->aspect_feature)
      throw file_error((dir / "model.json").string(),
                       "features.aspect_feature: true, but predict computes the grid heights only");
    m.spec.grid = s->grid;
    m.spec.raster_mm = s->raster_mm;
  } else {  // a model folder from before model.json carried its features
    const fs::path path = dir / "sampling.json";
    const Json sampling = read_json(path);
    if (!sampling.is_object() || !sampling.contains("grid") || !sampling["grid"].is_number_integer())
      throw file_error(path.string(), "grid: expected an integer (model.json has no \"features\" either)");
    if (!sampling.contains("raster_mm") || !sampling["raster_mm"].is_number())
      throw file_error(path.string(), "raster_mm: expected a number (model.json has no \"features\" either)");
    m.spec.grid = sampling["grid"].get<int>();
    m.spec.raster_mm = sampling["raster_mm"].get<double>();
  }
  m.spec.augment = predict_augment(config);
  return m;
}

namespace {

/// One part predicted, on whichever rank computed it: its predictions.json entry and its figures,
/// as CBOR (doubles bit-exact, so rank 0 writes the bytes of a one-process run).
std::string predict_one(const ModelFolder& folder, const PredictInput& in, const ingest::PrepareOptions& prep) {
  const classifier::Model& model = folder.model;
  PartPrediction pp;
  pp.file = in.file.string();
  pp.name = in.name.empty() ? in.file.stem().string() : in.name;
  pp.expected = in.expected;
  Json jp = {{"part", pp.name}, {"file", pp.file}};
  try {
    std::shared_ptr<const ingest::Mesh> mesh = in.mesh;
    if (!mesh) mesh = std::make_shared<const ingest::Mesh>(load_part(in.file, prep));
    if (const Json cad = cad_metrics(in.file); !cad.is_null()) jp["cad"] = cad;
    const datasets::ModelVectors mv = datasets::model_vectors(*mesh, pp.name, folder.spec, work_limits());
    const classifier::Prediction pr = classifier::predict(model, mv.inputs);
    const classifier::Ranking rk = classifier::rank(pr);
    pp.mean = rk.mean;
    pp.totals = rk.totals;
    pp.first_share = rk.first_share;
    pp.top = rk.top;
    pp.confidence = rk.confidence;
    pp.consistency = rk.consistency;
    pp.d2_min = rk.d2_min;
    pp.unfamiliar = rk.unfamiliar;
    pp.ok = true;
    const std::size_t unfamiliar = rk.unfamiliar_variants;
    const auto& variants = mv.variants;
    Json jv = Json::array();
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const auto row = pr.probabilities.row(static_cast<Eigen::Index>(v));
      jv.push_back({{"axis", std::string(1, augment::to_char(variants[v].axis))},
                    {"angle", variants[v].angle_deg},
                    {"flip", variants[v].flip},
                    {"top", rk.variant_top[v]},
                    {"d2_min", pr.d2_min(static_cast<Eigen::Index>(v))},
                    {"unfamiliar", static_cast<bool>(pr.unfamiliar[v])},
                    {"probabilities", std::vector<double>(row.begin(), row.end())}});
    }
    Json ranking = Json::array();
    for (std::size_t k : rk.order)
      ranking.push_back({{"slot", k + 1}, {"strategy", model.strategies[k]}, {"probability", pp.mean[k]},
                         {"total", pp.totals[k]}, {"share_first", pp.first_share[k]}});
    jp["status"] = "ok";
    jp["top"] = pp.top;
    jp["top_name"] = strategy_name(model.strategies, pp.top);
    jp["confidence"] = pp.confidence;
    jp["consistency"] = pp.consistency;
    jp["unfamiliar"] = pp.unfamiliar;
    jp["unfamiliar_variants"] = unfamiliar;
    jp["d2_min"] = pp.d2_min;
    if (pp.expected) jp["expected"] = pp.expected;
    jp["ranking"] = ranking;
    jp["variants"] = jv;
  } catch (const std::exception& e) {
    pp.ok = false;
    pp.error = e.what();
    jp["status"] = "error";
    jp["error"] = pp.error;
  }
  const Json unit = {{"jp", jp},
                     {"pp",
                      {{"name", pp.name}, {"file", pp.file}, {"ok", pp.ok}, {"error", pp.error}, {"top", pp.top},
                       {"confidence", pp.confidence}, {"consistency", pp.consistency}, {"unfamiliar", pp.unfamiliar},
                       {"d2_min", pp.d2_min}, {"expected", pp.expected}, {"mean", pp.mean}, {"totals", pp.totals},
                       {"first_share", pp.first_share}}}};
  const std::vector<std::uint8_t> cbor = Json::to_cbor(unit);
  return std::string(cbor.begin(), cbor.end());
}

}  // namespace

std::vector<PartPrediction> predict_parts(const ModelFolder& folder, const std::vector<PredictInput>& parts,
                                          const ingest::PrepareOptions& prep, const fs::path& out_dir) {
  const classifier::Model& model = folder.model;
  const auto K = static_cast<std::size_t>(model.outputs.cols());

  std::vector<PartPrediction> results;
  Json jparts = Json::array();
  std::ostringstream csv;
  csv << "part,file,status,top,top_name,confidence,consistency,unfamiliar,d2_min,expected";
  for (std::size_t k = 1; k <= K; ++k) csv << ",p_" << k;
  csv << ",error\n";
  // Work unit = part (any rank); rank 0 takes them in part order: pictures, warnings, the tables.
  const auto emit = [&](std::size_t, bool ok, std::string&& bytes) {
    if (!ok) throw Error("predict: " + bytes);  // predict_one reports a part's failure in its entry
    Json unit = Json::from_cbor(bytes);
    Json& jp = unit["jp"];
    const Json& u = unit["pp"];
    PartPrediction pp;
    pp.name = u["name"].get<std::string>();
    pp.file = u["file"].get<std::string>();
    pp.ok = u["ok"].get<bool>();
    pp.error = u["error"].get<std::string>();
    pp.top = u["top"].get<int>();
    pp.confidence = u["confidence"].get<double>();
    pp.consistency = u["consistency"].get<double>();
    pp.unfamiliar = u["unfamiliar"].get<bool>();
    pp.d2_min = u["d2_min"].get<double>();
    pp.expected = u["expected"].get<int>();
    pp.mean = u["mean"].get<std::vector<double>>();
    pp.totals = u["totals"].get<std::vector<double>>();
    pp.first_share = u["first_share"].get<std::vector<double>>();
    pp.strategies = model.strategies;
    if (pp.ok) {
      try {
        pp.png = out_dir / (pp.name + ".png");
        (void)report::grouped_bar_png(pp.png, model.strategies,
                                      {{"mean probability over " + std::to_string(jp["variants"].size()) + " variants", pp.mean},
                                       {"share of variants ranking it first", pp.first_share}},
                                      pp.name + ": predicted finishing strategy " + std::to_string(pp.top) +
                                          " (consistency " + fixed(100 * pp.consistency, 0) + " %)" +
                                          (pp.unfamiliar ? " - UNFAMILIAR part" : ""),
                                      "probability / share", {.show_values = true, .value_decimals = 2, .y_range = std::pair{0.0, 1.0}});
        if (pp.unfamiliar)
          warn("predict: " + pp.file + ": far from every stored model (d² = " + fixed(pp.d2_min, 1) +
               " > threshold " + fixed(model.unfamiliar_threshold, 1) + "): the prediction is an extrapolation");
      } catch (const std::exception& e) {
        pp.ok = false;
        pp.error = e.what();
        jp["status"] = "error";
        jp["error"] = pp.error;
      }
    }
    if (!pp.ok) warn("predict: " + pp.error);
    csv << pp.name << "," << pp.file << "," << (pp.ok ? "ok" : "error") << "," << pp.top << ","
        << (pp.ok ? "\"" + strategy_name(model.strategies, pp.top) + "\"" : "") << "," << format_double(pp.confidence)
        << "," << format_double(pp.consistency) << "," << (pp.unfamiliar ? 1 : 0) << "," << format_double(pp.d2_min)
        << "," << pp.expected;
    for (std::size_t k = 0; k < K; ++k) csv << "," << (pp.ok ? format_double(pp.mean[k]) : "");
    std::string err = pp.error;
    std::replace(err.begin(), err.end(), '"', '\'');
    csv << "," << (err.empty() ? "" : "\"" + err + "\"") << "\n";
    jparts.push_back(std::move(jp));
    results.push_back(std::move(pp));
  };
  const DistributeStats st = distribute(
      parts.size(), [&](std::size_t i) { return predict_one(folder, parts[i], prep); }, emit, false, "predict");
  if (!cluster_root()) return results;
  log_distribution("predict", st);
  Json out = {{"model", fs::absolute(folder.dir / "model.json").string()},
              {"alpha", model.alpha},
              {"strategies", model.strategies},
              {"unfamiliar_threshold_d2", model.unfamiliar_threshold},
              {"parts", jparts}};
  write_file_atomic(out_dir / "predictions.json", out.dump(2) + "\n");
  write_file_atomic(out_dir / "predictions.csv", csv.str());
  return results;
}

}  // namespace millnet::app
