// millnet job's rest operation (job_rest.hpp).
#include "job_rest.hpp"

#include "cli.hpp"
#include "cutting.hpp"
#include "text.hpp"

#include "millnet/finish/rest.hpp"
#include "millnet/job/links.hpp"

namespace millnet::app {

std::optional<gcode::Program> job_rest_program(const job::Part& part, const FinishSettings& settings,
                                               const simulate::ZMap& z, const tooling::Cutter& rest_tool,
                                               double min_area_mm2, const RestCut& cut, std::string& why,
                                               const job::Design* design, const std::vector<job::ChainStep>& before) {
  FinishSettings plain = settings;
  plain.simulate = false;                                 // the frame and parameters only
  const PartJob job = finishing_job(part, plain, false);  // the rest tool drops on its own index below
  finish::FinishParams p = rest_finish_params(settings, job.params, rest_tool);
  p.tool_label.clear();
  p.comments = {"tool: " + p.tool.describe()};
  p.spindle_rpm = cut.rpm, p.feed_mm_min = cut.feed_mm_min, p.plunge_feed_mm_min = cut.plunge_feed_mm_min;
  finish::RestStock stock = stock_of(z, job.frame);
  if (design != nullptr && !before.empty())
    job::measure_rest_exactly(stock, z, *design, before, settings.rest_threshold_mm);
  finish::RestParams rp;
  rp.stock = &stock;
  rp.threshold_mm = settings.rest_threshold_mm;
  rp.margin_mm = settings.rest_margin_mm;
  const finish::DropCutter dropper(part.mesh, p.tool);
  const finish::RestRegions r = finish::rest_regions(part.mesh, dropper, rp, p.x0, p.y0, p.x1, p.y1);
  if (r.empty() || r.rest_axis_area_mm2 < min_area_mm2) {
    why = "rest finishing: " + fixed(r.rest_axis_area_mm2, 1) + " mm² of " + rest_tool.describe() +
          " positions over rest thicker than " + fixed(rp.threshold_mm, 3) + " mm, under /finish/rest/min_area_mm2 (" +
          fixed(min_area_mm2, 1) + " mm²): no rest operation";
    return std::nullopt;
  }
  why = "rest finishing with " + rest_tool.describe() +
        " from the stock the finishing leaves: " + std::to_string(r.regions) + " region(s), " +
        fixed(r.rest_axis_area_mm2, 1) + " mm² of tool positions over " + fixed(rp.threshold_mm, 3) + " mm of rest";
  // As deep as the tool reaches and no deeper (CAM's "limit to the tool's reach"): a region whose
  // lowest tip lies below the stick-out from the stock top is cut down to it and the rest below is
  // left, said in the note — never a deeper cut, never the whole job refused for a corner.
  const double floor_z = job.frame.stock_top - rest_tool.reach_mm;
  if (rest_tool.reach_mm > 0 && floor_z > p.boundary.z_min) {
    p.boundary.z_min = floor_z;
    const finish::RestAgainstFloor reach = finish::against_floor(r, floor_z);
    if (reach.within == 0) {
      why = "rest finishing: " + fixed(r.rest_axis_area_mm2, 1) + " mm² of " + rest_tool.describe() +
            " positions over rest thicker than " + fixed(rp.threshold_mm, 3) + " mm, all of it deeper than the " +
            format_double(rest_tool.reach_mm) + " mm the tool reaches below the stock top: no rest operation";
      return std::nullopt;
    }
    if (reach.deeper > 0)
      why += "; " + std::to_string(reach.deeper) + " of them go down to " +
             fixed(job.frame.depth_below_top(reach.lowest_z), 1) + " mm below the stock top, beyond the tool's " +
             format_double(rest_tool.reach_mm) + " mm stick-out: cut to its reach, the rest below it left";
  }
  try {
    return finish::plan_rest(part.mesh, dropper, r, "the stock the finishing leaves", p).program;
  } catch (const finish::NoRestToCut&) {  // what the regions hold no pass of the tool removes: said
    why += ", but no pass of " + rest_tool.describe() + " removes any of it: no rest operation";
    return std::nullopt;
  }
}

std::optional<job::Operation> rest_operation(const job::Part& part, const FinishSettings& settings,
                                             const simulate::ZMap& left, const job::Design& design,
                                             const std::vector<job::ChainStep>& before, const tooling::Tool& rest,
                                             const RestCut& cut, double min_area_mm2, bool keep_deep_cuts,
                                             const std::string& stem, std::vector<std::string>& notes) {
  auto say = [&](const std::string& what) {
    info("job: " + stem + ": " + what);
    notes.push_back(what);
  };
  std::string why;
  const std::optional<gcode::Program> program =
      job_rest_program(part, settings, left, cutter_of(rest), min_area_mm2, cut, why, &design, before);
  say(why);
  if (!program) return std::nullopt;
  // Planned within the tool's reach; its links clear the stock it read, 0.1 mm over its cells.
  job::check_reach(rest.cutter(), rest.label(), -job::deepest_z(*program), "the rest finishing's lowest cut");
  // Machined on a copy of the stock: whether its links really cut nothing — only if one does are
  // they raised over the pooled stock (job::clear_rapids: its 0.5 mm cells and 1 mm clearance
  // turned every entry into a feed through a millimetre of air, a third of the feed on s4) — and
  // whether its flutes take what it meets: a rest operation is a clean-up, so one that would go
  // beyond them is left out, not the whole job refused (--keep-deep-cuts keeps it, warned).
  gcode::Program cleared = *program;
  simulate::ZMap after = left;
  job::StepResult st = job::machine_steps(after, design, {{&cleared, rest.cutter()}}, settings.machine).front();
  if (st.cutting_rapids > 0) {
    cleared = job::clear_rapids(*program, left, rest.cutter(), settings.params.clearance_mm, cut.plunge_feed_mm_min);
    after = left;
    st = job::machine_steps(after, design, {{&cleared, rest.cutter()}}, settings.machine).front();
  }
  if (rest.flute_length_mm > 0 && st.max_depth_of_cut_mm > rest.flute_length_mm && !keep_deep_cuts) {
    say("rest finishing left out: " + rest.label() + " would cut " + fixed(st.max_depth_of_cut_mm, 2) +
        " mm deep at X" + fixed(st.max_cut_at[0], 2) + " Y" + fixed(st.max_cut_at[1], 2) + " Z" +
        fixed(st.max_cut_at[2], 2) + ", beyond its " + fixed(rest.flute_length_mm, 1) +
        " mm flutes (what stands over a corner it reaches first); the rest stays");
    return std::nullopt;
  }
  return job::Operation{"rest finishing (" + rest.label() + ")", rest, std::move(cleared)};
}

}  // namespace millnet::app
