#include "learn.hpp"

#include "cli.hpp"
#include "finish_job.hpp"
#include "labelling.hpp"
#include "mpi_cluster.hpp"
#include "text.hpp"
#include "report_util.hpp"
#include "train_curves.hpp"

#include "millnet/augment/variants.hpp"
#include "millnet/classifier/rank.hpp"
#include "millnet/classifier/regret.hpp"
#include "millnet/classifier/tolerances.hpp"
#include "millnet/classifier/io/model_file.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/datasets/agreement.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/datasets/io/labels.hpp"
#include "millnet/datasets/io/manifest.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/report/plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

/// A number as the manifest's writer (format_double) spells it once parsed: integral values as
/// JSON integers ("1", not "1.0"), so that sampling.json keeps its bytes.
Json number_json(double v) {
  if (std::isfinite(v) && std::abs(v) < 9007199254740992.0 && v == std::trunc(v))
    return Json(static_cast<std::int64_t>(v));
  return Json(v);
}

}  // namespace

namespace {

/// The table's rows over the ranks (issue 10): the work unit is one (part, variant) pair, handed
/// out dynamically in table order; a rank keeps the last part it loaded (memory: one part per
/// rank), and the raster sampling inside a unit uses the rank's OpenMP threads. A unit's result is
/// its row (and, for a part's first variant, the part's manifest record), binary; rank 0 writes
/// each row as soon as the rows before it are in. A unit that fails stops the build with its
/// message (the part and the variant, as one process says it).
void build_rows_distributed(const datasets::Recipe& recipe, const datasets::TablePlan& plan,
                            datasets_io::TableWriter* writer, std::vector<datasets::SourceFile>& sources) {
  std::vector<std::pair<std::size_t, std::size_t>> units;  // (part, variant) in table order
  units.reserve(plan.rows);
  for (std::size_t k = 0; k < plan.variants.size(); ++k)
    for (std::size_t v = 0; v < plan.variants[k].size(); ++v) units.emplace_back(k, v);
  std::optional<std::size_t> held;  // the part this rank holds
  datasets::LoadedPart part;
  const auto put_u64 = [](std::string& out, std::uint64_t x) { out.append(reinterpret_cast<const char*>(&x), 8); };
  const auto work = [&](std::size_t i) {
    const auto [k, v] = units[i];
    if (held != k) {
      held.reset();
      part = datasets::load_table_part(recipe, k);
      held = k;
    }
    const datasets::Row r = datasets::variant_row(recipe, plan, k, part.mesh, v, part.wall_share);
    // The row: its inputs, aspect and wall share as raw doubles (bit for bit); the rest rank 0 knows
    // from the unit.
    std::string msg(reinterpret_cast<const char*>(r.inputs.data()), r.inputs.size() * sizeof(double));
    msg.append(reinterpret_cast<const char*>(&r.aspect), sizeof(double));
    msg.append(reinterpret_cast<const char*>(&r.wall_share), sizeof(double));
    if (v == 0) {
      const datasets::SourceFile& s = part.source;
      put_u64(msg, s.fnv1a64);
      put_u64(msg, static_cast<std::uint64_t>(s.bytes));
      put_u64(msg, s.triangles);
      put_u64(msg, s.degenerate_triangles);
    }
    return msg;
  };
  const std::size_t m = plan.header.inputs_per_row();
  const auto take = [&](std::size_t i, bool ok, std::string&& bytes) {
    if (!ok) throw Error(bytes);  // names the part (and the variant)
    const auto [k, v] = units[i];
    const datasets::PartSpec& p = recipe.parts[k];
    const augment::Variant& var = plan.variants[k][v];
    const std::size_t need = (m + 2) * sizeof(double) + (v == 0 ? 32 : 0);
    if (bytes.size() != need)
      throw Error("mpi: a table row of " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(need));
    datasets::Row r;
    r.source = p.name.empty() ? p.file.stem().string() : p.name;
    r.id = r.source + "#" + std::to_string(v + 1);
    r.label = p.label;
    r.axis = var.axis;
    r.angle_deg = var.angle_deg;
    r.flip = var.flip;
    r.inputs.resize(m);
    std::memcpy(r.inputs.data(), bytes.data(), m * sizeof(double));
    std::memcpy(&r.aspect, bytes.data() + m * sizeof(double), sizeof(double));
    std::memcpy(&r.wall_share, bytes.data() + (m + 1) * sizeof(double), sizeof(double));
    r.outputs = p.outputs ? *p.outputs : datasets::one_hot(p.label);
    if (v == 0) {
      std::uint64_t f[4];
      std::memcpy(f, bytes.data() + (m + 2) * sizeof(double), 32);
      datasets::SourceFile s;
      s.name = r.source;
      s.file = p.file.generic_string();
      s.label = p.label;
      s.fnv1a64 = f[0];
      s.bytes = static_cast<std::uintmax_t>(f[1]);
      s.triangles = static_cast<std::size_t>(f[2]);
      s.degenerate_triangles = static_cast<std::size_t>(f[3]);
      sources.push_back(std::move(s));
    }
    writer->add(r);
  };
  const DistributeStats st = distribute(units.size(), work, take, true, "dataset");
  log_distribution("dataset: model vectors", st);
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
  std::optional<datasets_io::LabelFile> labels_out;  // out_dir/labels.json, with the table
  if (!which.empty()) {
    const FinishSettings fs_ = simulated_finish_settings(config);
    const std::vector<SimulatedLabel> labels = labels_of(recipe, which, fs_);
    if (!cluster_root()) {
      // Rank 0 holds the simulated labels and writes the labelling; the other ranks go on to sample
      // the table's heights, which do not depend on a label (rank 0 puts each row's label in).
      for (const std::size_t k : which)
        if (recipe.parts[k].label_by_simulation) recipe.parts[k].label = 1;
    } else {
      Json parts = Json::array();
      datasets_io::LabelFile out_labels{simulate::to_string(fs_.aim.aim), recipe.simulation_settings_json, {}};
      for (std::size_t i = 0; i < which.size(); ++i) {
        datasets::PartSpec& p = recipe.parts[which[i]];
        const datasets_io::PartLabel& l = labels[i].label;
        if (p.label_by_simulation) {
          p.label = l.best;
          p.outputs = l.outputs();
        }
        out_labels.parts.push_back(l);
        parts.push_back(Json{{"name", l.name},
                             {"label_by_simulation", p.label_by_simulation},
                             {"recipe_label", labels[i].recipe_label},
                             {"simulated_best", l.best},
                             {"strategies", figures_json(l)}});
      }
      if (!out_labels.settings_json.empty()) labels_out = std::move(out_labels);
      Json lj{{"aim", simulate::to_string(fs_.aim.aim)}, {"parts", parts}};
      if (with_agreement) {
        auto [aj, md] = agreement(labels, recipe);
        lj["agreement"] = aj;
        write_file_atomic(out_dir / "agreement.md",
                          "# How often the simulated best strategy agrees with the recipe's label\n\nAim: " +
                              std::string(simulate::to_string(fs_.aim.aim)) +
                              "; five strategies planned and "
                              "simulated per part (millnet finish --strategy all --simulate; figures per part in "
                              "manifest.json under labelling).\n\n" +
                              md);
        info("dataset: agreement of the simulated best with the labels → " + (out_dir / "agreement.md").string() +
             "\n" + md);
      }
      labelling = lj.dump();
    }
  }
  // The table: rows streamed to vectors.csv in table order, never all held (issue 10).
  const datasets::TablePlan plan = datasets::plan_table(recipe);
  std::optional<datasets_io::TableWriter> writer;
  std::optional<OutputSet> table_files;  // vectors.csv and manifest.json together or neither (core/output_set.hpp)
  if (cluster_root()) {
    table_files.emplace();
    writer.emplace(out_dir, plan.header.grid_n, plan.header.has_aspect, plan.header.strategies,
                   plan.header.has_wall_share);
    if (labels_out) datasets_io::write_labels(out_dir / "labels.json", *labels_out);
  }
  std::vector<datasets::SourceFile> sources;
  if (cluster_size() == 1) {
    Progress progress("dataset", 0);
    datasets::build_rows(
        recipe, plan, [&](datasets::Row&& r) { writer->add(r); }, sources, progress.callback());
    progress.finish();
  } else {
    build_rows_distributed(recipe, plan, writer ? &*writer : nullptr, sources);
    if (!cluster_root()) return false;  // rank 0 writes the table
  }
  writer->finish(sources, plan.header.config_json, labelling);
  table_files->commit();
  info("dataset: " + std::to_string(writer->rows()) + " vectors from " + std::to_string(recipe.parts.size()) +
       " parts → " + (out_dir / "vectors.csv").string());
  return true;
}

namespace {

/// How many copies of the wall share the network takes (/train/wall_share_copies when the table has
/// the column, else none).
int wall_share_copies(const datasets::Table& table, const Json& config) {
  return table.has_wall_share ? config["train"]["wall_share_copies"].get<int>() : 0;
}

/// The training set of a table — the network's inputs are the heights, then the wall share's copies
/// (classifier::InputSpec); strategy names from the manifest beside the CSV, else the config's.
classifier::TrainingSet training_set(const datasets::Table& table, const datasets_io::Manifest& manifest,
                                     const Json& config) {
  classifier::TrainingSet set;
  set.inputs = table.inputs_matrix(wall_share_copies(table, config));
  set.outputs = table.outputs_matrix();
  set.groups = table.row_sources();
  set.strategies = manifest.strategies.empty() ? config["dataset"]["strategies"].get<std::vector<std::string>>()
                                               : manifest.strategies;
  return set;
}

/// The figures of a trained model (train_report.json's, and the summary's).
TrainSummary train_summary(const classifier::Model& model, const datasets::Table& table,
                           const classifier::TrainingSet& set) {
  const classifier::LooReport& loo = model.loo;
  TrainSummary s;
  s.alpha = model.alpha;
  s.mode = classifier::to_string(loo.mode);
  s.edge = classifier::to_string(loo.mode == classifier::LooMode::PartOut ? loo.part.edge : loo.vector.edge);
  s.rms_part = loo.rms_part_at_alpha;
  s.rms_vector = loo.rms_vector_at_alpha;
  s.accuracy_part = loo.accuracy_part_at_alpha;
  s.accuracy_vector = loo.accuracy_vector_at_alpha;
  s.vectors = table.rows.size();
  std::vector<std::string> g = set.groups;
  std::sort(g.begin(), g.end());
  s.parts = static_cast<std::size_t>(std::unique(g.begin(), g.end()) - g.begin());
  return s;
}

/// Whether every output row is one-hot (or all zero): labels given by hand or by family.
bool one_hot_outputs(const Eigen::MatrixXd& Y) {
  for (Eigen::Index i = 0; i < Y.rows(); ++i)  // O(N·K)
    for (Eigen::Index k = 0; k < Y.cols(); ++k)
      if (Y(i, k) != 0 && Y(i, k) != 1) return false;
  return true;
}

/// What the table's simulated outputs were computed for: the aim and the surface specification of
/// the labels' settings (the manifest's config.label_by_simulation), as JSON text; "" if unknown.
std::string training_target(const datasets_io::Manifest& manifest) {
  if (manifest.config_json.empty()) return "";
  const Json c = Json::parse(manifest.config_json);
  if (!c.contains("label_by_simulation") || !c["label_by_simulation"].contains("finish")) return "";
  const Json& f = c["label_by_simulation"]["finish"];
  return Json{{"aim", f.value("aim", "")}, {"spec", f.value("spec", Json::object())}}.dump();
}

/// The regret block of train_report.json: the parts' leave-one-part-out picks at α, their figures,
/// the always-one-strategy baseline, the calibration's reliability table (issue 39 §1, §3). Fills
/// the summary's figures. O(N·K + P² log P).
Json regret_report(const classifier::Model& model, const classifier::TrainingSet& set, TrainSummary& s) {
  s.criterion = classifier::to_string(model.criterion);
  if (!classifier::one_output_per_part(set.outputs, set.groups))
    return Json{{"criterion", s.criterion}, {"note", "a part's vectors carry different outputs: no part picks"}};
  const std::vector<classifier::PartPick> picks =
      classifier::part_picks(model.loo.verification, set.outputs, set.groups, model.loo.nearest_d2);
  s.regret = classifier::summarize(picks);
  s.baseline = classifier::always_the_same(picks);
  const auto figures = [](const classifier::RegretSummary& r) {
    return Json{{"parts", r.parts},
                {"top1", r.top1},
                {"mean_regret", r.mean},
                {"median_regret", r.median},
                {"p90_regret", r.p90},
                {"misses", r.misses},
                {"spearman_mean", std::isfinite(r.spearman) ? Json(r.spearman) : Json(nullptr)}};
  };
  const auto K = static_cast<std::size_t>(set.outputs.cols());
  Json rel = Json::array();
  for (const classifier::ReliabilityBin& b : classifier::reliability(picks, K, model.unfamiliar_threshold))
    rel.push_back(Json{{"confidence_from", b.low},
                       {"confidence_to", b.high},
                       {"parts", b.parts},
                       {"mean_confidence", b.mean_confidence},
                       {"share_right", b.share_right}});
  Json parts = Json::array();
  for (const classifier::PartPick& p : picks)
    parts.push_back(Json{{"part", p.part},
                         {"best", p.best + 1},
                         {"pick", p.pick + 1},
                         {"regret", p.regret},
                         {"confidence", model.calibration.confidence(p.pick, p.margin, p.d2_min)}});
  Json baseline = figures(s.baseline.figures);
  baseline["strategy"] = s.baseline.slot + 1;
  return Json{{"criterion", s.criterion},
              {"outputs", s.scores ? "scores" : "one-hot"},
              {"miss_regret", classifier::tol::kMissRegret},
              {"leave_one_part_out", figures(s.regret)},
              {"always_the_same_strategy", baseline},
              {"reliability", rel},
              {"parts", parts}};
}

void write_train_report(const TrainSummary& s, const classifier::Model& model, const Json& regret,
                        const fs::path& out_dir) {
  const classifier::LooReport& loo = model.loo;
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
              {"unfamiliar_threshold_d2", model.unfamiliar_threshold},
              {"regret", regret}};
  write_file_atomic(out_dir / "train_report.json", rep.dump(2) + "\n");
}

}  // namespace

