// `millnet run`'s summary.md and summary page (run_summary.hpp).
#include "millnet/report/run_summary.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace millnet::report {

namespace {

std::string summary_fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

bool any_finished(const RunSummary& s) {
  return std::any_of(s.parts.begin(), s.parts.end(), [](const RunPart& p) { return p.finished; });
}

/// The index of the network's top slot among the simulated ones, or slots.size().
std::size_t top_index(const RunPart& p) {
  return static_cast<std::size_t>(std::find(p.slots.begin(), p.slots.end(), p.top) - p.slots.begin());
}

/// The slot the simulation ranks first, 0 when none.
int simulated_best(const RunPart& p) {
  for (std::size_t k = 0; k < p.slots.size() && k < p.simulated_rank.size(); ++k)
    if (p.simulated_rank[k] == 1) return p.slots[k];
  return 0;
}

/// A regret below 0 (a strategy faster than the ranked best, which won a near tie on Ra p90 under
/// time to spec) is no gain: the aim ranks the best first, so choosing another costs ≥ 0. NaN stays.
double no_gain(double r) { return std::isnan(r) ? r : std::max(0.0, r); }

/// What picking `slot` costs on a finished part, counted as the library's figures are (issue 39):
/// its regret when it meets the specification, 1 (machining it twice) when it misses it, NaN when
/// not simulated or unmeasured.
double slot_cost(const RunPart& p, int slot) {
  const auto i = static_cast<std::size_t>(std::find(p.slots.begin(), p.slots.end(), slot) - p.slots.begin());
  if (!(p.finished && p.finish_ok) || i >= p.slots.size() || i >= p.regret.size()) return std::nan("");
  if (i < p.meets_spec.size() && !p.meets_spec[i] && i < p.spec_share.size() && !std::isnan(p.spec_share[i]))
    return 1.0;
  return no_gain(p.regret[i]);
}

/// The network's picks beside always the library's most frequent best, on the test parts.
void baseline_on_test_parts(std::ostringstream& md, const RunSummary& s) {
  if (!s.scores || s.baseline_slot < 1) return;
  double net = 0, base = 0;
  std::size_t n = 0, net_best = 0, base_best = 0;
  for (const RunPart& p : s.parts) {  // O(parts × strategies)
    if (!p.predicted) continue;
    const double a = slot_cost(p, p.top), b = slot_cost(p, s.baseline_slot);
    if (std::isnan(a) || std::isnan(b)) continue;
    net += a;
    base += b;
    ++n;
    net_best += simulated_best(p) == p.top ? 1U : 0U;
    base_best += simulated_best(p) == s.baseline_slot ? 1U : 0U;
  }
  if (!n) return;
  md << "Against the shop's baseline without millnet — always strategy " << s.baseline_slot
     << " (the simulated best on the most training parts) — on the same " << n << " parts, a pick that misses the "
     << "specification counted as 100 % (the part machined twice): the network's picks cost a mean regret of "
     << summary_fixed(100 * net / static_cast<double>(n), 1) << " % (the best on " << net_best << "), always "
     << s.baseline_slot << " " << summary_fixed(100 * base / static_cast<double>(n), 1) << " % (the best on "
     << base_best << ").\n\n";
}

/// What matters first (issue 37 §2): per part, the network's pick, the simulation's best at the
/// aim, and what the pick costs against it.
void decision(std::ostringstream& md, const RunSummary& s, const RunCounts& c) {
  md << "## The network's pick against the simulation\n\n"
     << "Each test part machined virtually with all five strategies and ranked by the aim (" << s.aim
     << "). Regret = the pick's machining time / the simulated best's − 1 (0: the pick is the best, or a faster "
        "strategy in its near tie; "
        "\"misses spec\": the pick leaves more of the surface out of the specification than it allows).\n\n"
     << "| part | network's pick | simulated best | pick's simulated rank | pick's regret | pick in spec (%) | "
        "best's time (min) | pick's time (min) |\n|---|---|---|---:|---:|---:|---:|---:|\n";
  for (const RunPart& p : s.parts) {  // O(parts × strategies)
    if (!(p.finished && p.finish_ok)) continue;
    const std::size_t ti = top_index(p);
    const bool top = p.predicted && ti < p.slots.size();
    const int best = simulated_best(p);
    const auto bi = static_cast<std::size_t>(std::find(p.slots.begin(), p.slots.end(), best) - p.slots.begin());
    auto at = [](const std::vector<double>& v, std::size_t i) { return i < v.size() ? v[i] : std::nan(""); };
    const double r = pick_regret(p);
    std::string regret = "-";
    if (top && !std::isnan(r)) regret = summary_fixed(100 * r, 1) + " %";
    if (top && ti < p.regret.size() && p.regret[ti] < 0 && ti < p.meets_spec.size() && p.meets_spec[ti])
      regret += " (" + summary_fixed(-100 * p.regret[ti], 1) + " % faster: a near tie the best won on Ra p90)";
    if (top && ti < p.meets_spec.size() && !p.meets_spec[ti] && !std::isnan(at(p.spec_share, ti)))
      regret += " (misses spec)";
    md << "| " << p.name << " | " << (p.predicted ? std::to_string(p.top) + " " + p.top_name : "-") << " | "
       << (best ? std::to_string(best) : "-") << " | " << (top ? std::to_string(p.simulated_rank[ti]) : "-") << " | "
       << regret << " | "
       << (top && !std::isnan(at(p.spec_share, ti)) ? summary_fixed(100 * at(p.spec_share, ti), 1) : "-") << " | "
       << (bi < p.slots.size() ? summary_fixed(at(p.time_min, bi), 1) : "-") << " | "
       << (top ? summary_fixed(at(p.time_min, ti), 1) : "-") << " |\n";
  }
  if (c.pick_parts)
    md << "\nThe pick is the simulated best on " << c.pick_is_best << " of " << c.pick_parts << " parts and meets "
       << "the specification on " << c.pick_meets_spec << "; mean regret of the pick "
       << (c.regret_parts ? summary_fixed(100 * c.mean_pick_regret, 1) + " % over the " +
                                std::to_string(c.regret_parts) + " parts where it meets it"
                          : std::string("not measured"))
       << ".\n\n";
  baseline_on_test_parts(md, s);
}

void training(std::ostringstream& md, const RunSummary& s) {
  if (s.scores) {
    md << "## Training\n\n"
       << "Training set: " << s.vectors << " vectors from " << s.training_parts
       << " parts, each labelled by virtual machining: output k holds strategy k's score under the aim (the best "
       << "1, a strategy twice as long 0.5, one that gouges or misses the specification 0; datasets/" << s.labels_file
       << "). "
       << "Penalty coefficient α = " << summary_fixed(s.alpha, 4) << ", chosen for the " << s.criterion
       << " leaving out whole parts.\n\n"
       << "| leaving out each training part | parts | pick = simulated best | mean regret | median | p90 | "
          "picks that miss the spec |\n|---|---:|---:|---:|---:|---:|---:|\n"
       << "| the network | " << s.lopo_parts << " | " << summary_fixed(100 * s.lopo_top1, 1) << " % | "
       << summary_fixed(100 * s.lopo_mean, 2) << " % | " << summary_fixed(100 * s.lopo_median, 1) << " % | "
       << summary_fixed(100 * s.lopo_p90, 1) << " % | " << s.lopo_misses << " |\n"
       << "| always strategy " << s.baseline_slot << " | " << s.lopo_parts << " | "
       << summary_fixed(100 * s.baseline_top1, 1) << " % | " << summary_fixed(100 * s.baseline_mean, 2) << " % | "
       << summary_fixed(100 * s.baseline_median, 1) << " % | " << summary_fixed(100 * s.baseline_p90, 1) << " % | |\n\n"
       << "A pick that misses the specification counts 100 %. Label accuracy on the outputs' argmax: "
       << summary_fixed(100 * s.accuracy_part, 1) << " % of the vectors leaving out whole parts.\n\n"
       << "![leave-one-out regret curve](model/loo_regret.png)\n\n";
    return;
  }

  md << "## Training\n\n"
     << "Training set: " << s.vectors << " vectors from " << s.training_parts
     << " parts. Penalty coefficient α = " << summary_fixed(s.alpha, 4) << " chosen by leave-one-" << s.loo_mode
     << "-out" << (s.alpha_edge != "none" ? " (at the " + s.alpha_edge + " edge of the scan)" : std::string()) << ".\n"
     << "Verification accuracy: " << summary_fixed(100 * s.accuracy_part, 1) << " % leaving out whole parts, "
     << summary_fixed(100 * s.accuracy_vector, 1) << " % leaving out single vectors (the paper's LOO; optimistic, "
     << "since a vector's rotated siblings stay in).\n\n"
     << "![leave-one-out curve](model/loo_curve.png)\n\n";
}

void prediction_table(std::ostringstream& md, const RunSummary& s, const RunCounts& c) {
  md << "| part | expected | predicted strategy | confidence | consistency | unfamiliar | roughing time (min) | "
        "retractions | cut length (mm) | levels |\n|---|---:|---|---:|---:|---|---:|---:|---:|---:|\n";
  for (const RunPart& p : s.parts) {  // O(parts)
    md << "| [" << p.name << "](parts/" << p.name << "/) | " << (p.expected ? std::to_string(p.expected) : "-")
       << " | ";
    if (p.predicted)
      md << p.top << " " << p.top_name << " | " << summary_fixed(100 * p.confidence, 0) << " % | "
         << summary_fixed(100 * p.consistency, 0) << " % | " << (p.unfamiliar ? "yes" : "no") << " | ";
    else
      md << "error: " << p.predict_error << " | | | | ";
    if (p.roughed && p.rough_ok)
      md << summary_fixed(p.rough_time_min, 1) << " | " << summary_fixed(p.retractions, 0) << " | "
         << summary_fixed(p.cut_length_mm, 0) << " | " << p.levels << " |\n";
    else if (p.roughed)
      md << "error: " << p.rough_error << " | | | |\n";
    else
      md << "- | - | - | - |\n";
  }
  if (c.labelled)
    md << "\nFamily agreement (the strategy number the part generator gave the test part's family, which is what "
          "the network is trained on — not a machining outcome): "
       << c.correct << " of " << c.labelled << ".\n";
}

void finishing_table(std::ostringstream& md, const RunSummary& s, const RunCounts& c) {
  md << "\n## Finishing: the network's ranking beside the simulated one\n\n"
     << "Every part finished with the five strategies (" << s.finish_settings_note << "), each program read back "
     << "and machined on a z-map from the design + finishing stock, ranked by the aim (" << s.aim << "); the "
     << "network ranks them by its totals over the variants (the paper's Figure 8 beside its Figure 9). ρ is "
     << "Spearman's rank correlation of the two rankings (1 = same order, −1 = reversed). Then the roughing "
     << "program and the network's top strategy machined one after the other on one z-map from flat stock. "
     << "Material left above the design by more than the tolerance (along the surface normal) is a scallop "
     << "when it lies between passes that reached the design within the tool's radius on both sides, rest "
     << "material when the finishing tool cannot reach the design there (a concave corner tighter than it: "
     << "the same for every strategy), and uncut otherwise.\n\n"
     << "| part | network ranking | simulated ranking | ρ | top strategy's simulated rank | Ra median of the "
        "top (µm) | best Ra median (µm) | rough + top: deepest cut of the finisher (mm) | rough + top: Ra median "
        "(µm) | rough + top: uncut (mm²) | rough + top: rest material (mm²) | rough + top: gouge (mm) |\n"
     << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const RunPart& p : s.parts) {  // O(parts × strategies)
    if (!p.finished) continue;
    md << "| " << p.name << " | ";
    if (!p.finish_ok) {
      md << "error: " << p.finish_error << " | | | | | | | | | |\n";
      continue;
    }
    const double best = *std::min_element(p.ra_median_um.begin(), p.ra_median_um.end());
    const std::size_t ti = top_index(p);
    const bool top = ti < p.slots.size();
    md << (p.network_rank.empty() ? "-" : ranking_text(p.slots, p.network_rank)) << " | "
       << ranking_text(p.slots, p.simulated_rank) << " | "
       << (p.network_rank.empty() ? "-" : summary_fixed(p.spearman, 2)) << " | "
       << (top ? std::to_string(p.simulated_rank[ti]) : "-") << " | "
       << (top ? summary_fixed(p.ra_median_um[ti], 2) : "-") << " | " << summary_fixed(best, 2) << " | ";
    if (p.chained)
      md << summary_fixed(p.chain_finisher_depth_of_cut_mm, 2) << " | " << summary_fixed(p.chain_ra_median_um, 2)
         << " | " << summary_fixed(p.chain_uncut_mm2, 1) << " | " << summary_fixed(p.chain_rest_mm2, 1) << " | "
         << summary_fixed(p.chain_gouge_mm, 4) << " |\n";
    else
      md << "- | - | - | - | - |\n";
  }
  if (c.spearman_parts)
    md << "\nMean ρ over " << c.spearman_parts << " parts: " << summary_fixed(c.mean_spearman, 2) << ".\n";
}

