// millnet job --mesh FILE [--config FILE] [--post linuxcnc|grbl|fanuc] [--strategy K|best] --out DIR
// One program for a part (issue 40 §2–3): drilling where the roughing pre-drills, roughing, then the
// chosen finishing strategy, each operation with its tool change, in one work offset; the same
// operations as programs of their own; the job machined from the block; the setup sheet.
#include "cli.hpp"
#include "finish_job.hpp"
#include "job_rest.hpp"
#include "job_semi.hpp"
#include "job_stock.hpp"
#include "run_job.hpp"
#include "settings.hpp"
#include "text.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/sha256.hpp"
#include "millnet/job/chain.hpp"
#include "millnet/job/links.hpp"
#include "millnet/job/operations.hpp"
#include "millnet/job/tool_choice.hpp"
#include "millnet/report/setup_sheet.hpp"
#include "millnet/tooling/io/tool_tables.hpp"

#include <algorithm>
#include <variant>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct JobOpts {
  Common common;
  MeshFlags mesh_flags;
  std::string mesh, out, strategy = "best";
  std::optional<std::string> post, finish_tool, rough_tool, material, rest_tool, stock;
  BoundaryFlags boundary;       ///< the finishing's (and semi-finishing's) machining boundary
  bool keep_deep_cuts = false;  ///< write a job whose cut goes beyond a tool's flutes (warned), as before 2026-11-27
};

/// Removes the operation programs an earlier job of this part left in `out` that this one does not
/// write (<stem>.op<N>.<name>.nc: an operation it no longer has, or numbered otherwise), so that no
/// stale program stands beside the job's — its tool may not even be in the new tool table. Other
/// files are left alone. O(files in the folder).
void remove_stale_programs(const fs::path& out, const std::string& stem, const std::vector<std::string>& written) {
  const std::string prefix = stem + ".op";
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(out, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.size() <= prefix.size() + 3 || name.rfind(prefix, 0) != 0 ||
        !name.ends_with(".nc") || std::find(written.begin(), written.end(), name) != written.end())
      continue;
    const std::size_t dot = name.find('.', prefix.size());
    const std::string number = name.substr(prefix.size(), dot == std::string::npos ? 0 : dot - prefix.size());
    if (number.empty() || !std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    if (fs::remove(e.path(), ec)) info("job: " + stem + ": removed " + name + ", a program of an earlier job");
  }
}

/// A tool as the job runs it: the configured one, or the library's one of the same kind that reaches
/// (job::tool_that_reaches); `note` says which and why.
tooling::Tool reaching(const ToolLibrary& lib, const tooling::Tool& configured, double depth_mm,
                       const std::string& what, const std::string& file, std::vector<std::string>& notes) {
  const tooling::Tool* t = job::tool_that_reaches(lib.tools, configured, depth_mm);
  if (t == nullptr)
    throw Error(file + ": the " + what + " tool " + configured.label() + " sticks out " +
                fixed(configured.stickout_mm, 1) + " mm, the part reaches " + fixed(depth_mm, 1) +
                " mm below the stock top, and no tool of its kind in the library reaches that deep: add one "
                "(/cutting/tools_file) or choose another tool");
  if (t->id != configured.id)
    notes.push_back("the " + what + " tool " + configured.id + " (stick-out " + fixed(configured.stickout_mm, 1) +
                    " mm) cannot reach " + fixed(depth_mm, 1) + " mm below the stock top: " + t->id + " (stick-out " +
                    fixed(t->stickout_mm, 1) + " mm) runs it instead");
  return *t;
}

/// The finishing strategy of the job: `choice` "best" = the simulated ranking's first (under the
/// aim, which puts first a strategy that meets the spec without a gouge), else the slot given.
job::StrategyOutcome chosen_strategy(const std::vector<job::StrategyOutcome>& outcomes, const std::string& file) {
  auto best = std::min_element(outcomes.begin(), outcomes.end(), [](const auto& a, const auto& b) {
    return (a.rank > 0 ? a.rank : 1 << 20) < (b.rank > 0 ? b.rank : 1 << 20);
  });
  if (best == outcomes.end()) throw Error(file + ": no finishing strategy was planned");
  if (best->simulated && best->surface.gouged)
    throw Error(file + ": the finishing strategy s" + std::to_string(static_cast<int>(best->strategy)) +
                " gouges the part (" + fixed(best->surface.max_gouge_mm, 3) + " mm): no job is written");
  return *best;
}

/// The cutting data of the drilling: the drill's own speed and feed in the material.
job::DrillCut drill_cut(const tooling::Tool& drill, const Json& config, const std::optional<std::string>& material,
                        double depth_mm) {
  const CuttingSettings cs = cutting_settings(config, material);
  const ToolLibrary lib = tool_library(config);
  const tooling::CuttingData d = tooling::cutting_data(drill, lib.material(cs.material_id, cs.material_from),
                                                       std::max(depth_mm, 0.1), cs.machine, cs.factors);
  return {d.rpm, d.feed_plunge_mm_min};
}

/// A tool named on the command line: a library id, or inline (ball:D, flat:D, bull:D:r) with the
/// reach of the library's tool of its shape.
tooling::Tool job_tool(const std::string& text, const Json& config, const std::optional<std::string>& material,
                       const ToolLibrary& lib) {
  if (text.find(':') == std::string::npos) return lib.tool(text, "--rest-tool (or /finish/rest/tool)");
  const tooling::Cutter c = parse_tool(text);
  return inline_tool(c.type, c.diameter, c.corner_radius, cutting_settings(config, material), lib);
}

