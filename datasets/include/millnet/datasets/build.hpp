#pragma once
// Building a model-vector table from a recipe: for each part, load_mesh → prepare → for each
// augmented variant apply → sample_grid → one row. All-or-nothing: a part that cannot be loaded or
// sampled aborts the build with an error naming its file (a training set silently missing a part
// would train a different classifier than the one asked for).
#include "millnet/augment/variants.hpp"
#include "millnet/core/budget.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/ingest/mesh.hpp"

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace millnet::datasets {

struct PartSpec {
  std::filesystem::path file;  ///< mesh file (any format ingest::load_mesh reads)
  int label = 0;               ///< 1..8, 0 = unknown
  std::string name;            ///< source name in the table; empty ⇒ the file's stem
  /// The recipe says "label": "simulate": the caller sets `label` to the strategy its virtual
  /// machining ranks first before build_table; recipe_json echoes "simulate" (so an up-to-date
  /// check needs no simulation).
  bool label_by_simulation = false;
  /// The model vector's outputs when they are not one_hot(label): each strategy's score under the
  /// aim for a part labelled by simulation (issue 39 §1; label = the slot scoring highest).
  std::optional<std::array<double, kStrategySlots>> outputs;
};

/// The plain-struct form of a dataset recipe (the CLI parses datasets/recipe.json into it).
struct Recipe {
  std::vector<PartSpec> parts;
  ingest::Units units = ingest::Units::mm;
  bool units_explicit = false;  ///< units override a STEP/IGES part's own unit (see ingest::PrepareOptions)
  ingest::CadOptions cad;       ///< tessellation of STEP/IGES parts
  ingest::Up up = ingest::Up::PosZ;
  double raster_mm = 1.0;  ///< > 0
  int grid = 15;           ///< n of the n×n grid, ≥ 2
  augment::AugmentParams augment = augment::AugmentParams::defaults();
  StrategyNames strategies = default_strategy_names();
  bool aspect_feature = false;             ///< add the `aspect` column
  bool wall_share_feature = false;         ///< add the `wall_share` column (datasets::wall_share)
  std::optional<GenerateParams> generate;  ///< echoed in the manifest when the parts were generated
  /// JSON text of the settings that simulated labels depend on (tool, stepover, aim, …), echoed as
  /// "label_by_simulation" when some part is labelled by simulation; empty otherwise.
  std::string simulation_settings_json;
  /// labels.json of the recipe (issue 39 §2): simulated labels reused where the part file and the
  /// settings match; empty = none. `relabel`: simulate every part labelled by simulation anyway.
  std::filesystem::path labels_file;
  bool relabel = false;
  /// Budgets of the table (rows × inputs per row, counted before any part is read) and of each
  /// variant's height-field raster (ingest::raster_work), issue 12.
  WorkLimits limits;
};

/// Parts of generate_default_parts as recipe parts.
[[nodiscard]] std::vector<PartSpec> to_part_specs(const std::vector<GeneratedPart>& parts);

/// The recipe as JSON text in the recipe.json shape (for the manifest's config echo).
[[nodiscard]] std::string recipe_json(const Recipe& recipe);

/// A recipe's table before any part is read: the recipe checked (labels, names, raster, grid),
/// every part's variants and first row, the header fields of the Table (no rows), and the table's
/// size checked against recipe.limits. Throws millnet::Error. O(parts · variants).
struct TablePlan {
  std::vector<std::vector<augment::Variant>> variants;  ///< per part, augment::make_variants order
  std::vector<std::size_t> first_row;                   ///< per part: its first row's index
  std::size_t rows = 0;
  Table header;  ///< grid_n, has_aspect, strategies, config_json
};
[[nodiscard]] TablePlan plan_table(const Recipe& recipe);

/// Part k loaded and prepared for sampling, with its manifest record (hash, size, triangles).
/// Throws millnet::Error naming the part and its file.
struct LoadedPart {
  ingest::Mesh mesh;
  SourceFile source;
  double wall_share = 0;  ///< the part's (datasets::wall_share), with Recipe::wall_share_feature
};
[[nodiscard]] LoadedPart load_table_part(const Recipe& recipe, std::size_t k);

/// The row of variant v of part k (its mesh and wall share loaded by load_table_part). Throws
/// millnet::Error naming the part and the variant. O(triangles + raster points).
[[nodiscard]] Row variant_row(const Recipe& recipe, const TablePlan& plan, std::size_t k, const ingest::Mesh& mesh,
                              std::size_t v, double wall_share = 0);

using RowSink = std::function<void(Row&&)>;

/// Every row in table order to `sink` (and every part's record to `sources`), holding one batch of
/// parts (≈ 4 M triangles) and its rows at a time: OpenMP over the batch's (part, variant) pairs,
/// rows delivered in order after the batch. Throws the first failure in index order.
void build_rows(const Recipe& recipe, const TablePlan& plan, const RowSink& sink, std::vector<SourceFile>& sources,
                const ProgressFn& progress = {});

/// Builds the table. Rows are ordered part by part, variants in augment::make_variants order;
/// ids are "<name>#<k>" (k = 1-based variant index). OpenMP over (part, variant) pairs with results
/// placed by index: identical table for any thread count. `progress` (done, total rows) is called
/// from serial code only. Throws millnet::Error naming the part file. O(rows · (triangles + raster)).
[[nodiscard]] Table build_table(const Recipe& recipe, const ProgressFn& progress = {});

}  // namespace millnet::datasets