TrainSummary train_model(const fs::path& dataset_csv, const Json& config, const fs::path& out_dir) {
  const datasets::Table table = datasets::read_table(dataset_csv);
  const fs::path manifest_path = dataset_csv.parent_path() / "manifest.json";
  const datasets_io::Manifest manifest =
      fs::exists(manifest_path) ? datasets_io::read_manifest(manifest_path) : datasets_io::Manifest{};
  const classifier::TrainingSet set = training_set(table, manifest, config);

  classifier::TrainParams tp = train_params(config);
  const bool scores = !one_hot_outputs(set.outputs);
  if (config["train"]["criterion"].get<std::string>() == "auto")
    tp.criterion = scores ? classifier::Criterion::Regret : classifier::Criterion::Rms;
  Progress progress("train (leave-one-out)", 0);
  tp.search.progress = progress.callback();
  classifier::Model model = classifier::train(set, tp);
  progress.finish();

  // The model describes its own inputs (model.json "features"): the table's raster and grid, and the
  // wall share's copies after the n² heights (never an aspect column).
  const double raster_mm = manifest.raster_mm ? *manifest.raster_mm : config["dataset"]["raster_mm"].get<double>();
  model.input_spec = classifier::InputSpec{raster_mm, table.grid_n, false, wall_share_copies(table, config)};
  if (scores) model.target_json = training_target(manifest);
  classifier_io::save_model(model, out_dir / "model.json");
  // sampling.json: the same spec for readers of model folders from before "features".
  const Json sampling = {{"grid", table.grid_n},
                         {"raster_mm", manifest.raster_mm ? number_json(raster_mm) : Json(raster_mm)},
                         {"inputs", table.inputs_per_row()},
                         {"dataset", fs::absolute(dataset_csv).string()}};
  write_file_atomic(out_dir / "sampling.json", sampling.dump(2) + "\n");

  write_loo_curve(model, out_dir);
  write_verification(table, model.loo, out_dir);
  TrainSummary s = train_summary(model, table, set);
  s.scores = scores;
  const Json regret = regret_report(model, set, s);
  write_train_report(s, model, regret, out_dir);
  if (s.edge != "none")
    warn("train: the optimum α lies at the " + s.edge +
         " edge of the scan; widen /train/range_low or /train/range_high");
  info("train: α = " + fixed(s.alpha, 4) + " (" + s.mode + " LOO); verification accuracy " +
       fixed(100 * s.accuracy_part, 1) + " % leaving out parts, " + fixed(100 * s.accuracy_vector, 1) +
       " % leaving out single vectors → " + (out_dir / "model.json").string());
  if (scores)
    info("train: α chosen for " + s.criterion + "; leaving out parts, the pick is the simulated best on " +
         fixed(100 * s.regret.top1, 1) + " % of " + std::to_string(s.regret.parts) + " parts, regret mean " +
         fixed(100 * s.regret.mean, 1) + " %, median " + fixed(100 * s.regret.median, 1) + " %, p90 " +
         fixed(100 * s.regret.p90, 1) + " % (always strategy " + std::to_string(s.baseline.slot + 1) + ": mean " +
         fixed(100 * s.baseline.figures.mean, 1) + " %)");
  return s;
}