/// Per part, its job: one program from the block to the finish, machined virtually.
void jobs_table(std::ostringstream& md, const RunSummary& s) {
  if (std::none_of(s.parts.begin(), s.parts.end(), [](const RunPart& p) { return p.jobbed; })) return;
  md << "\n## Jobs: one program per part\n\n"
     << "Each part's job as `millnet job` writes it (docs/job.md): drilling where the roughing pre-drills, "
        "roughing, semi-finishing where the finishing ball's flutes would not take what the roughing leaves, "
        "then the simulated ranking's first strategy, each with its tool change, in one work offset; machined "
        "from the block on one z-map. Cycle time = the operations' kinematic times + the tool changes.\n\n"
     << "| part | job program | finishing | operations | tool changes | cycle time (min) | gouge (mm) | setup "
        "sheet |\n|---|---|---:|---:|---:|---:|---:|---|\n";
  for (const RunPart& p : s.parts) {  // O(parts)
    if (!p.jobbed) continue;
    const std::string d = "parts/" + p.name + "/job/";
    md << "| " << p.name << " | ";
    if (p.job_program.empty()) {
      md << "error: " << p.job_error << " | | | | | | |\n";
      continue;
    }
    md << "[" << p.job_program << "](" << d << p.job_program << ") | s" << p.job_strategy << " | " << p.job_operations
       << " | " << p.job_tool_changes << " | " << summary_fixed(p.job_time_min, 1) << " | "
       << (p.job_ok ? summary_fixed(p.job_gouge_mm, 4) : "**" + summary_fixed(p.job_gouge_mm, 4) + "**")
       << " | [setup](" << d << p.name << ".setup.html) |\n";
  }
}