report::SetupTool setup_tool(const tooling::Tool& t) {
  report::SetupTool s;
  s.number = t.number;
  s.length_offset = t.length_offset_register();
  s.id = t.id;
  s.description = t.description.empty() ? t.label() : t.description;
  s.type = tooling::to_string(t.type);
  s.diameter_mm = t.diameter_mm;
  s.corner_radius_mm = t.corner_radius_mm;
  s.stickout_mm = t.stickout_mm;
  s.holder_diameter_mm = t.holder_diameter_mm;
  s.holder_length_mm = t.holder_length_mm;
  return s;
}

std::string share_text(double share) { return std::isnan(share) ? "–" : fixed(100 * share, 2) + " %"; }

/// The machine's depth-of-cut limit (/machine/max_depth_of_cut_mm, issue 38; 0: none): a milling
/// tool of the job takes at most that at once — its flute length, as every check of the job reads
/// it, capped (a drill's flutes stay: drilling is no depth of cut).
tooling::Tool within_machine(tooling::Tool t, double max_cut) {
  if (max_cut > 0 && t.type != tooling::ToolType::Drill)
    t.flute_length_mm = t.flute_length_mm > 0 ? std::min(t.flute_length_mm, max_cut) : max_cut;
  return t;
}

/// The job of `o` with `config` read; `reuse` (from `millnet run`): what is already computed.
int build_job(const JobOpts& o, const Json& config, const RunJobInput* reuse, RunJobResult* result) {
  // 1. Settings and the part.
  FinishSettings fs_ = finish_settings(config, {o.finish_tool, o.material});
  fs_.post = post_dialect(config, o.post);
  o.boundary.apply(fs_);
  fs_.simulate = true;
  fs_.strategies = o.strategy == "best" ? finish::all_strategies() : std::vector{finish::parse_strategy(o.strategy)};
  PocketFlags pflags;
  pflags.tool_id = o.rough_tool;
  pflags.material = o.material;
  CuttingRecord rough_cutting;
  rough::Params rp = rough_params(config, explicit_pocket_section(o.common.config), pflags, &rough_cutting);
  ToolLibrary lib = tool_library(config);
  const ingest::PrepareOptions prep = o.mesh_flags.prepare(&config["rough"], &config);
  job::Part part = reuse != nullptr ? *reuse->part : load_part(o.mesh, prep);
  const std::string stem = part.name, file = o.mesh;
  const fs::path out = o.out;
  const job::Frame frame = job::frame_of(part.mesh, rp.top_allowance_mm);
  std::vector<std::string> notes;
  const Json& max_cut_key = config["machine"]["max_depth_of_cut_mm"];
  const double max_cut = max_cut_key.is_null() ? 0.0 : max_cut_key.get<double>();
  if (max_cut > 0) {  // the machine's limit: every milling tool's flutes read as at most it
    for (tooling::Tool& t : lib.tools) t = within_machine(t, max_cut);
    notes.push_back("the machine takes at most " + fixed(max_cut, 2) +
                    " mm at once (/machine/max_depth_of_cut_mm): each milling tool's flute length is read as at "
                    "most that" +
                    (rp.cut.step_down > max_cut ? ", and the roughing steps down " + fixed(max_cut, 2) +
                                                      " mm instead of " + fixed(rp.cut.step_down, 2)
                                                : std::string()));
  }
  const bool step_capped = max_cut > 0 && rp.cut.step_down > max_cut;
  if (step_capped) rp.cut.step_down = max_cut;

  // 2. Tools that reach what they machine (never a silent deeper cut): the roughing its last level
  // over the part's base, the finishing (and the semi-finishing and rest after it) the lowest face
  // it machines: inside the part's silhouette or a boundary that is the lowest face facing up, not
  // the outside walls below it (issue 38: a 27 mm cavity was refused for walls going to 42 mm).
  const double depth = frame.depth_below_top(frame.part_bottom);
  const tooling::Tool mill = within_machine(
      reaching(lib, rough_cutting.tool, depth - rp.floor_allowance_mm, "roughing", file, notes), max_cut);
  rp.cut.tool = mill.cutter();
  std::string why;
  fs_ = for_part(fs_, part, &why);  // the part's ball when no finishing tool is named
  if (!why.empty()) notes.push_back(why);
  const finish::Boundary& fb = fs_.params.boundary;
  const double finish_depth = fb.on_part || !fb.polygons.empty()
                                  ? std::min(depth, job::part_shape(part.mesh, frame.stock_top).depth_mm)
                                  : depth;
  const tooling::Tool ball =
      within_machine(reaching(lib, fs_.cutting.tool, finish_depth, "finishing", file, notes), max_cut);
  fs_.cutting.tool = ball;
  fs_.params.tool = ball.cutter();
  const job::SimParams sim = sim_params(fs_);

  // A given stock is read once, checked before the minutes of roughing, planning and simulation it
  // would feed (refused naming its file and the place), and the roughing plans from it; a sawn
  // blank (/rough/stock_squared false) is the block with its top faced first (job_stock.hpp).
  const double blank_top = sawn_blank_top(config, rp, o.stock);
  const StockSource stock_src{o.mesh, prep, frame};
  const std::optional<GivenStock> given = read_stock(o.stock, stock_src);
  const GivenStock* const given_stock = given ? &*given : nullptr;
  rp.stock_top = roughing_stock(given_stock, stock_src, part.mesh, rp, sim);

  OutputSet files;  // every file of the job, or none (core/output_set.hpp)
  fs::create_directories(out);
  // 3. Roughing, and the drilling its pre-drilled entries need.
  info("job: " + stem + ": roughing with " + mill.label());
  std::optional<rough::Result> own_rough;  // the run's roughing when it ran with this tool
  const bool reuse_rough =
      reuse != nullptr && reuse->rough != nullptr && mill.id == rough_cutting.tool.id && !step_capped;
  const rough::Result& rough = reuse_rough ? *reuse->rough : own_rough.emplace(rough::rough_mesh(part.mesh, rp));
  // From a given stock that holds nothing above any level (an earlier job's roughing), no roughing.
  const bool no_roughing = rp.stock_top && rough.machining.status == pocket::PlanStatus::NothingToCut;
  if (!no_roughing && rough.machining.status != pocket::PlanStatus::Ok)
    throw Error(file + ": roughing: " + rough.machining.message);
  if (no_roughing) notes.push_back("roughing: none, the stock holds no material above any roughing level");
  const tooling::Tool* drill = nullptr;
  job::DrillCut dc;
  if (!no_roughing && job::predrills(rough.machining.program)) {
    const double hole = -job::deepest_z(rough.machining.program);
    drill = job::drill_for(lib.tools, mill, hole);
    if (drill == nullptr)
      throw Error(file + ": the roughing pre-drills its entries " + fixed(hole, 1) + " mm deep and no drill of Ø" +
                  fixed(mill.diameter_mm / 2, 1) + "–" + fixed(mill.diameter_mm, 1) +
                  " mm in the tool library reaches that deep: add one (/cutting/tools_file) or set /pocket/entry to "
                  "helix or ramp");
    dc = drill_cut(*drill, config, o.material, hole);
  }
  std::vector<job::Operation> ops =
      no_roughing ? std::vector<job::Operation>{} : job::roughing_operations(rough.machining.program, mill, drill, dc);
  const job::FacingSpec facing = facing_spec(rough, rp, mill, blank_top);
  if (blank_top > 0) ops.insert(ops.begin(), job::facing_operation(mill, facing));

  // 4. Finishing: the strategies machined and ranked (their files in DIR/strategies), the chosen one's program.
  info("job: " + stem + ": finishing with " + ball.label() + " (" + std::to_string(fs_.strategies.size()) + " strateg" +
       (fs_.strategies.size() == 1 ? "y" : "ies") + " simulated)");
  const fs::path strategies_dir = reuse != nullptr ? reuse->strategies_dir : out / "strategies";
  std::optional<PartFinish> own_finish;
  const PartFinish& pf =
      reuse != nullptr ? *reuse->finished : own_finish.emplace(finish_part(part, fs_, strategies_dir));
  // The finishing was planned over the design + its allowance; in the job it meets what the drilling
  // and roughing leave: its rapids are lifted over that stock (issue 38), and where its flutes would
  // not take what it meets a semi-finishing goes first; a strategy whose cut goes beyond its flutes
  // even then gives way to the next of the ranking (--strategy K: K, or no job).
  const job::Design& design = *pf.design;
  simulate::ZMap roughed = starting_stock(given_stock, stock_src, design, sim, blank_top);
  std::vector<job::StepResult> before = job::machine_steps(roughed, design, job::chain_steps(ops), fs_.machine);
  const job::StepResult met =
      before.empty() ? job::left_above(roughed, design) : before.back();  // what finishing meets
  const bool by_rank = o.strategy == "best";
  std::vector<job::StrategyOutcome> candidates{chosen_strategy(pf.outcomes, file)};
  if (by_rank) candidates = job::ranked_clean(pf.outcomes, candidates.front());
  std::optional<SemiFinish> semi;  // planned once, when a strategy first needs it
  std::optional<simulate::ZMap> semi_stock;
  job::StepResult semi_result;
  std::string semi_error, passed_over;
  job::StrategyOutcome pick = candidates.front();
  gcode::Program finish_program;
  job::LinkChanges links;
  double finish_cut = 0;
  gcode::Point3 finish_cut_at{};
  bool use_semi = false;
  for (std::size_t c = 0; c < candidates.size(); ++c) {  // O(strategies × simulation)
    const job::StrategyOutcome& cand = candidates[c];
    const fs::path nc =
        strategies_dir / program_file_name(stem + ".s" + std::to_string(static_cast<int>(cand.strategy)), cand);
    const ChainProgram read = read_chain_program(nc, ball.cutter(), frame.post(fs_.post));
    job::LinkChanges l;
    gcode::Program program = job::clear_rapids(read.written.program, roughed, ball.cutter(), fs_.params.clearance_mm,
                                               fs_.params.plunge_feed_mm_min, &l);
    // Whether the finishing tool's flutes take what it meets: its axial engagement on a copy of the
    // stock. The stock's height over the design is only a bound (at the foot of a steep wall it is
    // the wall's height, which a pass down the wall takes a little at a time).
    const auto engagement = [&](const simulate::ZMap& stock) {
      simulate::ZMap trial = stock;
      return job::machine_steps(trial, design, {{&program, ball.cutter()}}, fs_.machine).front();
    };
    const bool last = c + 1 == candidates.size();
    double cut = 0;
    gcode::Point3 at{};
    if (ball.flute_length_mm > 0 && met.max_left_mm > ball.flute_length_mm) {
      const job::StepResult st = engagement(roughed);
      cut = st.max_depth_of_cut_mm, at = st.max_cut_at;
    }
    bool needs_semi = cut > ball.flute_length_mm;
    if (needs_semi) {
      info("job: " + stem + ": s" + std::to_string(static_cast<int>(cand.strategy)) + " would cut " + fixed(cut, 2) +
           " mm deep (at X" + fixed(at[0], 2) + " Y" + fixed(at[1], 2) + " Z" + fixed(at[2], 2) + "), more than the " +
           fixed(ball.flute_length_mm, 1) + " mm flutes of " + ball.label() + ": semi-finishing");
      if (!semi && semi_error.empty()) {
        try {
          semi = semi_finishing_that_fits({part, pf, fs_, ball, mill, met, finish_depth}, roughed, design, fs_, config,
                                          o.material, lib, file, cut);
          semi_stock = roughed;
          semi_result =
              job::machine_steps(*semi_stock, design, {{&semi->op.program, semi->op.tool.cutter()}}, fs_.machine)
                  .front();
        } catch (const Error& e) {
          semi_error = e.what();
        }
      }
      if (!semi && (!by_rank || last)) throw Error(semi_error);
      const double after = semi ? engagement(*semi_stock).max_depth_of_cut_mm : cut;
      if (after > ball.flute_length_mm && by_rank && !last) {
        passed_over += (passed_over.empty() ? "" : "; ") + std::string("s") +
                       std::to_string(static_cast<int>(cand.strategy)) + " would cut " + fixed(after, 2) + " mm deep" +
                       (semi ? " even after the semi-finishing" : "");
        continue;
      }
    }
    pick = cand, finish_program = std::move(program), links = l, finish_cut = cut, finish_cut_at = at;
    use_semi = needs_semi;
    break;
  }
  if (!passed_over.empty())
    notes.push_back("the ranking's first strategies would cut beyond the " + fixed(ball.flute_length_mm, 1) +
                    " mm flutes of " + ball.label() + " (" + passed_over + "): the job finishes with s" +
                    std::to_string(static_cast<int>(pick.strategy)) + ", the first a machine survives");
  const int slot = static_cast<int>(pick.strategy);
  const std::string strategy_name = "s" + finish::strategy_name(pick.strategy);  // "s3 profile finishing, …"
  std::optional<finish::FinishParams> semi_params;
  if (use_semi) {
    semi_params = semi->params;
    notes.push_back("the finishing would cut " + fixed(finish_cut, 2) + " mm deep (at X" + fixed(finish_cut_at[0], 1) +
                    " Y" + fixed(finish_cut_at[1], 1) + " Z" + fixed(finish_cut_at[2], 1) +
                    ") into what the roughing leaves, more than the " + fixed(ball.flute_length_mm, 1) +
                    " mm flutes of " + ball.label() + " take: " + semi->op.tool.label() + " semi-finishes first");
    ops.push_back(std::move(semi->op));
    roughed = std::move(*semi_stock);
    before.push_back(semi_result);
  }
  ops.push_back({"finishing (" + strategy_name + ")", ball, std::move(finish_program)});
  if (links.raised + links.fed > 0)
    notes.push_back("finishing: " + std::to_string(links.raised) + " links lifted over the stock left before it (" +
                    fixed(met.max_left_mm, 2) + " mm above the design at most, at X" + fixed(met.max_left_at[0], 1) +
                    " Y" + fixed(met.max_left_at[1], 1) + "), " + std::to_string(links.fed) +
                    " approaches finished at the plunge feed");
  // 4b. Rest finishing (issue 41): a smaller tool where the finishing leaves rest, its own operation.
  const std::string rest_id = o.rest_tool.value_or(config["finish"]["rest"]["tool"].get<std::string>());
  RestCut rest_cut;  // the rest tool's cutting data (its operation's sheet entry)
  if (!rest_id.empty()) {
    const tooling::Tool rest = job_tool(rest_id, config, o.material, lib);
    if (!(rest.diameter_mm < ball.diameter_mm))
      throw Error(file + ": the rest tool " + rest.label() + " is not smaller than the finishing tool " + ball.label());
    (void)job::machine_steps(roughed, design, {job::chain_steps(ops).back()},
                             fs_.machine);  // what the finishing leaves
    const CuttingSettings cs = cutting_settings(config, o.material);
    const tooling::CuttingData d =
        tooling::cutting_data(rest, lib.material(cs.material_id, cs.material_from),
                              config["simulate"]["allowance_mm"].get<double>(), cs.machine, cs.factors);
    const finish::FinishParams rest_params = rest_finish_params(fs_, fs_.params, cutter_of(rest));
    rest_cut = {d.rpm, d.feed_mm_min, d.feed_plunge_mm_min, rest_params.stepover_mm, rest_params.step_down_mm};
    // /finish/rest/measure "programs": the rest read by the programs' exact approach, not the z-map.
    const bool exact = config["finish"]["rest"]["measure"].get<std::string>() == "programs";
    if (std::optional<job::Operation> op = rest_operation(
            part, fs_, roughed, design, exact ? job::chain_steps(ops) : std::vector<job::ChainStep>{}, rest, rest_cut,
            config["finish"]["rest"]["min_area_mm2"].get<double>(), o.keep_deep_cuts, stem, notes))
      ops.push_back(std::move(*op));
  }
  if (!pick.meets_spec && pf.outcomes.size() > 1)
    notes.push_back("no strategy meets the surface specification; the job finishes with the best of them");
  ops = job::numbered(std::move(ops));

  // 5. The job program and one program per operation.
  std::vector<std::string> header{
      "millnet job: " + stem, "part " + fs::path(file).filename().string(), frame.header(),
      "work offset G54: X0 Y0 = the " + gcode::to_string(fs_.post.origin_at) + ", Z0 = stock top"};
  if (blank_top > 0)
    header.push_back("sawn blank: its top at Z" + fixed(blank_top, 3) +
                     ", faced to Z0 by operation 1: touch off on the blank's top and set Z" + fixed(blank_top, 3));
  for (const job::Operation& op : ops) header.push_back("T" + std::to_string(op.tool.number) + " " + op.tool.label());
  const fs::path job_nc = out / (stem + ".job.nc");
  const gcode::Dialect post = frame.post(fs_.post);  // the work origin on this part's stock
  const gcode::Written job_w = gcode::write_program(job_nc, job::job_program(ops, header), post);
  std::vector<report::SetupFile> program_files{{job_nc.filename().string(), sha256_hex(job_w.text), job_w.text.size()}};
  std::vector<std::string> op_files;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    std::string name = ops[i].name.substr(0, ops[i].name.find(' '));
    const fs::path p = out / (stem + ".op" + std::to_string(i + 1) + "." + name + ".nc");
    const gcode::Written w = gcode::write_program(
        p,
        job::operation_program(ops[i], {"millnet job: " + stem + ", operation " + std::to_string(i + 1) + " of " +
                                            std::to_string(ops.size()) + ": " + ops[i].name,
                                        frame.header()}),
        post);
    op_files.push_back(p.filename().string());
    program_files.push_back({p.filename().string(), sha256_hex(w.text), w.text.size()});
  }
  remove_stale_programs(out, stem, op_files);

  // The job's tools as a LinuxCNC tool table (what the control loads before the job runs).
  const std::vector<tooling::Tool> job_tools = job::tools_of(ops);
  const fs::path tbl = out / (stem + ".tool.tbl");
  const std::string tbl_text = tooling::io::linuxcnc_tool_table(job_tools).text;
  write_file_atomic(tbl, tbl_text);
  program_files.push_back({tbl.filename().string(), sha256_hex(tbl_text), tbl_text.size()});

  // 6. The job program machined from the block, tool by tool, on one z-map.
  info("job: " + stem + ": machining the job program from the block");
  simulate::ZMap z = starting_stock(given_stock, stock_src, design, sim, blank_top);
  const std::vector<job::ToolRun> runs = job::split_at_tool_changes(job_w.program);
  std::map<int, const job::Operation*> by_number;
  for (const job::Operation& op : ops) by_number[op.tool.number] = &op;
  std::vector<job::ChainStep> steps;
  for (const job::ToolRun& r : runs) {
    const auto it = by_number.find(r.tool_number);
    if (it == by_number.end()) continue;  // only comments before the first tool change
    steps.push_back({&r.program, it->second->tool.cutter()});
  }
  if (steps.size() != ops.size())
    throw Error(job_nc.string() + ": read back with " + std::to_string(steps.size()) + " tool changes, written with " +
                std::to_string(ops.size()));
  // A rest operation last: the chain measures the rest before and after it (issue 41), split by
  // what each tool reaches (job::split_rest, exact from the mesh), as `millnet simulate` does.
  const bool rest_last = ops.back().name.rfind("rest finishing", 0) == 0;
  const job::ChainResult chain = job::machine_chain(z, design, steps, fs_.machine, sim, rest_last);
  std::optional<job::RestSplit> rest_split;
  if (chain.rest_step)
    rest_split = job::split_rest(part.mesh, design, z, chain, steps, ops.back().tool.cutter(), sim.rest_threshold_mm,
                                 ops.back().tool.cutter().reach_mm > 0 ? -ops.back().tool.cutter().reach_mm
                                                                       : -std::numeric_limits<double>::infinity(),
                                 frame.z_shift());

  // 7. The setup sheet's tools (reach and holder clearance over the part) and operations.
  report::SetupSheet sheet;
  sheet.title = stem + " — setup sheet";
  sheet.part_file = file;
  sheet.post = fs_.post.name;
  sheet.material = fs_.cutting.material_id;
  sheet.stock_x0 = rough.stock_x0, sheet.stock_y0 = rough.stock_y0;
  sheet.stock_x1 = rough.stock_x1, sheet.stock_y1 = rough.stock_y1;
  sheet.stock_bottom_z = frame.program_bottom();
  sheet.blank_top_z = blank_top;
  sheet.origin_x = post.origin[0], sheet.origin_y = post.origin[1];
  sheet.origin_name = gcode::to_string(post.origin_at);
  sheet.part_width = frame.width, sheet.part_depth = frame.depth;
  sheet.part_top_z = frame.part_top - frame.stock_top, sheet.part_bottom_z = frame.program_bottom();
  sheet.grid = design.grid;
  sheet.heights = &design.heights;
  std::map<int, report::SetupTool> tools;
  Json ops_json = Json::array();
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const job::Operation& op = ops[i];
    const job::HolderClearance hc = job::holder_clearance(*steps[i].program, op.tool, design.grid, design.heights);
    report::SetupTool& t = tools.try_emplace(op.tool.number, setup_tool(op.tool)).first->second;
    t.reach_needed_mm = std::max(t.reach_needed_mm, hc.reach_needed_mm);
    t.holder_checked = hc.checked;
    t.holder_clearance_mm = op.tool.stickout_mm - t.reach_needed_mm;
    if (hc.checked && hc.min_clearance_mm < 0)
      warn(file + ": operation " + std::to_string(i + 1) + " (" + op.name + "): the holder of " + op.tool.label() +
           " comes " + fixed(-hc.min_clearance_mm, 2) + " mm into the part at X" + fixed(hc.worst[0], 2) + " Y" +
           fixed(hc.worst[1], 2) + " Z" + fixed(hc.worst[2], 2) + ": a longer tool is needed");
    const job::StepResult& st = chain.steps[i];
    if (op.tool.flute_length_mm > 0 && st.max_depth_of_cut_mm > op.tool.flute_length_mm) {
      // What the operations before it left is more than this tool's flutes take (issue 38): a tool
      // breaks there, so no job is written (--keep-deep-cuts: written, with the warning).
      const std::string line =
          "operation " + std::to_string(i + 1) + " (" + op.name + ") cuts " + fixed(st.max_depth_of_cut_mm, 2) +
          " mm deep at X" + fixed(st.max_cut_at[0], 2) + " Y" + fixed(st.max_cut_at[1], 2) + " Z" +
          fixed(st.max_cut_at[2], 2) + " (" + job_nc.filename().string() + " line " + std::to_string(st.max_cut_line) +
          "), beyond the " + fixed(op.tool.flute_length_mm, 1) + " mm flutes of " + op.tool.label() +
          ": the stock left before it needs another pass (a smaller semi-finishing ball that reaches, or rest "
          "machining)";
      if (!o.keep_deep_cuts) throw Error(file + ": " + line + "; no job is written (--keep-deep-cuts writes it)");
      warn(file + ": " + line);
      notes.push_back(line);
    }
    report::SetupOperation so;
    so.index = static_cast<int>(i + 1);
    so.name = op.name;
    so.tool_number = op.tool.number;
    so.deepest_z_mm = hc.deepest_tip_z;
    so.max_depth_of_cut_mm = st.max_depth_of_cut_mm;
    so.beyond_flutes = op.tool.flute_length_mm > 0 && st.max_depth_of_cut_mm > op.tool.flute_length_mm;
    so.cutting_rapids = st.cutting_rapids;
    so.left_after_mm = st.max_left_mm;
    so.time_min = st.stats.kinematic_time_min;
    so.program = op_files[i];
    if (op.name == "facing") {
      so.strategy = "facing the sawn top: zigzag passes along the longer side";
      so.rpm = rp.cut.spindle_rpm, so.feed_mm_min = rp.cut.feed_half;
      so.stepover_mm = facing.stepover_mm, so.step_down_mm = facing.max_depth_mm;
    } else if (op.name == "drilling") {
      so.strategy = "plunge per pre-drilled entry";
      so.rpm = dc.rpm, so.feed_mm_min = dc.feed_mm_min;
    } else if (op.name.rfind("semi-finishing", 0) == 0 && semi_params) {
      so.strategy = "s1 slope mode over the design + " + format_double(sim.allowance_mm) + " mm";
      so.rpm = semi_params->spindle_rpm, so.feed_mm_min = semi_params->feed_mm_min;
      so.stepover_mm = semi_params->stepover_mm, so.step_down_mm = semi_params->step_down_mm;
    } else if (op.name.rfind("rest finishing", 0) == 0) {  // job_rest_program's passes and cutting data
      so.strategy = "rest finishing: pencil passes, then s1 slope mode in the rest regions";
      so.rpm = rest_cut.rpm, so.feed_mm_min = rest_cut.feed_mm_min;
      so.stepover_mm = rest_cut.stepover_mm, so.step_down_mm = rest_cut.step_down_mm;
    } else if (op.name == "roughing") {  // the roughing's own cutting data
      so.strategy = "Z-level roughing";
      so.rpm = rp.cut.spindle_rpm, so.feed_mm_min = rp.cut.feed_half;
      so.stepover_mm = rp.cut.stepover, so.step_down_mm = rp.cut.step_down;
    } else {
      so.strategy = strategy_name;
      so.rpm = fs_.params.spindle_rpm,
      so.feed_mm_min = pick.feed_mm_min > 0 ? pick.feed_mm_min : fs_.params.feed_mm_min;
      so.stepover_mm = pick.stepover_mm, so.step_down_mm = pick.step_down_mm;
    }
    sheet.deepest_z = std::min(sheet.deepest_z, hc.deepest_tip_z);
    sheet.total_time_min += so.time_min;
    sheet.operations.push_back(so);
    ops_json.push_back(Json{
        {"operation", so.index},
        {"name", op.name},
        {"strategy", so.strategy},
        {"tool", Json{{"number", op.tool.number},
                      {"length_offset", op.tool.length_offset_register()},
                      {"id", op.tool.id},
                      {"label", op.tool.label()}}},
        {"spindle_rpm", so.rpm},
        {"feed_mm_min", so.feed_mm_min},
        {"stepover_mm", so.stepover_mm},
        {"step_down_mm", so.step_down_mm},
        {"deepest_z_mm", so.deepest_z_mm},
        {"reach_needed_mm", hc.reach_needed_mm},
        {"holder_checked", hc.checked},
        {"holder_clearance_mm", hc.checked ? Json(hc.min_clearance_mm) : Json(nullptr)},
        {"time_kinematic_min", so.time_min},
        {"time_feed_min", st.stats.feed_time_min},
        {"max_depth_of_cut_mm", st.max_depth_of_cut_mm},
        {"cutting_rapids", st.cutting_rapids},
        {"air_cut_share", st.air_cut_share()},
        {"feed_outside_zmap_mm", st.outside_feed_mm},
        {"air_run_share", st.air_run_share()},
        {"max_depth_of_cut_at",
         Json{{"line", st.max_cut_line}, {"x", st.max_cut_at[0]}, {"y", st.max_cut_at[1]}, {"z", st.max_cut_at[2]}}},
        {"left_above_design_mm", st.max_left_mm},
        {"left_above_design_at", {st.max_left_at[0], st.max_left_at[1]}},
        {"program", op_files[i]}});
    if (const auto& g = chain.metrics.pass_max_gouge_mm; g.size() >= ops.size())  // its own passes are the last
      ops_json.back()["max_gouge_mm"] = g[g.size() - ops.size() + i];
    if (rest_split && i + 1 == ops.size()) {  // the rest operation's figures (as simulate reports them)
      Json& j = ops_json.back();
      j["over_threshold_before_mm2"] = chain.rest_area_before_mm2;
      j["over_threshold_after_mm2"] = chain.rest_area_after_mm2;
      j["rest_area_before_mm2"] = rest_split->before_mm2;
      j["rest_area_after_mm2"] = rest_split->after_mm2;
      j["rest_area_unreachable_mm2"] = rest_split->unreachable_mm2;
      j["rest_area_missed_mm2"] = rest_split->missed_mm2;            // within the tool's reach
      j["rest_area_missed_zmap_mm2"] = rest_split->missed_zmap_mm2;  // before the programs' exact check
      j["rest_area_beyond_reach_mm2"] = rest_split->beyond_reach_mm2;
    }
  }
  for (auto& [n, t] : tools) sheet.tools.push_back(t);
  for (const std::string& n : notes)
    for (report::SetupTool& t : sheet.tools)
      if (n.find(" " + t.id + " (stick-out") != std::string::npos) t.note = n;

  // 8. The simulated result, job.json and the setup sheet.
  const simulate::SurfaceMetrics& m = chain.metrics;
  const double cell2 = design.grid.cell * design.grid.cell;
  sheet.result = {
      {"gouge",
       m.gouged ? "YES: " + fixed(m.max_gouge_mm, 3) + " mm at G-code line " + std::to_string(m.first_gouge_move.line)
                : "none (largest " + fixed(m.max_gouge_mm, 4) + " mm, within the tolerance)"},
      {"surface specification",
       m.spec_measured ? share_text(m.spec_share) + " of " + fixed(static_cast<double>(m.spec_cells) * cell2, 0) +
                             " mm² in spec (needs " + share_text(1 - fs_.spec.out_of_spec_share) + ")"
                       : "not measured"},
      {"left above the design (uncut)", fixed(m.uncut_area_mm2, 1) + " mm²"},
      {"rest material (corners tighter than the ball)", fixed(m.rest_area_mm2, 1) + " mm²"},
      {"largest scallop", fixed(m.scallop_max_mm * 1000, 1) + " µm"},
      {"Ra median / p90", fixed(m.ra_median_um, 2) + " / " + fixed(m.ra_p90_um, 2) + " µm"},
      {"finishing chosen", strategy_name + (o.strategy == "best" ? " (first of the simulated ranking, " +
                                                                       fs::relative(strategies_dir, out).string() +
                                                                       "/" + stem + ".strategies.md)"
                                                                 : " (--strategy)")}};
  sheet.files = program_files;
  sheet.tool_changes =
      static_cast<int>(std::count_if(job_w.program.items.begin(), job_w.program.items.end(), [](const gcode::Item& it) {
        return std::holds_alternative<gcode::ToolChange>(it);
      }));
  sheet.tool_change_s = config["machine"]["tool_change_s"].get<double>();
  notes.push_back("operation times are kinematic (the /machine motion model); the cycle time adds " +
                  std::to_string(sheet.tool_changes) + " tool changes × " + format_double(sheet.tool_change_s) +
                  " s (/machine/tool_change_s); the operator's setup is not counted");
  if (drill != nullptr)
    notes.push_back("the drill's tip goes to each hole's level; its point leaves a cone the end mill's plunge cuts");
  if (o.stock) notes.insert(notes.begin(), "the job starts from the stock " + *o.stock + ", not the block");
  if (blank_top > 0)
    notes.insert(notes.begin(), "a sawn blank (/rough/stock_squared false): operation 1 faces its top " +
                                    fixed(blank_top, 2) + " mm down to Z0 with the roughing's " + mill.label() +
                                    "; its sides stay as sawn");
  sheet.notes = notes;
  Json j{{"part", stem},
         {"file", file},
         {"post", fs_.post.name},
         {"frame",
          Json{{"origin", "X0 Y0 = " + gcode::to_string(post.origin_at) + ", Z0 = stock top (G54)"},
               {"origin_in_part_frame_mm", {post.origin[0], post.origin[1]}},
               {"stock_mm",
                {sheet.stock_x0, sheet.stock_y0, sheet.stock_bottom_z, sheet.stock_x1, sheet.stock_y1, blank_top}},
               {"blank_top_z_mm", blank_top},
               {"deepest_z_mm", sheet.deepest_z},
               {"stock_from", o.stock ? Json(*o.stock) : Json("block")}}},
         {"operations", ops_json},
         {"total_time_kinematic_min", sheet.total_time_min},
         {"tool_changes", sheet.tool_changes},
         {"tool_change_s", sheet.tool_change_s},
         {"tool_change_time_min", sheet.cycle_time_min() - sheet.total_time_min},
         {"total_time_min", sheet.cycle_time_min()},
         {"simulated", sim_metrics_json(m, design.grid)},
         {"strategy", Json{{"slot", slot}, {"name", finish::strategy_name(pick.strategy)}, {"chosen_by", o.strategy}}},
         {"notes", notes}};
  Json fj = Json::array();
  for (const report::SetupFile& f : program_files)
    fj.push_back(Json{{"file", f.name}, {"sha256", f.sha256}, {"bytes", f.bytes}});
  j["programs"] = fj;
  write_file_atomic(out / (stem + ".job.json"), j.dump(2) + "\n");
  report::write_setup_sheet(out / (stem + ".setup.html"), sheet);
  files.commit();
  info("job: " + stem + ": " + std::to_string(ops.size()) + " operations, " + fixed(sheet.cycle_time_min(), 1) +
       " min (" + std::to_string(sheet.tool_changes) + " tool changes), gouge " +
       (m.gouged ? fixed(m.max_gouge_mm, 3) + " mm" : std::string("none")) + " → " + job_nc.string());
  if (result != nullptr)
    *result = {job_nc, slot, ops.size(), sheet.tool_changes, sheet.cycle_time_min(), m.max_gouge_mm, m.gouged};
  if (m.gouged) {
    std::cerr << "millnet job: error: " << job_nc.string() << " gouges the part by " << fixed(m.max_gouge_mm, 3)
              << " mm (line " << m.first_gouge_move.line << ")\n";
    return 1;
  }
  return 0;
}

