// `millnet run`'s summary leads with the decision (issue 37 §2): per part the network's pick, the
// simulated best and the pick's regret, counted by hand on made-up parts.
#include "millnet/report/run_summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace millnet::report;

namespace {
// Five strategies finished; `sim` is each slot's simulated rank, `time` its minutes, `meets` 1 / 0.
RunPart part(const std::string& name, int top, std::vector<int> sim, std::vector<double> time, std::vector<int> meets) {
  RunPart p;
  p.name = name;
  p.predicted = true;
  p.top = top;
  p.top_name = "strategy";
  p.finished = p.finish_ok = true;
  p.slots = {1, 2, 3, 4, 5};
  p.network_rank = {1, 2, 3, 4, 5};
  p.simulated_rank = std::move(sim);
  p.ra_median_um = {1, 1, 1, 1, 1};
  p.time_min = time;
  p.meets_spec = std::move(meets);
  p.spec_share = {1, 1, 1, 1, 1};
  // Regret against the simulated best (the slot ranked 1, which meets the spec here).
  double best = 0;
  for (std::size_t k = 0; k < 5; ++k)
    if (p.simulated_rank[k] == 1) best = time[k];
  for (double t : time) p.regret.push_back(t / best - 1);
  return p;
}
}  // namespace

TEST(RunSummary, LeadsWithThePickTheSimulatedBestAndThePicksRegret) {
  RunSummary s;
  s.config_name = "default.json";
  s.aim = "time_to_spec";
  // a: the pick (3) is the simulated best. b: the pick (2) is third, 60 min against the best's 40.
  s.parts.push_back(part("a", 3, {2, 3, 1, 5, 4}, {30, 40, 20, 50, 45}, {1, 1, 1, 0, 1}));
  s.parts.push_back(part("b", 2, {1, 3, 2, 4, 5}, {40, 60, 50, 30, 70}, {1, 1, 1, 0, 1}));
  s.parts.back().spec_share[1] = 0.97;  // and it misses the spec
  s.parts.back().meets_spec[1] = 0;
  const RunCounts c = run_counts(s);
  EXPECT_EQ(c.pick_parts, 2u);
  EXPECT_EQ(c.pick_is_best, 1u);
  EXPECT_EQ(c.pick_meets_spec, 1u);
  EXPECT_EQ(c.regret_parts, 1u);  // b's pick misses the spec: its regret is shown, not averaged
  EXPECT_DOUBLE_EQ(pick_regret(s.parts[0]), 0.0);
  EXPECT_DOUBLE_EQ(pick_regret(s.parts[1]), 0.5);  // 60 / 40 − 1
  EXPECT_DOUBLE_EQ(c.mean_pick_regret, 0.0);
  const std::string md = run_summary_md(s);
  const auto lead = md.find("## The network's pick against the simulation");
  ASSERT_NE(lead, std::string::npos);
  EXPECT_LT(lead, md.find("## Training"));
  EXPECT_NE(md.find("| a | 3 strategy | 3 | 1 | 0.0 % | 100.0 | 20.0 | 20.0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| b | 2 strategy | 1 | 3 | 50.0 % (misses spec) | 97.0 | 40.0 | 60.0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("simulated best on 1 of 2 parts and meets the specification on 1; mean regret of the pick "
                    "0.0 % over the 1 parts where it meets it"),
            std::string::npos);
}

TEST(RunSummary, NoRegretWithoutAPrediction) {
  RunPart p = part("a", 3, {2, 3, 1, 5, 4}, {30, 40, 20, 50, 45}, {1, 1, 1, 0, 1});
  p.predicted = false;
  EXPECT_TRUE(std::isnan(pick_regret(p)));
  p.predicted = true;
  p.top = 7;  // a slot that was not simulated
  EXPECT_TRUE(std::isnan(pick_regret(p)));
}

// A pick faster than the simulated best, which won a near tie on Ra p90 under time to spec: by hand
// 39.5 / 40 − 1 = −1.25 %. Choosing it costs nothing (0), never a gain below 0 in the means, and the
// table says why it is faster.
TEST(RunSummary, APickInTheBestsNearTieCostsNothingAndSaysWhyItIsFaster) {
  RunSummary s;
  s.config_name = "default.json";
  s.aim = "time_to_spec";
  s.parts.push_back(part("a", 5, {3, 4, 1, 5, 2}, {50, 60, 40, 70, 39.5}, {1, 1, 1, 0, 1}));
  s.parts.push_back(part("b", 2, {1, 2, 3, 4, 5}, {40, 44, 50, 60, 70}, {1, 1, 1, 1, 1}));
  ASSERT_DOUBLE_EQ(s.parts[0].regret[4], 39.5 / 40 - 1);
  EXPECT_DOUBLE_EQ(pick_regret(s.parts[0]), 0.0);
  const RunCounts c = run_counts(s);
  EXPECT_EQ(c.regret_parts, 2u);
  EXPECT_NEAR(c.mean_pick_regret, (0.0 + 0.1) / 2, 1e-15);  // b: 44 / 40 − 1
  const std::string md = run_summary_md(s);
  EXPECT_NE(md.find("| a | 5 strategy | 3 | 2 | 0.0 % (1.2 % faster: a near tie the best won on Ra p90) | 100.0 | "
                    "40.0 | 39.5 |"),
            std::string::npos)
      << md;
}
