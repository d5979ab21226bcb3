// millnet finish --mesh FILE … --out DIR     (the five finishing strategies, optionally simulated)
// millnet simulate --gcode FILE.nc --mesh FILE --tool … --out DIR   (the z-map simulator on any G-code)
#include "cli.hpp"
#include "finish_job.hpp"
#include "mpi_cluster.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/job/part.hpp"
#include "millnet/gcode/bounds.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <iostream>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

/// A unit's outcomes as they travel between ranks: their metrics files' JSON, as CBOR (doubles bit
/// for bit); the ranking is rebuilt from them on rank 0 (outcome_from_metrics).
struct UnitOutcomes {
  std::vector<job::StrategyOutcome> outcomes;
  Json metrics = Json::array();
  double cell_mm = 0;
};

std::string encode_unit(const UnitOutcomes& u) {
  const std::vector<std::uint8_t> cbor = Json::to_cbor(Json{{"cell_mm", u.cell_mm}, {"metrics", u.metrics}});
  return {cbor.begin(), cbor.end()};
}

UnitOutcomes decode_unit(const std::string& bytes) {
  const Json j = Json::from_cbor(bytes);
  UnitOutcomes u;
  u.cell_mm = j.at("cell_mm").get<double>();
  u.metrics = j.at("metrics");
  for (const Json& m : u.metrics) u.outcomes.push_back(outcome_from_metrics(m, u.cell_mm));
  return u;
}

/// finish over a batch of parts, one code path for one process and for MPI (distribute_typed):
/// a unit is a part (its strategies share the drop-cutter), or under MPI a part × strategy, so
/// that fewer parts than ranks still keep every rank busy. Rank 0 writes each part's files and its
/// ranking when its last unit is in, in a part OutputSet: a batch writes every good part and
/// nothing of a bad one. Returns the number of parts that failed.
std::size_t finish_batch(const std::vector<fs::path>& files, const ingest::PrepareOptions& prep,
                         const FinishSettings& s, const std::string& out, std::vector<std::string>& gouges) {
  const std::size_t S = s.strategies.size();
  const std::size_t per_part = cluster_size() > 1 ? S : 1, chunk = S / per_part;
  const std::function<UnitOutcomes(std::size_t, const std::string&)> work = [&](std::size_t u, const std::string& dir) {
    const job::Part part = load_part(files[u / per_part], prep);
    std::string why;
    const FinishSettings ps = for_part(s, part, &why);  // the part's ball when none is named
    const std::vector<finish::Strategy> mine(
        s.strategies.begin() + static_cast<std::ptrdiff_t>(u % per_part * chunk),
        s.strategies.begin() + static_cast<std::ptrdiff_t>((u % per_part + 1) * chunk));
    UnitOutcomes r;
    r.outcomes = finish_strategies(part, ps, mine, dir);
    if (!why.empty() && u % per_part == 0) info("finish: " + part.name + ": " + why);
    r.cell_mm = sim_params(ps).cell_mm;
    for (const job::StrategyOutcome& o : r.outcomes) r.metrics.push_back(strategy_metrics(o, ps, part));
    return r;
  };
  std::vector<job::StrategyOutcome> outcomes;
  std::vector<std::string> packed;
  std::optional<std::string> error;
  std::size_t failed = 0;
  const std::function<void(std::size_t, UnitOutcome<UnitOutcomes> &&)> take = [&](std::size_t u,
                                                                                  UnitOutcome<UnitOutcomes>&& r) {
    const fs::path& f = files[u / per_part];
    if (u % per_part == 0) outcomes.clear(), packed.clear(), error.reset();
    if (!r.value && !error) error = r.error;
    if (r.value && !error) {
      outcomes.insert(outcomes.end(), r.value->outcomes.begin(), r.value->outcomes.end());
      packed.push_back(std::move(r.files));
    }
    if (u % per_part != per_part - 1) return;
    if (error) {  // the part's first failure, once; nothing of it is written
      if (files.size() == 1) throw Error(*error);
      warn(f.string() + ": " + *error);
      ++failed;
      return;
    }
    OutputSet part;  // this part's files complete, or none of them (core/output_set.hpp)
    for (const std::string& p : packed) unpack_files(p, out);
    write_strategy_ranking(f.stem().string(), s, outcomes, out);
    part.commit();
    for (const job::StrategyOutcome& o : outcomes)  // a confirmed gouge fails the command (issue 37 §1)
      if (o.simulated && o.surface.gouged) {
        const std::string base = f.stem().string() + ".s" + std::to_string(static_cast<int>(o.strategy));
        gouges.push_back(gouge_failure((fs::path(out) / program_file_name(base, o)).string(), o.surface));
      }
    info("finish: " + f.string() + ": " + std::to_string(outcomes.size()) + " strategies → " + out);
  };
  const DistributeStats st = distribute_typed<UnitOutcomes>(files.size() * per_part, work, take, false, "finish: parts",
                                                            {&encode_unit, &decode_unit});
  if (cluster_root()) log_distribution("finish", st);
  return failed;
}

}  // namespace