void part_sections(std::ostringstream& md, const RunSummary& s) {
  md << "\n## Parts\n";
  for (const RunPart& p : s.parts) {
    const std::string d = "parts/" + p.name + "/";
    md << "\n### " << p.name << "\n\n";
    if (p.predicted) md << "![prediction](" << d << p.name << ".png)\n";
    if (p.roughed && p.rough_ok) {
      md << "\nRoughing: [G-code](" << d << p.name << ".nc), [metrics](" << d << p.name
         << ".metrics.json). Top and bottom levels:\n\n"
         << "![level 1](" << d << p.name << ".level_1.png)\n";
      if (p.levels > 1) md << "![level " << p.levels << "](" << d << p.name << ".level_" << p.levels << ".png)\n";
    }
    if (p.finished && p.finish_ok) {
      md << "\nFinishing: [the five strategies ranked](" << d << "finish/" << p.name << ".strategies.md); share of "
         << "the surface per Ra bin, per strategy:\n\n![Ra per strategy](" << d << "finish/" << p.name
         << ".strategies.png)\n";
      if (p.chained)
        md << "\nRoughing, then strategy " << p.top << ", on one z-map ([figures](" << d << p.name
           << ".rough_finish.sim.json)):\n\n![Ra](" << d << p.name << ".rough_finish.ra.png) ![machined − design](" << d
           << p.name << ".rough_finish.deviation.png)\n";
    }
  }
}

}  // namespace

