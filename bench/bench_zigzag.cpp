// Zigzag planner on the three bench pockets (tool Ø10, stepover 5): regions, retractions, cut and
// rapid length, planning time, for the T- and I-partition, at 0° and with the direction search.
// Figures are reported as benchmark counters (not asserted).
#include "millnet/pocket/planner_zigzag.hpp"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>
#include <string>

using namespace millnet::pocket;

namespace {

Loop read_loop(const nlohmann::json& j) {
  Loop l;
  for (const auto& v : j)
    l.push_back({v.at(0).get<double>(), v.at(1).get<double>(), v.size() > 2 ? v.at(2).get<double>() : 0.0});
  return l;
}

Region load(const std::string& name) {
  const std::string path = std::string(MILLNET_SHARED_DIR) + "/bench/pockets/" + name + ".json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  const auto j = nlohmann::json::parse(in);
  Region r;
  r.boundary = read_loop(j.at("boundary"));
  if (j.contains("islands"))
    for (const auto& i : j.at("islands")) r.islands.push_back(read_loop(i));
  (void)validate_and_normalize(r, path);
  return r;
}

void BM_Zigzag(benchmark::State& st, const std::string& name, PartitionKind kind, bool autoangle) {
  const Region r = load(name);
  CutParams cut;
  cut.tool.diameter = 10;
  cut.stepover = 5;
  ZigzagParams zp;
  zp.partition = kind;
  if (autoangle) zp.angle_deg = std::nullopt;
  PlanResult res;
  for (auto _ : st) {
    res = plan_zigzag(r, cut, zp);
    benchmark::DoNotOptimize(res);
  }
  const ZigzagStats& zs = std::get<ZigzagStats>(res.stats);
  st.counters["regions"] = zs.regions;
  st.counters["retractions"] = static_cast<double>(res.path.retractions());
  st.counters["srps"] = static_cast<double>(zs.srps);
  st.counters["nls"] = zs.nls;
  st.counters["passes"] = static_cast<double>(zs.passes);
  st.counters["angle_deg"] = zs.angle_deg;
  st.counters["cut_mm"] = res.path.cut_length();
  st.counters["rapid_mm"] = res.path.rapid_length();
  st.counters["plan_s"] = res.planning_time_s;
}

}  // namespace

#define ZZ(name)                                                                                              \
  BENCHMARK_CAPTURE(BM_Zigzag, name##_T_0deg, #name, PartitionKind::T, false)->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(BM_Zigzag, name##_I_0deg, #name, PartitionKind::I, false)->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(BM_Zigzag, name##_T_auto, #name, PartitionKind::T, true)                                  \
      ->Unit(benchmark::kMillisecond)                                                                         \
      ->Iterations(1);                                                                                        \
  BENCHMARK_CAPTURE(BM_Zigzag, name##_I_auto, #name, PartitionKind::I, true)                                  \
      ->Unit(benchmark::kMillisecond)                                                                         \
      ->Iterations(1);

ZZ(four_islands)
ZZ(comb)
ZZ(eight_islands)

BENCHMARK_MAIN();