Registered register_finish(CLI::App& app) {
  struct Opts {
    Common common;
    MeshFlags mesh_flags;
    std::vector<std::string> meshes;
    std::optional<std::string> strategy, tool, material, post;
    std::optional<double> stepover, step_down, boundary_angle, scallop;
    BoundaryFlags boundary;
    bool simulate = false, pencil = false;
    std::optional<std::string> rest_tool, rest_reference, rest_from;
    std::optional<double> rest_threshold, rest_margin;
    int pencil_offsets = 0;
    std::string out;
  };
  auto o = std::make_shared<Opts>();
  auto parse_strategy_flag = [](const std::string& v) {
    try {
      return finish::parse_strategy(v);
    } catch (const Error&) {
      const std::vector<std::string> c = finish::strategy_choices();  // the registry's slots and "all"
      std::string expected;
      for (std::size_t i = 0; i < c.size(); ++i) expected += (i == 0 ? "" : i + 1 == c.size() ? " or " : ", ") + c[i];
      throw Error("--strategy: unknown finishing strategy '" + v.substr(0, 40) + "' (expected " + expected + ")");
    }
  };
  CLI::App* sub = app.add_subcommand(
      "finish",
      "finishing tool paths (Korosec & Kopac strategies 1..5) → G-code, metrics, PNG; --simulate scores them");
  sub->add_option("--mesh", o->meshes, "mesh file or folder (repeatable; added to /finish/meshes)");
  o->mesh_flags.add_to(sub);
  // Checked by finish::parse_strategy: one line and exit 1, like every other bad value.
  sub->add_option("--strategy", o->strategy, "strategy slot 1..5 or all");
  sub->add_option("--tool", o->tool,
                  "cutter: a tool library id (configs/tools.json), or ball:D, flat:D or bull:D:r (mm)");
  sub->add_option("--material", o->material, "workpiece material id (configs/materials.json)");
  sub->add_option("--stepover", o->stepover, "p_f, mm (every strategy then uses the parameters as written)")
      ->check(schema_range("/finish/stepover_mm"));
  sub->add_option("--step-down", o->step_down, "a_a, mm")->check(schema_range("/finish/step_down_mm"));
  sub->add_option("--boundary-angle", o->boundary_angle, "slope-mode boundary angle, degrees")
      ->check(schema_range("/finish/boundary_angle_deg"));
  sub->add_option("--scallop", o->scallop,
                  "largest scallop of the surface specification (and scallop mode's target), mm")
      ->check(schema_range("/finish/scallop_mm"));
  o->boundary.add_to(sub);
  sub->add_flag("--simulate", o->simulate, "machine each program on a z-map and score the surface");
  sub->add_option("--rest-tool", o->rest_tool,
                  "rest finishing with this smaller tool (ball:D, bull:D:r or a library id): <stem>.rest.nc");
  sub->add_option("--rest-reference", o->rest_reference, "the tool whose rest is taken (default: the finishing tool)");
  sub->add_option("--rest-from", o->rest_from,
                  "rest from the stock: a FILE.zmap saved by simulate --save-stock (or a folder of <stem>.zmap); "
                  "instead of --rest-reference");
  sub->add_option("--rest-threshold", o->rest_threshold, "material thicker than this is rest, mm (default 0.02)")
      ->check(CLI::Range(0.001, 10.0));
  sub->add_option("--rest-margin", o->rest_margin,
                  "rest regions grown by this, mm (default: the rest tool's radius / 2)")
      ->check(CLI::Range(0.0, 100.0));
  sub->add_flag("--pencil", o->pencil, "pencil tracing along concave edges with the finishing tool: <stem>.pencil.nc");
  sub->add_option("--pencil-offsets", o->pencil_offsets,
                  "multi-pencil: this many passes each side of the pencil line, the stepover apart (outermost "
                  "first, the corner last; needs --pencil)")
      ->check(CLI::Range(0, 50));
  add_post_flag(sub, o->post);
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common);
  return {sub, [o, parse_strategy_flag]() {
            const Json config = setup(o->common);
            FinishSettings s = finish_settings(config, {o->tool, o->material});
            if (o->post) s.post = post_dialect(config, o->post);
            if (o->strategy) {
              s.strategies =
                  *o->strategy == "all" ? finish::all_strategies() : std::vector{parse_strategy_flag(*o->strategy)};
            }
            if (o->stepover) s.params.stepover_mm = *o->stepover;
            if (o->step_down) s.params.step_down_mm = *o->step_down;
            if (o->boundary_angle) s.params.boundary_angle_deg = *o->boundary_angle;
            if (o->scallop) {  // the scallop target is the specification's (and scallop mode's)
              s.params.scallop_mm = *o->scallop;
              s.spec.scallop_mm = *o->scallop;
            }
            if ((o->stepover || o->step_down) && s.params_from_spec) {
              s.params_from_spec = false;  // a stepover written on the command line is the one cut
              info(
                  "finish: --stepover/--step-down given: every strategy uses the parameters as written, not "
                  "derived from /finish/spec (/finish/params_from fixed)");
            }
            o->boundary.apply(s);
            s.simulate = o->simulate;
            if (o->rest_tool) rest_tool_settings(s, *o->rest_tool, config, {o->tool, o->material});
            if (o->rest_reference) s.rest_reference = tool_arg(*o->rest_reference, config);
            if (o->rest_reference && !o->rest_tool) throw Error("--rest-reference needs --rest-tool");
            if (o->rest_from && !o->rest_tool) throw Error("--rest-from needs --rest-tool");
            if (o->rest_from && o->rest_reference)
              throw Error(
                  "--rest-from and --rest-reference: the rest comes from the stock or from a reference "
                  "tool, not both");
            if (o->rest_from) s.rest_from = *o->rest_from;
            if (o->rest_threshold) s.rest_threshold_mm = *o->rest_threshold;
            if (o->rest_margin) s.rest_margin_mm = *o->rest_margin;
            s.pencil = o->pencil;
            if (o->pencil_offsets > 0 && !o->pencil) throw Error("--pencil-offsets needs --pencil");
            s.pencil_offsets = o->pencil_offsets;
            s.params.check();
            std::vector<std::string> items = config["finish"]["meshes"].get<std::vector<std::string>>();
            items.insert(items.end(), o->meshes.begin(), o->meshes.end());
            if (items.empty()) throw Error("no mesh to finish: give --mesh FILE or set /finish/meshes in the config");
            const auto files = expand_inputs(items, ingest::mesh_extensions());
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"], &config);
            std::vector<std::string> gouges;
            const std::size_t failed = finish_batch(files, prep, s, o->out, gouges);
            if (!cluster_root()) return 0;
            // A program that gouges is a failure: its files are written (the program as .GOUGES.nc).
            for (const std::string& g : gouges) std::cerr << "millnet finish: error: " << g << "\n";
            if (failed == 0) return gouges.empty() ? 0 : 1;
            // The good parts are written (the command's outputs commit when it returns).
            std::cerr << ("millnet finish: error: " + std::to_string(failed) + " of " + std::to_string(files.size()) +
                          " parts failed (named above); the other parts are written\n");
            return 1;
          }};
}