std::string ranking_text(const std::vector<int>& slots, const std::vector<int>& rank) {
  std::vector<std::pair<int, int>> by;  // (rank, slot)
  for (std::size_t i = 0; i < slots.size() && i < rank.size(); ++i) by.emplace_back(rank[i], slots[i]);
  std::sort(by.begin(), by.end());
  std::string t;
  for (std::size_t r = 0; r < by.size(); ++r) t += (r ? " > " : "") + std::to_string(by[r].second);
  return t;
}

RunCounts run_counts(const RunSummary& s) {
  RunCounts c;
  double rho_sum = 0, regret_sum = 0;
  for (const RunPart& p : s.parts) {  // O(parts)
    if (p.predicted && p.expected) {
      ++c.labelled;
      c.correct += p.top == p.expected ? 1 : 0;
    }
    c.failures += (p.predicted ? 0U : 1U) + (p.roughed && !p.rough_ok ? 1U : 0U) +
                  (p.finished && !p.finish_ok ? 1U : 0U) + (p.jobbed && !p.job_ok ? 1U : 0U);
    if (p.finished && p.finish_ok && !p.network_rank.empty()) {
      rho_sum += p.spearman;
      ++c.spearman_parts;
    }
    const std::size_t ti = top_index(p);
    if (p.finished && p.finish_ok && p.predicted && ti < p.slots.size()) {
      ++c.pick_parts;
      c.pick_is_best += simulated_best(p) == p.top ? 1U : 0U;
      const bool meets = ti < p.meets_spec.size() && p.meets_spec[ti];
      c.pick_meets_spec += meets ? 1U : 0U;
      // A pick that misses the spec is faster for leaving work undone: its regret is not a gain.
      if (const double r = pick_regret(p);
          !std::isnan(r) && (meets || ti >= p.spec_share.size() || std::isnan(p.spec_share[ti]))) {
        regret_sum += r;
        ++c.regret_parts;
      }
    }
  }
  if (c.spearman_parts) c.mean_spearman = rho_sum / static_cast<double>(c.spearman_parts);
  if (c.regret_parts) c.mean_pick_regret = regret_sum / static_cast<double>(c.regret_parts);
  return c;
}

