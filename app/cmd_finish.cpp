// millnet finish --mesh FILE … --out DIR     (the five finishing strategies, optionally simulated)
// millnet simulate --gcode FILE.nc --mesh FILE --tool … --out DIR   (the z-map simulator on any G-code)
#include "cli.hpp"
#include "finish_job.hpp"
#include "mpi_cluster.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/gcode/bounds.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
/// A strategy's outcome as it travels from a rank to rank 0 (CBOR: doubles bit for bit).
Json outcome_json(const StrategyOutcome& o) {
  const simulate::StrategyScore& c = o.score;
  return Json{{"strategy", static_cast<int>(o.strategy)},
              {"metrics", o.metrics},
              {"score",
               {c.slot, c.ra_median_um, c.ra_p90_um, c.uncut_area_mm2, c.surface_area_mm2, c.max_gouge_mm, c.time_min}},
              {"ra_share", o.ra_share}};
}

StrategyOutcome outcome_from_json(const Json& j) {
  StrategyOutcome o;
  o.strategy = static_cast<finish::Strategy>(j.at("strategy").get<int>());
  o.metrics = j.at("metrics");
  const Json& c = j.at("score");
  o.score = {c.at(0).get<int>(),    c.at(1).get<double>(), c.at(2).get<double>(), c.at(3).get<double>(),
             c.at(4).get<double>(), c.at(5).get<double>(), c.at(6).get<double>()};
  o.ra_share = j.at("ra_share").get<std::vector<double>>();
  return o;
}
}  // namespace

