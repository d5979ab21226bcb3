#pragma once
// The one place where a checked config (and the command-line flags that override it) becomes the
// modules' parameter structs. Every command reads its settings from here; JSON goes no further.
//
//   pocket, compare, rough, run:  cut_params, planner_choice, rough_params
//   finish, simulate, dataset (labels by simulation), run:  finish_settings, simulated_finish_settings
//   dataset, train, predict, run:  recipe_from_config, train_params, predict_augment, run_settings
#include "cli.hpp"
#include "config.hpp"
#include "cutting.hpp"

#include "millnet/augment/variants.hpp"
#include "millnet/classifier/network.hpp"
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/finish/spec.hpp"
#include "millnet/finish/strategy.hpp"
#include "millnet/gcode/stats.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/mesh.hpp"
#include "millnet/job/frame.hpp"
#include "millnet/pocket/machining.hpp"
#include "millnet/pocket/plan.hpp"
#include "millnet/pocket/planner_som.hpp"
#include "millnet/pocket/planner_zigzag.hpp"
#include "millnet/pocket/io/pocket_io.hpp"
#include "millnet/rough/rough.hpp"
#include "millnet/simulate/aim.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::app {

// ---- pocket (pocket, compare, rough, run) ----

/// `explicit_pocket` = the "pocket" object as written in the config file (no defaults), so that a
/// pocket file's own keys are overridden only by keys the user actually wrote.
/// The roughing tool and its cutting data too (library or fixed feeds, issue 17); `record`, when
/// given, receives every figure with its source (the metrics' "cutting_data").
[[nodiscard]] pocket::CutParams cut_params(const Json& config, const Json& explicit_pocket,
                                           const pocket::PocketFile* file, const PocketFlags& flags,
                                           CuttingRecord* record = nullptr);

/// The pocket section as written in the config file named by --config (empty object otherwise).
[[nodiscard]] Json explicit_pocket_section(const std::string& config_path);

struct PlannerChoice {
  std::string name = "som";  ///< the planner's registry name (pocket/planner_registry.hpp)
  pocket::PlannerSpec spec;  ///< it and its parameters
  pocket::Entry entry = pocket::Entry::Predrill;
  double entry_angle_deg = 3.0;    ///< /pocket/entry_angle: helix and ramp descent
  double ramp_clearance_mm = 0.2;  ///< /pocket/ramp_clearance: where a helix or ramp starts
  bool contour = false;
  bool link_walls = true;
};
/// The machine profile of the motion-time model (/machine/…).
[[nodiscard]] gcode::MotionModel motion_model(const Json& config);

/// The stock block of /rough (margin_mm, stock_offsets_mm or stock_size_mm: one of the last two).
[[nodiscard]] gcode::StockBlock stock_block(const Json& config);

/// The controller's dialect every program is written in: --post, else /machine/post.
[[nodiscard]] gcode::Dialect post_dialect(const Json& config, const std::optional<std::string>& flag);

/// The planner of --planner, else /pocket/planner, with its settings from the "pocket" section and
/// the flags (--partition, --angle). A compare run's defaults are set before the flags, its overrides
/// after them.
[[nodiscard]] PlannerChoice planner_choice(const Json& config, const pocket::CutParams& cut, const PocketFlags& flags,
                                           const pocket::CompareRun* run = nullptr);

/// The machining options of a choice (entry, its angle, wall pass, links) and the config's machine
/// profile; the caller adds the program's name and comments.
[[nodiscard]] pocket::MachiningOptions machining_options(const PlannerChoice& choice, const Json& config);

// ---- rough (rough, run) ----

/// The planner and stock to leave of `rough` and `job` when neither the config's /pocket nor a flag
/// names one (issue 38's shop defaults; /pocket/planner som and /pocket/stock_to_leave 0 written in
/// the config, configs/presets/rough-before-2026-11-27.json, give the roughing of before).
inline constexpr std::string_view kRoughPlanner = "offset";
inline constexpr double kRoughStockToLeaveMm = 0.5;

/// rough::Params from a checked config (rough + pocket sections) and the pocket flags.
[[nodiscard]] rough::Params rough_params(const Json& config, const Json& explicit_pocket, const PocketFlags& flags,
                                         CuttingRecord* record = nullptr);

// ---- finish and simulate (finish, simulate, dataset labels by simulation, run) ----