int run_job(const JobOpts& o) { return build_job(o, setup(o.common), nullptr, nullptr); }

}  // namespace

RunJobResult write_run_job(const Json& config, const std::string& config_file, const std::string& mesh_file,
                           const RunJobInput& in, const fs::path& out) {
  JobOpts o;
  o.common.config = config_file;
  o.mesh = mesh_file;
  o.out = out.string();
  RunJobResult r;
  (void)build_job(o, config, &in, &r);
  return r;
}

Registered register_job(CLI::App& app) {
  auto o = std::make_shared<JobOpts>();
  CLI::App* sub = app.add_subcommand(
      "job", "one program for a part (drilling, roughing, finishing; tool changes) + its setup sheet, simulated");
  sub->add_option("--mesh", o->mesh, "the part's mesh or CAD file")->required();
  o->mesh_flags.add_to(sub);
  sub->add_option("--strategy", o->strategy,
                  "finishing strategy slot 1..5, or best (the simulated ranking's first under /finish/aim)")
      ->check([](const std::string& v) -> std::string {
        if (v == "best") return {};
        try {
          (void)finish::parse_strategy(v);
          return v == "all" ? "expected a slot 1..5 or best, got all" : std::string();
        } catch (const Error&) {
          return "expected a slot 1..5 or best, got '" + v.substr(0, 40) + "'";
        }
      });
  sub->add_option("--tool", o->finish_tool, "finishing tool (library id or ball:D, bull:D:r)");
  sub->add_option("--rough-tool", o->rough_tool, "roughing tool (library id)");
  sub->add_option("--stock", o->stock,
                  "start from this stock instead of the block: a FILE.zmap saved by simulate --save-stock on this "
                  "part (e.g. after an earlier job's roughing), or a stock mesh in the part file's coordinates")
      ->check(CLI::ExistingFile);
  sub->add_option("--rest-tool", o->rest_tool,
                  "rest finishing after the finishing with this smaller tool (library id or ball:D), from the stock "
                  "the finishing leaves, when its rest covers /finish/rest/min_area_mm2 (default /finish/rest/tool: "
                  "none)");
  o->boundary.add_to(sub);
  sub->add_flag("--keep-deep-cuts", o->keep_deep_cuts,
                "write the job even where a cut goes deeper than its tool's flutes (warned; refused without)");
  sub->add_option("--material", o->material, "workpiece material id (configs/materials.json)");
  add_post_flag(sub, o->post);
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common);
  return {sub, [o]() { return run_job(*o); }};
}

}  // namespace millnet::app
