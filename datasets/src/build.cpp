#include "millnet/datasets/build.hpp"

#include "millnet/core/json_text.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/features.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <set>

namespace millnet::datasets {
namespace fs = std::filesystem;

namespace {

// Parts whose triangles add up to this many are held in memory at once; their (part, variant)
// pairs form one parallel batch. Bounds memory for large libraries (~100 bytes per triangle).
constexpr std::size_t kBatchTriangles = 4'000'000;

std::string units_name(ingest::Units u) {
  switch (u) {
    case ingest::Units::mm: return "mm";
    case ingest::Units::inch: return "inch";
    case ingest::Units::m: return "m";
  }
  return "mm";
}

std::string part_name(const PartSpec& p) { return p.name.empty() ? p.file.stem().string() : p.name; }

// Errors from ingest usually start with the path already; add it only when they do not.
Error part_error(const PartSpec& p, const std::string& what) {
  const std::string file = p.file.string();
  if (what.rfind(file, 0) == 0) return Error("part '" + part_name(p) + "': " + what);
  return Error("part '" + part_name(p) + "': " + file + ": " + what);
}

}  // namespace

std::vector<PartSpec> to_part_specs(const std::vector<GeneratedPart>& parts) {
  std::vector<PartSpec> specs;
  specs.reserve(parts.size());
  for (const auto& p : parts) specs.push_back({p.file, p.label, p.name, false, std::nullopt});
  return specs;
}

std::string recipe_json(const Recipe& r) {
  std::string j = "{\"parts\": [";
  for (std::size_t k = 0; k < r.parts.size(); ++k)
    j += (k ? ", " : "") + std::string("{\"file\": ") + json_string(r.parts[k].file.generic_string()) +
         ", \"label\": " +
         (r.parts[k].label_by_simulation ? std::string("\"simulate\"") : std::to_string(r.parts[k].label)) +
         ", \"name\": " + json_string(part_name(r.parts[k])) + "}";
  j += "], \"units\": " + json_string(units_name(r.units)) + ", \"up\": " + json_string(ingest::to_string(r.up)) +
       ", \"raster_mm\": " + json_number(r.raster_mm, "raster_mm") + ", \"grid\": " + std::to_string(r.grid) +
       ", \"augment\": {\"angles_deg\": [";
  for (std::size_t k = 0; k < r.augment.angles_deg.size(); ++k)
    j += (k ? ", " : "") + json_number(r.augment.angles_deg[k], "augment.angles_deg");
  j += "], \"axes\": [";
  for (std::size_t k = 0; k < r.augment.axes.size(); ++k)
    j += (k ? ", \"" : "\"") + std::string(1, augment::to_char(r.augment.axes[k])) + "\"";
  j += std::string("], \"flip\": ") + (r.augment.flip ? "true" : "false") + "}, \"strategies\": [";
  for (std::size_t k = 0; k < kStrategySlots; ++k) j += (k ? ", " : "") + json_string(r.strategies[k]);
  j += std::string("], \"aspect_feature\": ") + (r.aspect_feature ? "true" : "false");
  if (r.wall_share_feature) j += ", \"wall_share_feature\": true";  // absent when false (older manifests)
  if (r.generate && r.generate->library == Library::Shop)
    j += ", \"generate\": {\"library\": \"shop\", \"seed\": " + std::to_string(r.generate->seed) +
         ", \"count\": " + std::to_string(r.generate->count) +
         ", \"spacing_mm\": " + json_number(r.generate->spacing_mm, "generate.spacing_mm") + "}";
  else if (r.generate)
    j += ", \"generate\": {\"seed\": " + std::to_string(r.generate->seed) +
         ", \"per_family\": " + std::to_string(r.generate->per_family) +
         ", \"resolution\": " + std::to_string(r.generate->resolution) + "}";
  const bool simulated =
      std::any_of(r.parts.begin(), r.parts.end(), [](const PartSpec& p) { return p.label_by_simulation; });
  if (simulated && !r.simulation_settings_json.empty()) j += ", \"label_by_simulation\": " + r.simulation_settings_json;
  return j + "}";
}

TablePlan plan_table(const Recipe& recipe) {
  if (recipe.parts.empty()) throw Error("dataset recipe: no parts");
  if (!(recipe.raster_mm > 0))
    throw Error("dataset recipe: raster_mm must be > 0, got " + format_double(recipe.raster_mm));
  if (recipe.grid < 2) throw Error("dataset recipe: grid must be ≥ 2, got " + std::to_string(recipe.grid));
  std::set<std::string> names;
  for (const auto& p : recipe.parts) {
    if (p.label < 0 || p.label > static_cast<int>(kStrategySlots))
      throw Error("dataset recipe: part " + p.file.string() + ": label " + std::to_string(p.label) + " outside 0..8");
    if (p.label_by_simulation && p.label < 1)
      throw Error("dataset recipe: part " + p.file.string() + ": its label by simulation was not resolved");
    if (!names.insert(part_name(p)).second)
      throw Error("dataset recipe: two parts are named '" + part_name(p) + "' (names group the variants of one part)");
  }
  TablePlan plan;
  plan.header.grid_n = recipe.grid;
  plan.header.has_aspect = recipe.aspect_feature;
  plan.header.has_wall_share = recipe.wall_share_feature;
  plan.header.strategies = recipe.strategies;
  plan.header.config_json = recipe_json(recipe);
  for (const auto& p : recipe.parts) {
    plan.variants.push_back(augment::make_variants(part_name(p), recipe.augment));
    if (plan.variants.back().empty()) throw Error("dataset recipe: the augmentation gives no variants (no angles?)");
    plan.first_row.push_back(plan.rows);
    plan.rows += plan.variants.back().size();
  }
  // The table's values before any part is read (issue 12): rows × inputs per row.
  const double values = static_cast<double>(plan.rows) * static_cast<double>(plan.header.inputs_per_row());
  check_work({std::to_string(recipe.parts.size()) + " parts × their " + std::to_string(plan.rows) +
                  " augmented variants at grid " + std::to_string(recipe.grid),
              values, "model-vector table values", 8.0 * values},
             recipe.limits);
  return plan;
}

LoadedPart load_table_part(const Recipe& recipe, std::size_t k) {
  const PartSpec& p = recipe.parts[k];
  ingest::PrepareOptions popts;
  popts.units = recipe.units;
  popts.units_explicit = recipe.units_explicit;
  popts.cad = recipe.cad;
  popts.up = recipe.up;
  LoadedPart l;
  l.source.name = part_name(p);
  l.source.file = p.file.generic_string();
  l.source.label = p.label;
  try {
    l.source.fnv1a64 = fnv1a64_file(p.file, &l.source.bytes);
    ingest::MeshReport rep;
    l.mesh = ingest::load_prepared(p.file, popts, &rep);
    l.source.triangles = rep.triangles;
    l.source.degenerate_triangles = rep.degenerate_triangles;
    if (recipe.wall_share_feature) l.wall_share = wall_share(l.mesh);  // once per part: O(triangles)
  } catch (const std::exception& e) {
    throw part_error(p, e.what());
  }
  return l;
}

Row variant_row(const Recipe& recipe, const TablePlan& plan, std::size_t k, const ingest::Mesh& mesh, std::size_t v,
                double part_wall_share) {
  const PartSpec& p = recipe.parts[k];
  const augment::Variant& var = plan.variants[k][v];
  try {
    ModelVector mv = model_vector(mesh, var, recipe.raster_mm, recipe.grid, recipe.limits);
    Row r;
    r.id = part_name(p) + "#" + std::to_string(v + 1);
    r.source = part_name(p);
    r.label = p.label;
    r.axis = var.axis;
    r.angle_deg = var.angle_deg;
    r.flip = var.flip;
    r.inputs = std::move(mv.inputs);
    r.inputs.resize(plan.header.inputs_per_row());
    r.outputs = p.outputs ? *p.outputs : one_hot(p.label);
    r.aspect = mv.aspect;
    if (recipe.wall_share_feature) r.wall_share = part_wall_share;  // the part's, on every variant
    return r;
  } catch (const std::exception& e) {
    throw part_error(p, "variant " + std::to_string(v + 1) + " (axis " + std::string(1, augment::to_char(var.axis)) +
                            ", angle " + format_double(var.angle_deg) + "°, flip " + (var.flip ? "1" : "0") +
                            "): " + e.what());
  }
}

void build_rows(const Recipe& recipe, const TablePlan& plan, const RowSink& sink, std::vector<SourceFile>& sources,
                const ProgressFn& progress) {
  const std::size_t total = plan.rows;
  std::size_t row_at = 0;
  if (progress) progress(0, total);
  std::size_t next_part = 0;
  while (next_part < recipe.parts.size()) {  // batches of parts: O(parts) iterations in all
    // 1. Load serially (clear errors, bounded memory).
    std::vector<ingest::Mesh> meshes;
    std::vector<double> walls;
    std::vector<std::size_t> batch_parts;
    std::size_t triangles = 0;
    while (next_part < recipe.parts.size() && (meshes.empty() || triangles < kBatchTriangles)) {
      LoadedPart l = load_table_part(recipe, next_part);
      triangles += static_cast<std::size_t>(l.mesh.F.rows());
      sources.push_back(std::move(l.source));
      meshes.push_back(std::move(l.mesh));
      walls.push_back(l.wall_share);
      batch_parts.push_back(next_part++);
    }
    // 2. (part, variant) pairs of the batch in parallel; each writes only its own row and error slot.
    std::vector<std::pair<std::size_t, std::size_t>> tasks;
    for (std::size_t b = 0; b < meshes.size(); ++b)
      for (std::size_t v = 0; v < plan.variants[batch_parts[b]].size(); ++v) tasks.emplace_back(b, v);
    std::vector<Row> rows(tasks.size());
    std::vector<std::string> errors(tasks.size());
    const auto n_tasks = static_cast<long>(tasks.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (long k = 0; k < n_tasks; ++k) {  // O(tasks · (triangles + raster points))
      const auto [b, v] = tasks[static_cast<std::size_t>(k)];
      try {
        rows[static_cast<std::size_t>(k)] = variant_row(recipe, plan, batch_parts[b], meshes[b], v, walls[b]);
      } catch (const std::exception& e) {
        errors[static_cast<std::size_t>(k)] = e.what();
      } catch (...) {
        errors[static_cast<std::size_t>(k)] =
            part_error(recipe.parts[batch_parts[b]], "variant " + std::to_string(v + 1) + ": unknown error").what();
      }
    }
    for (std::size_t k = 0; k < tasks.size(); ++k)  // first failure in index order: thread-count independent
      if (!errors[k].empty()) throw Error(errors[k]);
    for (Row& r : rows) sink(std::move(r));
    row_at += rows.size();
    if (progress) progress(row_at, total);
  }
}

Table build_table(const Recipe& recipe, const ProgressFn& progress) {
  const TablePlan plan = plan_table(recipe);
  Table t = plan.header;
  t.rows.reserve(plan.rows);
  build_rows(
      recipe, plan, [&](Row&& r) { t.rows.push_back(std::move(r)); }, t.sources, progress);
  return t;
}

}  // namespace millnet::datasets