double pick_regret(const RunPart& p) {
  const std::size_t ti = top_index(p);
  if (!(p.finished && p.finish_ok && p.predicted) || ti >= p.regret.size()) return std::nan("");
  return no_gain(p.regret[ti]);
}

std::string run_summary_md(const RunSummary& s) {
  const RunCounts c = run_counts(s);
  std::ostringstream md;
  md << "# millnet run: " << s.config_name << "\n\n";
  if (any_finished(s)) decision(md, s, c);
  training(md, s);
  prediction_table(md, s, c);
  if (any_finished(s)) finishing_table(md, s, c);
  jobs_table(md, s);
  part_sections(md, s);
  md << "\n## Time per stage\n\n| stage | seconds |\n|---|---:|\n";
  for (const auto& [stage, seconds] : s.timing_s) md << "| " << stage << " | " << summary_fixed(seconds, 2) << " |\n";
  return md.str();
}

SummaryPage run_summary_page(const RunSummary& s) {
  SummaryPage page;
  page.title = "millnet run: " + s.config_name;
  page.header = {"part",
                 "expected",
                 "predicted strategy",
                 "confidence",
                 "roughing time (min)",
                 "retractions",
                 "cut length (mm)",
                 "levels",
                 "3D preview",
                 "simulated best",
                 "pick's regret"};
  SummaryChart time_chart{"roughing time per part", "min", {}, {{"roughing time (min)", {}}}};
  SummaryChart ra_chart{"finishing: simulated Ra median per strategy", "Ra median (µm)", {}, {}};
  for (const RunPart& p : s.parts) {  // O(parts × strategies)
    const std::string d = "parts/" + p.name + "/";
    std::vector<std::string> row{p.name, p.expected ? std::to_string(p.expected) : "-"};
    if (p.predicted)
      row.insert(row.end(), {std::to_string(p.top) + " " + p.top_name, summary_fixed(100 * p.confidence, 0) + " %"});
    else
      row.insert(row.end(), {"error: " + p.predict_error, ""});
    if (p.roughed && p.rough_ok) {
      row.insert(row.end(), {summary_fixed(p.rough_time_min, 1), summary_fixed(p.retractions, 0),
                             summary_fixed(p.cut_length_mm, 0), std::to_string(p.levels),
                             "link:roughing|" + d + p.name + ".html"});
      time_chart.labels.push_back(p.name);
      time_chart.series[0].second.push_back(p.rough_time_min);
      page.previews.emplace_back(p.name + ": roughing", d + p.name + ".html");
    } else {
      row.insert(row.end(), {"", "", "", "", ""});
    }
    const int best = p.finished && p.finish_ok ? simulated_best(p) : 0;
    const double r = pick_regret(p);
    row.insert(row.end(), {best ? std::to_string(best) : "", std::isnan(r) ? "" : summary_fixed(100 * r, 1) + " %"});
    page.rows.push_back(row);
    if (!(p.finished && p.finish_ok)) continue;
    ra_chart.labels.push_back(p.name);
    for (std::size_t k = 0; k < p.slots.size(); ++k) {
      const std::string sname = "strategy " + std::to_string(p.slots[k]);
      auto it =
          std::find_if(ra_chart.series.begin(), ra_chart.series.end(), [&](const auto& x) { return x.first == sname; });
      if (it == ra_chart.series.end()) {
        ra_chart.series.emplace_back(sname, std::vector<double>(ra_chart.labels.size() - 1, std::nan("")));
        it = ra_chart.series.end() - 1;
      }
      it->second.push_back(p.ra_median_um[k]);
      page.previews.emplace_back(p.name + ": finishing, " + sname,
                                 d + "finish/" + p.name + ".s" + std::to_string(p.slots[k]) + ".html");
    }
    for (auto& sr : ra_chart.series) sr.second.resize(ra_chart.labels.size(), std::nan(""));
    if (p.chained)
      page.previews.emplace_back(p.name + ": roughing + top strategy, simulated", d + p.name + ".rough_finish.html");
  }
  if (!time_chart.labels.empty()) page.charts.push_back(time_chart);
  if (!ra_chart.labels.empty()) page.charts.push_back(ra_chart);
  return page;
}

}  // namespace millnet::report
