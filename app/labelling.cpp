// Labels by virtual machining (labelling.hpp).
#include "labelling.hpp"

#include "config.hpp"
#include "finish_job.hpp"
#include "mpi_cluster.hpp"
#include "text.hpp"

#include "millnet/core/error.hpp"
#include "millnet/datasets/agreement.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/simulate/aim.hpp"

#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>

namespace millnet::app {
namespace fs = std::filesystem;

std::string strategy_name(const std::vector<std::string>& names, int slot) {
  return slot >= 1 && static_cast<std::size_t>(slot) <= names.size() ? names[static_cast<std::size_t>(slot - 1)]
                                                                     : std::string("?");
}

namespace {

std::string part_name_of(const datasets::PartSpec& p) { return p.name.empty() ? p.file.stem().string() : p.name; }

/// Plans and simulates the five strategies on recipe part k (app::label_part: nothing written).
/// Throws millnet::Error naming the part.
SimulatedLabel simulate_label(const datasets::Recipe& recipe, std::size_t k, const FinishSettings& settings) {
  ingest::PrepareOptions prep;
  prep.units = recipe.units;
  prep.units_explicit = recipe.units_explicit;
  prep.cad = recipe.cad;
  prep.up = recipe.up;
  const datasets::PartSpec& p = recipe.parts[k];
  const std::string name = part_name_of(p);
  SimulatedLabel sl;
  sl.recipe_label = p.label_by_simulation ? 0 : p.label;
  sl.label.name = name;
  try {
    sl.label.fnv1a64 = datasets::to_hex(datasets::fnv1a64_file(p.file, &sl.label.bytes));
    job::Part part = load_part(p.file, prep);
    part.name = name;
    for (const job::StrategyFigures& f : label_part(part, settings)) {
      if (f.rank == 1) sl.label.best = f.slot;
      datasets_io::StrategyLabel s;
      s.strategy = f.slot;
      s.rank = f.rank;
      s.score = f.aim_score;
      s.time_min = f.score.time_min;
      s.spec_share = f.score.spec_share;
      s.meets_spec = simulate::meets_spec(f.score, settings.aim);
      s.max_gouge_mm = f.score.max_gouge_mm;
      s.ra_median_um = f.score.ra_median_um;
      s.ra_p90_um = f.score.ra_p90_um;
      s.uncut_area_mm2 = f.score.uncut_area_mm2;
      s.regret = f.regret;
      sl.label.strategies.push_back(s);
    }
  } catch (const std::exception& e) {
    throw Error("dataset: part '" + name + "' (" + p.file.string() + "): labelling by simulation: " + e.what());
  }
  return sl;
}

std::string encode_label(const SimulatedLabel& sl) {
  return std::to_string(sl.recipe_label) + "\n" + datasets_io::part_label_text(sl.label);
}

SimulatedLabel decode_label(const std::string& bytes) {
  const std::size_t nl = bytes.find('\n');
  if (nl == std::string::npos) throw Error("mpi: a simulated label without its recipe label");
  return {datasets_io::parse_part_label(bytes.substr(nl + 1), "mpi: a simulated label"),
          std::stoi(bytes.substr(0, nl))};
}

/// Plans and simulates the five strategies on each part and returns the slot the aim ranks first.
/// A part that fails stops the build (all-or-nothing, as the table). One code path for one
/// process and for MPI (a unit is a part), results in part order.
std::vector<SimulatedLabel> simulate_labels(const datasets::Recipe& recipe, const std::vector<std::size_t>& which,
                                            const FinishSettings& settings) {
  std::vector<SimulatedLabel> out;
  if (which.empty()) return out;
  const std::function<SimulatedLabel(std::size_t, const std::string&)> work = [&](std::size_t i, const std::string&) {
    return simulate_label(recipe, which[i], settings);
  };
  const std::function<void(std::size_t, UnitOutcome<SimulatedLabel> &&)> take = [&](std::size_t,
                                                                                    UnitOutcome<SimulatedLabel>&& r) {
    if (!r.value) throw Error(r.error);  // the part's own message (simulate_label names it)
    out.push_back(std::move(*r.value));
  };
  const DistributeStats st = distribute_typed<SimulatedLabel>(
      which.size(), work, take, true, "dataset: labels by simulation", {&encode_label, &decode_label});
  log_distribution("dataset: labels by simulation", st);
  return out;
}

/// The label settings `text` (/finish, /simulate, /cutting, /machine as recipe_from_config writes
/// them) with every key it lacks at its schema default; null when it does not pass the schema (a
/// key since removed, a value out of today's range).
Json label_settings_with_defaults(const std::string& text) {
  Json rule = {{"type", "object"}, {"properties", Json::object()}};
  Json doc;
  try {
    doc = Json::parse(text);
    if (!doc.is_object()) return nullptr;
    for (const char* section : {"finish", "simulate", "cutting", "machine"}) {
      rule["properties"][section] = schema()["properties"][section];
      if (!doc.contains(section)) doc[section] = Json::object();
    }
    check_against(doc, rule, fs::path(), "labels settings");
  } catch (const std::exception&) {
    return nullptr;
  }
  doc["finish"].erase("meshes");  // not label settings (recipe_from_config drops them too)
  doc["finish"].erase("strategy");
  doc["finish"].erase("rest");                  // a job's rest operation: no label plans it (label_part)
  doc["machine"].erase("max_depth_of_cut_mm");  // a job's limit: no label's finishing checks it
  return doc;
}

}  // namespace

bool same_label_settings(const std::string& cached, const std::string& current) {
  const Json a = label_settings_with_defaults(cached);
  return !a.is_null() && a == label_settings_with_defaults(current);
}

namespace {

/// The recipe's labels.json when it exists, was computed with the same settings and --relabel was
/// not asked; an empty file otherwise (the line says why).
datasets_io::LabelFile cached_labels(const datasets::Recipe& recipe) {
  if (recipe.labels_file.empty() || recipe.relabel || recipe.simulation_settings_json.empty()) return {};
  if (!fs::exists(recipe.labels_file)) {
    info("dataset: no " + recipe.labels_file.string() + " yet: every part labelled by simulation is simulated");
    return {};
  }
  datasets_io::LabelFile f = datasets_io::read_labels(recipe.labels_file);
  if (!same_label_settings(f.settings_json, recipe.simulation_settings_json)) {
    info("dataset: " + recipe.labels_file.string() +
         " was computed with other settings (/finish, /simulate, /cutting or /machine): every part is simulated");
    return {};
  }
  return f;
}

}  // namespace

/// The labels of recipe parts `which`: from the recipe's labels.json where the part's file bytes and
/// the settings match, by simulation otherwise (issue 39 §2). In `which` order, on rank 0; empty on
/// the other ranks (they simulate their share of the parts and hand it to rank 0).
std::vector<SimulatedLabel> labels_of(const datasets::Recipe& recipe, const std::vector<std::size_t>& which,
                                      const FinishSettings& settings) {
  const datasets_io::LabelFile cache = cached_labels(recipe);
  std::vector<std::optional<SimulatedLabel>> got(which.size());
  std::vector<std::size_t> missing;
  for (std::size_t i = 0; i < which.size(); ++i) {  // O(parts · cached parts), one hash of each file
    const datasets::PartSpec& p = recipe.parts[which[i]];
    std::uintmax_t bytes = 0;
    const std::string hash = cache.parts.empty() ? "" : datasets::to_hex(datasets::fnv1a64_file(p.file, &bytes));
    if (const datasets_io::PartLabel* c = cache.find(part_name_of(p), hash, bytes))
      got[i] = SimulatedLabel{*c, p.label_by_simulation ? 0 : p.label};
    else
      missing.push_back(which[i]);
  }
  if (!cache.parts.empty())
    info("dataset: labels by simulation: " + std::to_string(which.size() - missing.size()) + " of " +
         std::to_string(which.size()) + " parts from " + recipe.labels_file.string() + ", " +
         std::to_string(missing.size()) + " to simulate");
  std::vector<SimulatedLabel> fresh = simulate_labels(recipe, missing, settings);
  if (!cluster_root()) return {};  // rank 0 holds the simulated labels (simulate_labels)
  std::vector<SimulatedLabel> out;
  std::size_t f = 0;
  for (auto& g : got) out.push_back(g ? std::move(*g) : std::move(fresh[f++]));
  return out;
}

/// A label's figures as the manifest echoes them (under "labelling").
Json figures_json(const datasets_io::PartLabel& l) {
  Json figures = Json::parse(datasets_io::part_label_text(l))["strategies"];
  return figures;
}

/// The agreement of the simulated best with the recipe's labels, per label: JSON and a Markdown table.
std::pair<Json, std::string> agreement(const std::vector<SimulatedLabel>& labels, const datasets::Recipe& recipe) {
  std::vector<datasets::LabelledBest> parts;
  for (const auto& l : labels) parts.push_back({l.recipe_label, l.label.best});
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

}  // namespace millnet::app