struct SimSettings {
  double cell_mm = 0.025;     // the schema's default (/simulate/cell_mm)
  double cells_per_pass = 0;  ///< > 0: the cell is the passes' spacing / this (sim_params), not cell_mm
  double allowance_mm = 0.1;  ///< finishing stock over the design surface
  double tolerance_mm = 0.002;
  double sampling_length_mm = 0.8;
  double ra_spacing_mm = 0.1;  ///< Ra centres this far apart (whole cells)
  std::vector<double> ra_bins_um;
  double ra_target_um = 1.6;  ///< the quality aim's Ra target
};

struct FinishSettings {
  finish::FinishParams params;  ///< z_shift and the boundary are set per part
  std::vector<finish::Strategy> strategies;
  finish::SurfaceSpec spec;      ///< /finish/spec: what every simulated strategy is judged by
  bool params_from_spec = true;  ///< /finish/params_from "spec": each strategy derives its parameters
  /// Each strategy's parameters: `base` (the part's) with what it derives from the spec, or base.
  [[nodiscard]] std::vector<finish::FinishParams> strategy_params(const std::vector<finish::Strategy>& which,
                                                                  const finish::FinishParams& base) const;
  bool simulate = false;
  /// Rest finishing (issue 41; finish --rest-tool): the smaller tool, the reference tool whose rest it
  /// takes (unset: the finishing tool) and the thickness that counts as rest.
  std::optional<tooling::Cutter> rest_tool, rest_reference;
  /// The rest tool's own spindle and feeds (rest_tool_settings: the library's for its diameter,
  /// flutes and the material, as the job's rest operation gets); unset: the finishing tool's.
  struct Feeds {
    double spindle_rpm = 0, feed_mm_min = 0, plunge_feed_mm_min = 0;
  };
  std::optional<Feeds> rest_feeds;
  double rest_threshold_mm = 0.02;
  double rest_margin_mm = -1;  ///< < 0: the rest tool's radius / 2
  /// finish --rest-from: the rest from the stock a simulation saved (a FILE.zmap, or a folder holding
  /// <stem>.zmap per part) instead of behind a reference tool; empty: from the reference.
  std::string rest_from;
  bool pencil = false;     ///< finish --pencil: pencil tracing with the finishing tool
  int pencil_offsets = 0;  ///< finish --pencil-offsets: multi-pencil passes each side (finish::plan_pencil)
  double stock_top_above_part_mm = 1;
  gcode::MotionModel machine;
  gcode::Dialect post;  ///< the dialect the programs are written in (/machine/post)
  SimSettings sim;
  simulate::AimParams aim;
  CuttingRecord cutting;  ///< the tool, its cutting data and each figure's source
  /// Radial chip thinning of the finishing feed (issue 38): with the library's cutting data, the feed
  /// not written, /cutting/max_chip_thinning > 1 and the parameters from the spec, a strategy whose
  /// pass spacing on the surface is bounded (slope mode, scallop mode, equidistant: the spec's
  /// spacing w) runs at feed × min(D_eff / (2·√(w·(D_eff − w))), cap), within feed_max, so that its
  /// chip is the tool maker's fz; raster and Z-level (whose spacing on steep or flat areas grows
  /// without bound) keep the feed. d_eff_mm 0: off.
  struct Thinning {
    double d_eff_mm = 0, cap = 1, feed_max_mm_min = 0;
  } thinning;
  /// No finishing tool named (no --tool, /finish/tool/id "" or "auto" and no diameter): every library
  /// ball with its cutting data, one picked per part by for_part (job::finishing_ball). Empty: the
  /// tool above finishes every part.
  struct ToolChoice {
    CuttingRecord cutting;
    Thinning thinning;
    tooling::Cutter cutter;
    double spindle_rpm = 0, feed_mm_min = 0, plunge_feed_mm_min = 0;
  };
  std::vector<ToolChoice> tool_by_part;
  /// /finish/boundary's Z range (program frame: Z 0 = stock top), set into params.boundary per part.
  std::optional<double> z_min, z_max;
  /// /finish/boundary/faces, --faces: a STEP/IGES part's faces (1-based index or name) the axis stays
  /// over; resolved into params.boundary.triangles per part (for_part).
  std::vector<std::string> boundary_faces;
  /// params.boundary with the Z range in the part's mesh frame (the tip's z = program Z − z_shift).
  [[nodiscard]] finish::Boundary boundary_in(const job::Frame& frame) const;
};

/// The ball of /finish/tool when it gives neither an id nor a diameter and a part does not pick its
/// own (the dataset labels by simulation, simulate, view): Korosec & Kopac's Ø2 mm (§6.2).
inline constexpr double kPaperBallMm = 2.0;

