// The strategies' ranking table and Figure 9 (tables.hpp).
#include "millnet/report/tables.hpp"

#include "millnet/report/plots.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace millnet::report {

namespace {
std::string fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}
}  // namespace

StrategyTable strategy_table(const std::string& stem, const std::string& aim,
                             const std::vector<job::StrategyOutcome>& outcomes, const std::vector<std::size_t>& order,
                             bool simulated) {
  std::ostringstream csv, md;
  csv << "rank,strategy,name,path_length_mm,time_feed_min,time_kinematic_min,lifts";
  md << "# " << stem << ": finishing strategies ranked by " << aim << "\n\n"
     << "| rank | strategy | path (m) | time feed (min) | time kinematic (min) | lifts |";
  if (simulated) {
    csv << ",ra_median_um,ra_p90_um,scallop_max_mm,max_gouge_mm,uncut_area_mm2,not_machined_pct"
        << ",in_spec_pct,meets_spec,regret,ra_target_pct,stepover_mm,step_down_mm";
    md << " Ra median (µm) | Ra p90 (µm) | scallop (mm) | gouge (mm) | uncut (mm²) | not machined (%) |"
       << " in spec (%) | regret (%) | Ra ≤ target (%) | stepover / step-down (mm) |";
  }
  csv << "\n";
  md << "\n|---|---|---|---|---|---|" << (simulated ? "---|---|---|---|---|---|---|---|---|---|" : "") << "\n";
  auto pct = [](double share, int decimals) {
    return std::isnan(share) ? std::string() : fixed(100 * share, decimals);
  };
  for (std::size_t r = 0; r < order.size(); ++r) {  // O(strategies)
    const job::StrategyOutcome& o = outcomes[order[r]];
    const std::string name = finish::strategy_name(o.strategy);
    // A program that gouges never ranks (issue 37 §1): it is listed last, its rank "gouges".
    const std::string rank = o.simulated && o.surface.gouged ? std::string("gouges") : std::to_string(r + 1);
    csv << rank << "," << static_cast<int>(o.strategy) << ",\"" << name << "\"," << fixed(o.path_length_mm, 3) << ","
        << fixed(o.time_feed_min, 4) << "," << fixed(o.time_kinematic_min, 4) << "," << o.lifts;
    md << "| " << rank << " | " << name << " | " << fixed(o.path_length_mm / 1000, 2) << " | "
       << fixed(o.time_feed_min, 1) << " | " << fixed(o.time_kinematic_min, 1) << " | " << o.lifts << " |";
    if (simulated) {
      const simulate::SurfaceMetrics& m = o.surface;
      csv << "," << fixed(m.ra_median_um, 3) << "," << fixed(m.ra_p90_um, 3) << "," << fixed(m.scallop_max_mm, 4) << ","
          << fixed(m.max_gouge_mm, 4) << "," << fixed(m.uncut_area_mm2, 2) << ","
          << fixed(100 * m.ra_not_machined_share, 2);
      md << " " << fixed(m.ra_median_um, 2) << " | " << fixed(m.ra_p90_um, 2) << " | " << fixed(m.scallop_max_mm, 4)
         << " | " << fixed(m.max_gouge_mm, 4) << " | " << fixed(m.uncut_area_mm2, 1) << " | "
         << fixed(100 * m.ra_not_machined_share, 1) << " |";
      const double in_spec = m.spec_measured ? m.spec_share : std::nan("");
      csv << "," << pct(in_spec, 2) << "," << (m.spec_measured ? (o.meets_spec ? "yes" : "no") : "") << ","
          << (std::isnan(o.regret) ? std::string() : fixed(o.regret, 4)) << "," << pct(m.ra_target_share, 2) << ","
          << fixed(o.stepover_mm, 4) << "," << fixed(o.step_down_mm, 4);
      md << " " << pct(in_spec, 1) << (m.spec_measured && !o.meets_spec ? " (misses)" : "") << " | " << pct(o.regret, 1)
         << " | " << pct(m.ra_target_share, 1) << " | " << fixed(o.stepover_mm, 3) << " / " << fixed(o.step_down_mm, 3)
         << " |";
    }
    csv << "\n";
    md << "\n";
  }
  return {csv.str(), md.str()};
}

void ra_bins_png(const std::filesystem::path& path, const std::string& stem, const std::vector<double>& edges,
                 const std::vector<job::StrategyOutcome>& outcomes) {
  std::vector<std::string> cats;
  for (std::size_t b = 0; b < edges.size(); ++b)
    cats.push_back(b + 1 < edges.size() ? fixed(edges[b], 2) + "-" + fixed(edges[b + 1], 2)
                                        : ">= " + fixed(edges[b], 2));
  // Surface left at the stock has its own bar (issue 37 §1), drawn only when some strategy left any.
  const bool any_untouched = std::any_of(
      outcomes.begin(), outcomes.end(), [](const job::StrategyOutcome& o) { return o.surface.not_machined_cells > 0; });
  if (any_untouched) cats.emplace_back("not machined");
  std::vector<NamedValues> series;
  for (const job::StrategyOutcome& o : outcomes) {
    NamedValues nv{finish::strategy_name(o.strategy), {}};
    for (const double s : o.surface.ra_share) nv.values.push_back(100 * s);
    if (any_untouched) nv.values.push_back(100 * o.surface.ra_not_machined_share);
    series.push_back(std::move(nv));
  }
  BarOptions bo;
  bo.show_values = false;
  (void)grouped_bar_png(path, cats, series, stem + ": share of the surface per Ra bin (um)", "surface (%)", bo);
}

}  // namespace millnet::report