Registered register_finish(CLI::App& app) {
  struct Opts {
    Common common;
    MeshFlags mesh_flags;
    std::vector<std::string> meshes;
    std::optional<std::string> strategy, tool, material;
    std::optional<double> stepover, step_down, boundary_angle, scallop;
    bool simulate = false;
    std::string out;
  };
  auto o = std::make_shared<Opts>();
  auto parse_strategy_flag = [](const std::string& v) {
    try {
      return finish::parse_strategy(v);
    } catch (const Error&) {
      throw Error("--strategy: unknown finishing strategy '" + v + "' (expected 1, 2, 3, 4, 5 or all)");
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
  sub->add_option("--stepover", o->stepover, "p_f, mm")->check(schema_range("/finish/stepover_mm"));
  sub->add_option("--step-down", o->step_down, "a_a, mm")->check(schema_range("/finish/step_down_mm"));
  sub->add_option("--boundary-angle", o->boundary_angle, "slope-mode boundary angle, degrees")
      ->check(schema_range("/finish/boundary_angle_deg"));
  sub->add_option("--scallop", o->scallop, "scallop-height target, mm")->check(schema_range("/finish/scallop_mm"));
  sub->add_flag("--simulate", o->simulate, "machine each program on a z-map and score the surface");
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common);
  return {sub, [o, parse_strategy_flag]() {
            const Json config = setup(o->common);
            FinishSettings s = finish_settings(config, {o->tool, o->material});
            if (o->strategy) {
              s.strategies =
                  *o->strategy == "all" ? finish::all_strategies() : std::vector{parse_strategy_flag(*o->strategy)};
            }
            if (o->stepover) s.params.stepover_mm = *o->stepover;
            if (o->step_down) s.params.step_down_mm = *o->step_down;
            if (o->boundary_angle) s.params.boundary_angle_deg = *o->boundary_angle;
            if (o->scallop) s.params.scallop_mm = *o->scallop;
            s.simulate = o->simulate;
            s.params.check();
            std::vector<std::string> items = config["finish"]["meshes"].get<std::vector<std::string>>();
            items.insert(items.end(), o->meshes.begin(), o->meshes.end());
            if (items.empty()) throw Error("no mesh to finish: give --mesh FILE or set /finish/meshes in the config");
            const auto files = expand_inputs(items, ingest::mesh_extensions());
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"], &config);
            std::size_t failed = 0;
            if (cluster_size() > 1) {
              // MPI: work unit = part × strategy (unit u: part u / S, strategy u % S), so a library
              // of fewer parts than ranks still keeps every rank busy. Rank 0 writes each unit's
              // files as it is delivered (in unit order) and a part's ranking files after its last
              // strategy: the bytes of the one-process run.
              const std::size_t S = s.strategies.size();
              const auto work = [&](std::size_t u) {
                const fs::path& f = files[u / S];
                StrategyOutcome outcome;
                std::string files_of_unit = write_and_pack([&](const std::string& scratch) {
                  outcome = finish_strategy(load_part(f, prep), f.stem().string(), s, s.strategies[u % S], scratch,
                                            cad_metrics(f));
                });
                const std::vector<std::uint8_t> cbor = Json::to_cbor(outcome_json(outcome));
                std::string msg;
                put_bytes(msg, std::string(cbor.begin(), cbor.end()));
                put_bytes(msg, files_of_unit);
                return msg;
              };
              std::vector<StrategyOutcome> part_outcomes;
              std::optional<std::string> part_error;
              const auto take = [&](std::size_t u, bool ok, std::string&& bytes) {
                const fs::path& f = files[u / S];
                if (u % S == 0) {
                  part_outcomes.clear();
                  part_error.reset();
                }
                if (!ok) {
                  if (!part_error) part_error = bytes;
                } else if (!part_error) {
                  std::size_t pos = 0;
                  const std::string cbor = get_bytes(bytes, pos);
                  part_outcomes.push_back(outcome_from_json(Json::from_cbor(cbor)));
                  unpack_files(get_bytes(bytes, pos), o->out);
                }
                if (u % S != S - 1) return;
                if (part_error) {  // the part's first failure, once, as the one-process run reports it
                  if (files.size() == 1) throw Error(*part_error);
                  warn(f.string() + ": " + *part_error);
                  ++failed;
                  return;
                }
                write_strategy_ranking(f.stem().string(), s, part_outcomes, o->out);
                info("finish: " + f.string() + ": " + std::to_string(part_outcomes.size()) + " strategies → " + o->out);
              };
              const DistributeStats st = distribute(files.size() * S, work, take, false, "finish: parts × strategies");
              if (!cluster_root()) return 0;
              log_distribution("finish", st);
              if (failed > 0)
                throw Error(std::to_string(failed) + " of " + std::to_string(files.size()) + " parts failed");
              return 0;
            }
            for (const auto& f : files) {  // a batch keeps going past one bad part
              try {
                OutputSet part;  // this part's files complete, or none of them (core/output_set.hpp)
                const auto outcomes = finish_part(load_part(f, prep), f.stem().string(), s, o->out, cad_metrics(f));
                part.commit();
                info("finish: " + f.string() + ": " + std::to_string(outcomes.size()) + " strategies → " + o->out);
              } catch (const Error& e) {
                if (files.size() == 1) throw;
                warn(f.string() + ": " + e.what());
                ++failed;
              }
            }
            if (failed > 0)
              throw Error(std::to_string(failed) + " of " + std::to_string(files.size()) + " parts failed");
            return 0;
          }};
}

Registered register_simulate(CLI::App& app) {
  struct Opts {
    Common common;
    MeshFlags mesh_flags;
    std::vector<std::string> gcode, tools;
    std::string mesh, stock = "flat", out;
    bool save_stock = false;
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
  o->mesh_flags.add_to(sub);
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common);
  return {sub, [o]() {
            const Json config = setup(o->common);
            const FinishSettings s = finish_settings(config);
            if (o->tools.size() != 1 && o->tools.size() != o->gcode.size())
              throw Error("give one --tool for all programs or one per --gcode (" + std::to_string(o->gcode.size()) +
                          " programs, " + std::to_string(o->tools.size()) + " tools)");
            std::vector<std::pair<fs::path, finish::Cutter>> programs;
            for (std::size_t i = 0; i < o->gcode.size(); ++i) {
              // Bounds, a move, and the chords its arcs become, before the part is read (issue 42).
              (void)gcode::read_checked(read_file(o->gcode[i]), o->gcode[i], work_limits());
              programs.emplace_back(o->gcode[i], tool_arg(o->tools[o->tools.size() == 1 ? 0 : i], config));
            }
            const ingest::PrepareOptions prep = o->mesh_flags.prepare(&config["rough"], &config);
            const Json j = simulate_files(load_part(o->mesh, prep), fs::path(o->mesh).stem().string(), programs,
                                          o->stock, s, o->out, o->save_stock);
            info("simulate: Ra median " + j["ra_median_um"].dump() + " um, gouge " + j["max_gouge_mm"].dump() +
                 " mm → " + o->out);
            return 0;
          }};
}

}  // namespace millnet::app