Registered register_simulate(CLI::App& app) {
  struct Opts {
    Common common;
    MeshFlags mesh_flags;
    std::vector<std::string> gcode, tools;
    std::string mesh, stock = "flat", out;
    bool save_stock = false, moves = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "simulate", "machine G-code programs on a z-map of the part and score the surface (gouge, scallop, Ra)");
  sub->add_option("--gcode", o->gcode, "G-code file (repeatable: machined in order on the same stock)")->required();
  sub->add_option("--tool", o->tools,
                  "cutter per --gcode (a tool library id, or ball:D, flat:D, bull:D:r; one for all, or one each)")
      ->required();
  sub->add_option("--mesh", o->mesh, "the part's mesh (design surface and frame)")->required();
  sub->add_option("--stock", o->stock,
                  "flat (a block up to Z 0), design (the part + /simulate/allowance_mm), or a FILE.zmap saved by an "
                  "earlier simulate --save-stock of the same part");
  sub->add_flag("--save-stock", o->save_stock, "also write the machined z-map as DIR/<stem>.zmap (8 bytes per cell)");
  sub->add_flag("--moves", o->moves,
                "also write every move as machined (its line, end point, length, deepest cut and whether it cut "
                "air) as DIR/<stem>.moves.csv");
  o->mesh_flags.add_to(sub);
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            FinishSettings s = finish_settings(config);
            if (o->tools.size() != 1 && o->tools.size() != o->gcode.size())
              throw Error("give one --tool for all programs or one per --gcode (" + std::to_string(o->gcode.size()) +
                          " programs, " + std::to_string(o->tools.size()) + " tools)");
            std::vector<ChainProgram> programs;
            for (std::size_t i = 0; i < o->gcode.size(); ++i)  // each file read once, before any output
              programs.push_back(
                  read_chain_program(o->gcode[i], tool_arg(o->tools[o->tools.size() == 1 ? 0 : i], config, true)));
            // /simulate/cells_per_pass: the cell of the finest passes, the smallest of the programs' cutters.
            if (s.sim.cells_per_pass > 0)  // (--gcode is required: programs is not empty)
              s.params.tool = std::min_element(programs.begin(), programs.end(), [](const auto& a, const auto& b) {
                                return a.cutter.radius() < b.cutter.radius();
                              })->cutter;
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"], &config);
            const job::Part part = load_part(o->mesh, prep);
            // The programs' work origin (/machine/work_origin) on this part's stock, back to millnet's frame.
            const gcode::Dialect post = job::frame_of(part.mesh, s.stock_top_above_part_mm).post(s.post);
            for (ChainProgram& p : programs) gcode::shift(p.written.program, post.origin[0], post.origin[1]);
            const Json j = simulate_programs(part, part.name, std::move(programs), o->stock, s, o->out, o->save_stock,
                                             nullptr, true, o->moves);
            info("simulate: Ra median " + j["ra_median_um"].dump() + " um, gouge " + j["max_gouge_mm"].dump() +
                 " mm → " + o->out);
            if (!j.contains("gouge_failure")) return 0;
            // A confirmed gouge is a failure (issue 37 §1); the outputs and the program's copy are written.
            std::cerr << "millnet simulate: error: " << j["gouge_failure"].get<std::string>() << "\n";
            return 1;
          }};
}

}  // namespace millnet::app