namespace {

/// One model per aim (issue 39 §1): a model trained on simulated scores predicts them for the aim
/// and surface specification it was trained for; a config asking for another is refused.
void check_model_target(const ModelFolder& m, const Json& config) {
  if (m.model.target_json.empty()) return;
  const Json target = Json::parse(m.model.target_json);
  const Json asked{{"aim", config["finish"]["aim"]}, {"spec", config["finish"]["spec"]}};
  if (target == asked) return;
  throw file_error((m.dir / "model.json").string(),
                   "trained for aim " + target.value("aim", std::string("?")) + ", spec " + target["spec"].dump() +
                       "; the config asks for aim " + asked["aim"].get<std::string>() + ", spec " +
                       asked["spec"].dump() + " (/finish/aim, /finish/spec): train a model for it (millnet train)");
}

}  // namespace

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
    m.spec.wall_share_copies = s->wall_share_copies;
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
  check_model_target(m, config);
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
    std::shared_ptr<const job::Part> part = in.part;
    if (!part) part = std::make_shared<const job::Part>(load_part(in.file, prep));
    if (const Json cad = cad_metrics(*part); !cad.is_null()) jp["cad"] = cad;
    const datasets::ModelVectors mv = datasets::model_vectors(part->mesh, pp.name, folder.spec, work_limits());
    const classifier::Prediction pr = classifier::predict(model, mv.inputs);
    const classifier::Ranking rk = classifier::rank(pr);
    pp.mean = rk.mean;
    pp.totals = rk.totals;
    pp.first_share = rk.first_share;
    pp.top = rk.top;
    pp.confidence = rk.confidence;
    const Eigen::RowVectorXd er = classifier::expected_regret(model, mv.inputs).colwise().mean();
    pp.expected_regret.assign(er.data(), er.data() + er.size());
    pp.regret_risk = pp.expected_regret[static_cast<std::size_t>(rk.top - 1)];
    if (!model.calibration.prior.empty()) {
      double second = 0;
      for (std::size_t k = 0; k < rk.mean.size(); ++k)
        if (static_cast<int>(k) != rk.top - 1) second = std::max(second, rk.mean[k]);
      pp.confidence =
          model.calibration.confidence(rk.top - 1, rk.mean[static_cast<std::size_t>(rk.top - 1)] - second, rk.d2_min);
    }
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
    for (std::size_t k : rk.order)  // a spare slot ("spare 6".."spare 8": never machined) has no regret
      ranking.push_back({{"slot", k + 1},
                         {"strategy", model.strategies[k]},
                         {"probability", pp.mean[k]},
                         {"expected_score", pp.mean[k]},
                         {"expected_regret",
                          model.strategies[k].rfind("spare ", 0) == 0 ? Json(nullptr) : Json(pp.expected_regret[k])},
                         {"total", pp.totals[k]},
                         {"share_first", pp.first_share[k]}});
    jp["status"] = "ok";
    jp["top"] = pp.top;
    jp["top_name"] = strategy_name(model.strategies, pp.top);
    jp["confidence"] = pp.confidence;
    jp["regret_risk"] = pp.regret_risk;
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
                      {{"name", pp.name},
                       {"file", pp.file},
                       {"ok", pp.ok},
                       {"error", pp.error},
                       {"top", pp.top},
                       {"confidence", pp.confidence},
                       {"regret_risk", pp.regret_risk},
                       {"expected_regret", pp.expected_regret},
                       {"consistency", pp.consistency},
                       {"unfamiliar", pp.unfamiliar},
                       {"d2_min", pp.d2_min},
                       {"expected", pp.expected},
                       {"mean", pp.mean},
                       {"totals", pp.totals},
                       {"first_share", pp.first_share}}}};
  const std::vector<std::uint8_t> cbor = Json::to_cbor(unit);
  return std::string(cbor.begin(), cbor.end());
}

}  // namespace

