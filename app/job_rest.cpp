// millnet job's rest operation (job_rest.hpp).
#include "job_rest.hpp"

#include "cli.hpp"
#include "cutting.hpp"
#include "text.hpp"

#include "millnet/job/links.hpp"

namespace millnet::app {

std::optional<job::Operation> rest_operation(const job::Part& part, const FinishSettings& settings,
                                             const simulate::ZMap& left, const job::Design& design,
                                             const tooling::Tool& rest, const RestCut& cut, double min_area_mm2,
                                             bool keep_deep_cuts, const std::string& stem,
                                             std::vector<std::string>& notes) {
  auto say = [&](const std::string& what) {
    info("job: " + stem + ": " + what);
    notes.push_back(what);
  };
  std::string why;
  const std::optional<gcode::Program> program =
      job_rest_program(part, settings, left, cutter_of(rest), min_area_mm2, cut, why);
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