/// The settings a part is finished with: `s` itself, or (s.tool_by_part) with the ball
/// job::finishing_ball picks for the part's size, smallest concave radius and depth below the stock
/// top, and that ball's cutting data; `why` (when given) gets one line naming the ball and why.
/// s.boundary_faces are resolved on the part (job::face_selection).
[[nodiscard]] FinishSettings for_part(const FinishSettings& s, const job::Part& part, std::string* why = nullptr);

/// --boundary FILE and --z-range ZMIN ZMAX (finish, job): /finish/boundary from the command line.
struct BoundaryFlags {
  std::optional<std::string> file;
  std::vector<double> z_range;
  std::vector<std::string> faces;
  void add_to(CLI::App* sub);
  /// Reads the outline, checks the range (one line naming the flag), sets them into `s`.
  void apply(FinishSettings& s) const;
};

/// Reads a machining boundary (pocket JSON or DXF: the outline and its islands, arcs flattened to
/// 0.001 mm) into `p`'s polygons; errors name the file.
void set_boundary_file(FinishSettings& s, const std::string& file);

/// "ball:2", "flat:10", "bull:6:1" (type:diameter[:corner radius]); throws millnet::Error.
[[nodiscard]] tooling::Cutter parse_tool(const std::string& text);

/// The command line's choice of finishing tool and material (finish --tool, --material).
struct FinishToolFlags {
  std::optional<std::string> tool;  ///< a library id, or ball:D / flat:D / bull:D:r
  std::optional<std::string> material;
};

/// Settings from a checked config (/finish, /simulate, /machine, /cutting, /rough/top_allowance_mm)
/// and the flags: the tool, then its cutting data (library or fixed feeds).
[[nodiscard]] FinishSettings finish_settings(const Json& config, const FinishToolFlags& flags = {});

/// finish --rest-tool TEXT (a library id, or ball:D / flat:D / bull:D:r): the rest tool into
/// s.rest_tool and its own cutting data into s.rest_feeds (a figure written in /finish wins, as for
/// the finishing tool). Throws millnet::Error naming --rest-tool.
void rest_tool_settings(FinishSettings& s, const std::string& text, const Json& config, const FinishToolFlags& flags);

/// A --tool value of finish or simulate: ball:D, flat:D, bull:D:r, or a tool library id.
/// `drills`: a library drill is taken too (simulate machines what a drill cuts; finishing refuses one).
[[nodiscard]] tooling::Cutter tool_arg(const std::string& text, const Json& config, bool drills = false);

/// finish_settings with every strategy, simulated: how a part is labelled by simulation (dataset)
/// and how run finishes its test parts.
[[nodiscard]] FinishSettings simulated_finish_settings(const Json& config);

// ---- learning (dataset, train, predict, run) ----

/// The dataset recipe of a checked config; generates the default training parts into
/// dataset.parts_dir when dataset.parts is empty (deterministic: same seed ⇒ same bytes).
[[nodiscard]] datasets::Recipe recipe_from_config(const Json& config);
/// /dataset/generate as the generator's parameters (the library, its seed and sizes).
[[nodiscard]] datasets::GenerateParams generate_params(const Json& config);

/// /train → the classifier's training parameters (the progress callback is the caller's).
[[nodiscard]] classifier::TrainParams train_params(const Json& config);

/// /predict/augment: the variants a part is predicted over.
[[nodiscard]] augment::AugmentParams predict_augment(const Json& config);

/// The augmentation an /…/augment object describes (angles, axes, flip).
[[nodiscard]] augment::AugmentParams augment_from(const Json& augment);

/// Mesh preparation from the --units / --up strings.
[[nodiscard]] ingest::PrepareOptions prepare_options(const std::string& units, const std::string& up);

/// /run: which stages run after predict, and where the held-out test parts come from.
struct RunSettings {
  bool rough = true;
  bool finish = true;
  bool job = true;  ///< /run/job (with finish): each test part's job, write_run_job
  struct TestPart {
    std::filesystem::path file;
    std::string name;  ///< empty ⇒ file stem
    int label = 0;
  };
  std::vector<TestPart> test_parts;   ///< /run/test_parts; empty ⇒ generated
  datasets::GenerateParams generate;  ///< /run/generate_test_parts (seed checked against the training parts')
  std::filesystem::path generate_dir;
};
[[nodiscard]] RunSettings run_settings(const Json& config);

}  // namespace millnet::app