std::vector<PartPrediction> predict_parts(const ModelFolder& folder, const std::vector<PredictInput>& parts,
                                          const ingest::PrepareOptions& prep, const fs::path& out_dir) {
  const classifier::Model& model = folder.model;
  const auto K = static_cast<std::size_t>(model.outputs.cols());

  std::vector<PartPrediction> results;  // per part its summary (K means); the variants go to disk
  // predictions.json and predictions.csv are streamed as the parts come in, in part order (issue 10:
  // rank 0 of a large batch holds no table): the bytes of `out.dump(2)` for the whole document, the
  // parts' array written element by element (each element's dump(2), indented two levels).
  std::optional<AtomicOFStream> json_out, csv_out;
  std::string json_tail;
  bool first_part = true;
  if (cluster_root()) {
    const Json head = {{"model", fs::absolute(folder.dir / "model.json").string()},
                       {"alpha", model.alpha},
                       {"strategies", model.strategies},
                       {"unfamiliar_threshold_d2", model.unfamiliar_threshold},
                       {"parts", "\x01"}};
    const std::string text = head.dump(2) + "\n";
    const std::string mark = "\"parts\": \"\\u0001\"";
    const std::size_t at = text.find(mark);
    if (at == std::string::npos) throw Error("predict: internal: the document's layout changed");
    json_out.emplace(out_dir / "predictions.json");
    json_out->stream() << text.substr(0, at) << "\"parts\": [";
    json_tail = text.substr(at + mark.size());
    csv_out.emplace(out_dir / "predictions.csv");
  }
  std::ostringstream csv;
  csv << "part,file,status,top,top_name,confidence,consistency,unfamiliar,d2_min,expected";
  for (std::size_t k = 1; k <= K; ++k) csv << ",p_" << k;
  csv << ",error\n";
  if (csv_out) csv_out->stream() << csv.str();
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
    pp.regret_risk = u["regret_risk"].get<double>();
    pp.expected_regret = u["expected_regret"].get<std::vector<double>>();
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
        (void)report::grouped_bar_png(
            pp.png, model.strategies,
            {{"mean probability over " + std::to_string(jp["variants"].size()) + " variants", pp.mean},
             {"share of variants ranking it first", pp.first_share}},
            pp.name + ": predicted finishing strategy " + std::to_string(pp.top) + " (consistency " +
                fixed(100 * pp.consistency, 0) + " %)" + (pp.unfamiliar ? " - UNFAMILIAR part" : ""),
            "probability / share", {.show_values = true, .value_decimals = 2, .y_range = std::pair{0.0, 1.0}});
        if (pp.unfamiliar)
          warn("predict: " + pp.file + ": far from every stored model (d² = " + fixed(pp.d2_min, 1) + " > threshold " +
               fixed(model.unfamiliar_threshold, 1) + "): the prediction is an extrapolation");
      } catch (const std::exception& e) {
        pp.ok = false;
        pp.error = e.what();
        jp["status"] = "error";
        jp["error"] = pp.error;
      }
    }
    if (!pp.ok) warn("predict: " + pp.error);
    csv.str("");
    csv << pp.name << "," << pp.file << "," << (pp.ok ? "ok" : "error") << "," << pp.top << ","
        << (pp.ok ? "\"" + strategy_name(model.strategies, pp.top) + "\"" : "") << "," << format_double(pp.confidence)
        << "," << format_double(pp.consistency) << "," << (pp.unfamiliar ? 1 : 0) << "," << format_double(pp.d2_min)
        << "," << pp.expected;
    for (std::size_t k = 0; k < K; ++k) csv << "," << (pp.ok ? format_double(pp.mean[k]) : "");
    std::string err = pp.error;
    std::replace(err.begin(), err.end(), '"', '\'');
    csv << "," << (err.empty() ? "" : "\"" + err + "\"") << "\n";
    csv_out->stream() << csv.str();
    std::string element = jp.dump(2);  // one level in: every line of it indented by four spaces
    std::string indented = "    ";
    for (const char c : element) {
      indented += c;
      if (c == '\n') indented += "    ";
    }
    json_out->stream() << (first_part ? "\n" : ",\n") << indented;
    first_part = false;
    results.push_back(std::move(pp));
  };
  const DistributeStats st = distribute(
      parts.size(), [&](std::size_t i) { return predict_one(folder, parts[i], prep); }, emit, false, "predict");
  if (!cluster_root()) return results;
  log_distribution("predict", st);
  json_out->stream() << (first_part ? "]" : "\n  ]") << json_tail;
  json_out->commit();
  csv_out->commit();
  return results;
}

}  // namespace millnet::app
