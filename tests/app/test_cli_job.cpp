// millnet job (issue 40 §2–3): one program per part with a tool change per operation — drilling where
// the roughing pre-drills, roughing, finishing — in every dialect; LinuxCNC's interpreter accepts the
// LinuxCNC job, the GRBL grammar check the GRBL one, the Fanuc one reads back to the LinuxCNC moves;
// the job.json checksums are the files' SHA-256 (sha256sum's); the job machined tool by tool gives
// the figures of its operations' own programs machined one after the other by `millnet simulate`;
// a tool that cannot reach is replaced by the library's one that can, or the job is refused.
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"
#include "testing/gcode_replay.hpp"
#include "testing/grbl_check.hpp"

#include "millnet/gcode/reader.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <variant>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;
using Json = nlohmann::json;

/// A 30 × 24 mm block 8 mm tall with a bowl-shaped cavity 5 mm deep in its middle.
fs::path write_cavity(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r2 = (x - 15) * (x - 15) / 81 + (y - 12) * (y - 12) / 49;
        return r2 < 1 ? 3 + 5 * r2 : 8.0;
      },
      0, 30, 0, 24, 60, 48);
  const fs::path p = dir / "cavity.stl";
  ingest::save_stl_binary(m, p);
  return p;
}

std::string sha256sum(const fs::path& f) {
  const fs::path out = f.string() + ".sha256";
  EXPECT_EQ(std::system(("sha256sum '" + f.string() + "' >'" + out.string() + "'").c_str()), 0);
  return slurp(out).substr(0, 64);
}

/// The positions a program's moves go to, a move within 0.0015 mm of the last one kept left out (a
/// Fanuc G43 H line restates Z after each tool change; its Z home at the end goes nowhere the
/// program knows; a LinuxCNC step of 0.0005 mm may be none on the Fanuc's 0.001 mm increment).
std::vector<gcode::Point3> positions(const fs::path& f) {
  std::vector<gcode::Point3> out;
  for (const gcode::Item& i : gcode::read(slurp(f), f.string()).items) {
    const auto* m = std::get_if<gcode::Move>(&i);
    if (m == nullptr || m->axes != gcode::kXYZ) continue;
    auto near = [&](const gcode::Point3& q) {
      return std::abs(q[0] - m->to[0]) <= 0.0015 && std::abs(q[1] - m->to[1]) <= 0.0015 &&
             std::abs(q[2] - m->to[2]) <= 0.0015;
    };
    if (out.empty() || !near(out.back())) out.push_back(m->to);
  }
  return out;
}

/// A shop library of one ball (`<config>.tools.json`) and a config `<config>.json` that finishes
/// with it at 0.1 mm cells.
void shop_ball(const fs::path& d, const std::string& config, const std::string& id, double diameter,
               double flute_length, double stickout, int number) {
  std::ofstream(d / (config + ".tools.json"))
      << R"({"tools": [{"id": ")" << id << R"(", "description": "shop ball", "type": "ball", "diameter": )" << diameter
      << R"(, "flutes": 2, "flute_length": )" << flute_length << R"(, "stickout": )" << stickout
      << R"(, "tool_material": "carbide", "number": )" << number << "}]}";
  std::ofstream(d / (config + ".json")) << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": ")" << id
                                        << R"("}}, "cutting": {"tools_file": ")" << config << R"(.tools.json"}})";
}

constexpr const char* kFast = R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}}})";

TEST(CliJob, OneProgramPerPartInEveryDialectWithItsToolChangesChecksumsAndSetupSheet) {
  const fs::path d = fresh_dir("cli_job");
  const fs::path mesh = write_cavity(d);
  std::ofstream(d / "fast.json") << kFast;
  for (const std::string post : {"linuxcnc", "grbl", "fanuc"}) {
    const auto r = run_millnet("job --quiet --no-preview --config fast.json --mesh '" + mesh.string() +
                                   "' --strategy 1 --post " + post + " --out " + post,
                               d);
    ASSERT_EQ(r.code, 0) << post << ": " << r.err;
  }
  const fs::path lx = d / "linuxcnc";
  const Json j = Json::parse(slurp(lx / "cavity.job.json"));
  const auto& ops = j["operations"];
  // The cavity's entries are pre-drilled; the roughing's 5 mm steps are more than the Ø2 ball's 3 mm
  // flutes take, so a Ø6 ball semi-finishes first (issue 38).
  ASSERT_EQ(ops.size(), 4U) << j.dump(1);
  EXPECT_EQ(ops[0]["name"], "drilling");
  EXPECT_EQ(ops[0]["tool"]["id"], "dr10-hss");
  EXPECT_EQ(ops[1]["name"], "roughing");
  EXPECT_EQ(ops[1]["tool"]["id"], "em10-3f-carbide");
  EXPECT_EQ(ops[2]["name"], "semi-finishing (s1 slope mode, leaving 0.1 mm)");
  EXPECT_EQ(ops[2]["tool"]["id"], "bn6-2f-carbide");
  // Planned with a Ø6.2 ball over the design (the allowance), its program names the real Ø6 ball.
  const std::string semi_text = slurp(d / "linuxcnc" / ops[2]["program"].get<std::string>());
  const auto named = semi_text.find("semi-finishing, bn6-2f-carbide");
  ASSERT_NE(named, std::string::npos);
  const std::string line = semi_text.substr(named, semi_text.find('\n', named) - named);
  EXPECT_EQ(line.find("6.2"), std::string::npos) << line << ": the grown planning ball is not the tool";
  EXPECT_EQ(ops[3]["tool"]["id"], "bn2-2f-carbide");
  // A job a machine survives: no rapid into material, no cut deeper than the tool's flutes (the
  // library's: drill 87, Ø10 end mill 22, Ø6 ball 10, Ø2 ball 3 mm).
  const double flutes[] = {87, 22, 10, 3};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(ops[k]["cutting_rapids"], 0) << ops[k]["name"];
    EXPECT_LE(ops[k]["max_depth_of_cut_mm"].get<double>(), flutes[k]) << ops[k]["name"];
  }
  EXPECT_GT(ops[1]["left_above_design_mm"].get<double>(), 3) << "the roughing leaves more than the Ø2 takes";
  EXPECT_LT(ops[2]["left_above_design_mm"].get<double>(), 3) << "the semi-finishing leaves less";
  // Tool changes in the operations' order, the library's numbers.
  const std::string text = slurp(lx / "cavity.job.nc");
  const auto t10 = text.find("T10 M6"), t3 = text.find("T3 M6"), t8 = text.find("T8 M6"), t7 = text.find("T7 M6");
  ASSERT_NE(t10, std::string::npos);
  EXPECT_LT(t10, t3);
  EXPECT_LT(t3, t8);
  EXPECT_LT(t8, t7);
  EXPECT_EQ(text.find("PRE-DRILL"), std::string::npos);       // a drilling operation, not a comment
  const std::string tbl = (lx / "cavity.tool.tbl").string();  // the job's tools, as the control loads them
  EXPECT_TRUE(linuxcnc_accepts((lx / "cavity.job.nc").string(), tbl));
  for (int k = 1; k <= 4; ++k) {  // each operation's own program, with its tool change
    const std::string name = ops[static_cast<std::size_t>(k - 1)]["program"];
    EXPECT_TRUE(linuxcnc_accepts((lx / name).string(), tbl)) << name;
  }
  // Checksums: sha256sum's, for the job and each operation's program.
  ASSERT_EQ(j["programs"].size(), 6U);  // the job, its four operations, the tool table
  for (const auto& p : j["programs"]) EXPECT_EQ(p["sha256"], sha256sum(lx / p["file"].get<std::string>())) << p;
  // GRBL: accepted by the grammar check, the tool changes as pauses.
  const std::string g = slurp(d / "grbl" / "cavity.job.nc");
  const auto errors = grbl_errors(g);
  EXPECT_TRUE(errors.empty()) << grbl_report(errors);
  EXPECT_EQ(g.find("M6"), std::string::npos);
  // Fanuc: G43 H per tool, and the same moves as the LinuxCNC job within the 0.001 mm increment.
  const std::string f = slurp(d / "fanuc" / "cavity.job.nc");
  EXPECT_NE(f.find("G43 H10"), std::string::npos);
  EXPECT_NE(f.find("G43 H3"), std::string::npos);
  EXPECT_NE(f.find("G43 H8"), std::string::npos);
  EXPECT_NE(f.find("G43 H7"), std::string::npos);
  const auto a = positions(lx / "cavity.job.nc"), b = positions(d / "fanuc" / "cavity.job.nc");
  ASSERT_GT(a.size(), 1000U);
  // Walked side by side: each position matched within the increments, or a step of < 0.003 mm on
  // one side only (a 0.0016 mm LinuxCNC step that Fanuc's rounding brings under positions()' 0.0015).
  auto apart = [](const gcode::Point3& p, const gcode::Point3& q) {
    return std::max({std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2])});
  };
  std::size_t m = 0, n = 0, skipped = 0;
  while (m < a.size() && n < b.size()) {
    if (apart(a[m], b[n]) <= 0.0015 + 1e-9) {
      ++m, ++n;
    } else if (m > 0 && apart(a[m], a[m - 1]) < 0.003) {
      ++m, ++skipped;
    } else if (n > 0 && apart(b[n], b[n - 1]) < 0.003) {
      ++n, ++skipped;
    } else {
      ADD_FAILURE() << "position " << m << " of the LinuxCNC job (" << a[m][0] << ", " << a[m][1] << ", " << a[m][2]
                    << ") is not position " << n << " of the Fanuc job";
      break;
    }
  }
  EXPECT_EQ(m, a.size());
  EXPECT_EQ(n, b.size());
  EXPECT_LE(skipped, 5U);
  // The setup sheet names every tool and file.
  const std::string sheet = slurp(lx / "cavity.setup.html");
  for (const char* s :
       {"dr10-hss", "em10-3f-carbide", "bn6-2f-carbide", "bn2-2f-carbide", "cavity.job.nc", "part-picture"})
    EXPECT_NE(sheet.find(s), std::string::npos) << s;
  // The job machined tool by tool: no gouge, and the figures of the operations' own programs machined
  // one after the other by simulate (an independent reading of the four files).
  EXPECT_EQ(j["simulated"]["gouge_line"], nullptr);
  double sum = 0;
  for (const auto& o : ops) sum += o["time_kinematic_min"].get<double>();
  EXPECT_NEAR(j["total_time_kinematic_min"].get<double>(), sum, 1e-9);
  // The cycle time adds each tool change of the program (/machine/tool_change_s, 15 s by default):
  // counted here on the written text, one "M6" per tool change.
  std::size_t m6 = 0;
  {
    std::istringstream in(slurp(lx / "cavity.job.nc"));
    for (std::string line; std::getline(in, line);)
      m6 += line.find(" M6") != std::string::npos && line.find('(') != 0 ? 1U : 0U;
  }
  EXPECT_EQ(m6, 4U);
  // The drilling as canned cycles where the control has them (GRBL: the moves), one simulated result.
  EXPECT_NE(slurp(lx / "cavity.job.nc").find("G98 G81 X"), std::string::npos);
  EXPECT_NE(slurp(lx.parent_path() / "fanuc" / "cavity.job.nc").find("G98 G81 X"), std::string::npos);
  EXPECT_EQ(slurp(lx.parent_path() / "grbl" / "cavity.job.nc").find("G81"), std::string::npos);
  EXPECT_EQ(j["tool_changes"].get<std::size_t>(), m6);
  EXPECT_EQ(j["tool_change_s"].get<double>(), 15.0);
  EXPECT_NEAR(j["tool_change_time_min"].get<double>(), 4 * 15.0 / 60, 1e-12);
  EXPECT_NEAR(j["total_time_min"].get<double>(), sum + 1.0, 1e-9);
  EXPECT_NE(sheet.find("+ 4 tool changes × 15 s"), std::string::npos);
  const auto s =
      run_millnet("simulate --quiet --no-preview --config fast.json --mesh '" + mesh.string() +
                      "' --gcode linuxcnc/cavity.op1.drilling.nc --gcode linuxcnc/cavity.op2.roughing.nc "
                      "--gcode linuxcnc/cavity.op3.semi-finishing.nc --gcode linuxcnc/cavity.op4.finishing.nc "
                      "--tool dr10-hss --tool em10-3f-carbide --tool bn6-2f-carbide --tool bn2-2f-carbide "
                      "--out sim",
                  d);
  ASSERT_EQ(s.code, 0) << s.err;
  const Json sim = Json::parse(slurp(d / "sim" / "cavity.sim.json"));
  for (const char* k : {"uncut_area_mm2", "rest_area_mm2", "max_gouge_mm", "ra_median_um", "scallop_max_mm"})
    EXPECT_DOUBLE_EQ(sim[k].get<double>(), j["simulated"][k].get<double>()) << k;
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(sim["programs"][i]["time_kinematic_min"].get<double>(), ops[i]["time_kinematic_min"].get<double>(),
                1e-9);
}

TEST(CliJob, AToolThatCannotReachIsReplacedByOneThatCanOrTheJobIsRefused) {
  const fs::path d = fresh_dir("cli_job_reach");
  const fs::path mesh = write_cavity(d);
  // A shop library: the Ø2 ball also in a short version (5 mm out of the holder: the cavity's floor is
  // 6 mm below the stock top; the outside walls below it to 9 mm are the roughing's, not the ball's).
  shop_ball(d, "short", "bn2-short", 2, 3, 5, 21);
  const auto r =
      run_millnet("job --no-preview --config short.json --mesh '" + mesh.string() + "' --strategy 1 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(slurp(d / "o" / "cavity.job.json"));
  EXPECT_EQ(j["operations"].back()["tool"]["id"], "bn2-2f-carbide");  // 45 mm out: the shortest that reaches
  EXPECT_NE(j["notes"].dump().find("bn2-short"), std::string::npos) << j["notes"];
  // Nothing of that kind reaches: one line naming the tool and the depth, nothing written.
  shop_ball(d, "short2", "bn3-short", 3, 3, 5, 22);
  const auto bad =
      run_millnet("job --no-preview --config short2.json --mesh '" + mesh.string() + "' --strategy 1 --out o2", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("bn3-short"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("6.0 mm below the stock top"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(fs::exists(d / "o2" / "cavity.job.nc"));
}

// Issue 38: a cut deeper than the tool's flutes breaks the tool: the job is refused in one line
// naming the operation, the place and the depth (--keep-deep-cuts writes it, warned). A Ø2 ball with
// 0.1 mm of flutes: the roughing leaves 5 mm, a Ø6 ball semi-finishes to the 0.1 mm allowance plus
// its cusps, and the Ø2 ball still meets more than 0.1 mm.
/// A 30 × 24 mm block 8 mm tall with a rectangular pocket 2 mm deep (walls steep over one 0.5 mm
/// grid step): its floor meets the walls in corners no ball fills.
fs::path write_pocket(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) { return x > 8 && x < 22 && y > 6 && y < 18 ? 6.0 : 8.0; }, 0, 30, 0, 24, 60, 48);
  const fs::path p = dir / "pocket.stl";
  ingest::save_stl_binary(m, p);
  return p;
}

TEST(CliJob, RestFinishingIsAnOperationWithItsToolChangeWhereTheFinishingLeavesRest) {
  const fs::path d = fresh_dir("cli_job_rest");
  const fs::path mesh = write_pocket(d);
  std::ofstream(d / "fast.json") << kFast;
  const std::string base = "job --quiet --no-preview --config fast.json --mesh '" + mesh.string() + "' --strategy 1 ";
  const auto r = run_millnet(base + "--rest-tool ball:1 --out out", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(slurp(d / "out" / "pocket.job.json"));
  const auto& ops = j["operations"];
  ASSERT_GE(ops.size(), 3U) << j.dump(1);
  const auto& finishing = ops[ops.size() - 2];
  const auto& rest = ops.back();
  EXPECT_EQ(finishing["tool"]["id"], "bn2-2f-carbide");
  EXPECT_EQ(rest["name"].get<std::string>().rfind("rest finishing", 0), 0U) << rest["name"];
  EXPECT_NE(rest["tool"]["number"], finishing["tool"]["number"]);  // its own tool, its own change
  EXPECT_EQ(rest["cutting_rapids"], 0);
  EXPECT_LE(rest["max_depth_of_cut_mm"].get<double>(), 1.0);  // the corners' rest, not a slot
  EXPECT_LT(rest["left_above_design_mm"].get<double>(), finishing["left_above_design_mm"].get<double>());
  EXPECT_LT(rest["time_kinematic_min"].get<double>(), finishing["time_kinematic_min"].get<double>() / 4);
  EXPECT_LT(rest["air_cut_share"].get<double>(), 0.5);
  EXPECT_LE(j["simulated"]["max_gouge_mm"].get<double>(), 0.002);
  EXPECT_EQ(rest["strategy"].get<std::string>().rfind("rest finishing", 0), 0U) << rest["strategy"];
  // At the specification's scallop (0.005 mm) with its own ball, as strategy 1 derives them: the Ø1's
  // spacing w = 2√(2·0.5·0.005 − 0.005²) = 0.14107 mm, across the shallow ground w·cos 30°, down the
  // walls w·sin 30° — not the Ø2 finishing's 0.2 mm (a 0.010 mm scallop with the Ø1) and 0.04 mm.
  EXPECT_NEAR(rest["stepover_mm"].get<double>(), 0.122170, 1e-5) << rest.dump(1);
  EXPECT_NEAR(rest["step_down_mm"].get<double>(), 0.070534, 1e-5) << rest.dump(1);
  // Its rest before and after (issue 41), as `simulate` splits them: less after, and what is left
  // is where the Ø1 cannot reach or missed (no stick-out: nothing beyond its reach).
  const double before = rest["rest_area_before_mm2"].get<double>(), after = rest["rest_area_after_mm2"].get<double>();
  EXPECT_GT(before, 0);
  EXPECT_LT(after, before / 2) << rest.dump(1);
  EXPECT_EQ(rest["rest_area_beyond_reach_mm2"].get<double>(), 0.0);
  EXPECT_LE(rest["rest_area_missed_mm2"].get<double>(), after + 1e-9);
  for (const auto& op : ops) EXPECT_LE(op["max_gouge_mm"].get<double>(), 0.002) << op["name"];
  const std::string text = slurp(d / "out" / "pocket.job.nc");
  EXPECT_NE(text.find("T" + std::to_string(rest["tool"]["number"].get<int>()) + " M6"), std::string::npos);
  EXPECT_TRUE(linuxcnc_accepts((d / "out" / "pocket.job.nc").string(), (d / "out" / "pocket.tool.tbl").string()));
  // Over the minimum area only; a rest tool no smaller than the finishing's is refused.
  std::ofstream(d / "big.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"},
                                       "rest": {"tool": "ball:1", "min_area_mm2": 1e6}}})";
  // Into a folder where an earlier job of the part left its rest program: that program is removed
  // (its tool is not in the new tool table), the folder's other files stay.
  const std::string rest_nc = "pocket.op" + std::to_string(ops.size()) + ".rest.nc";
  fs::create_directories(d / "none");
  fs::copy_file(d / "out" / rest_nc, d / "none" / rest_nc);
  std::ofstream(d / "none" / "pocket.op9.notes.txt") << "mine";
  std::ofstream(d / "none" / "pocket.opx.nc") << "mine";
  const auto none = run_millnet(
      "job --quiet --no-preview --config big.json --mesh '" + mesh.string() + "' --strategy 1 --out none", d);
  ASSERT_EQ(none.code, 0) << none.err;
  const Json n = Json::parse(slurp(d / "none" / "pocket.job.json"));
  EXPECT_EQ(n["operations"].size(), ops.size() - 1);
  EXPECT_NE(n.dump().find("no rest operation"), std::string::npos);
  EXPECT_FALSE(fs::exists(d / "none" / rest_nc));
  EXPECT_TRUE(fs::exists(d / "none" / "pocket.op9.notes.txt"));
  EXPECT_TRUE(fs::exists(d / "none" / "pocket.opx.nc"));
  for (std::size_t k = 1; k < ops.size(); ++k)  // the job's own programs, numbered as before
    EXPECT_EQ(
        fs::exists(d / "none" /
                   ("pocket.op" + std::to_string(k) + "." +
                    ops[k - 1]["name"].get<std::string>().substr(0, ops[k - 1]["name"].get<std::string>().find(' ')) +
                    ".nc")),
        true)
        << k;
  const auto big = run_millnet(base + "--rest-tool ball:3 --out bad", d);
  EXPECT_NE(big.code, 0);
  EXPECT_NE(big.err.find("not smaller"), std::string::npos) << big.err;
}

// /finish/rest/measure "programs" (issue 41): the rest operation reads the rest by the programs'
// exact approach where the z-map reads rest over the threshold. On the pocket's corners it is a
// rest operation as with the z-map's reading: its own tool, no rapid into the stock, no gouge,
// accepted by LinuxCNC, what it leaves split as before. A value the schema does not know is
// refused naming the key.
TEST(CliJob, RestMeasuredByTheProgramsIsARestOperationToo) {
  const fs::path d = fresh_dir("cli_job_rest_programs");
  const fs::path mesh = write_pocket(d);
  std::ofstream(d / "exact.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"},
                                         "rest": {"measure": "programs"}}})";
  const std::string base = "job --quiet --no-preview --mesh '" + mesh.string() + "' --strategy 1 --rest-tool ball:1 ";
  const auto r = run_millnet(base + "--config exact.json --out out", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(slurp(d / "out" / "pocket.job.json"));
  const auto& ops = j["operations"];
  ASSERT_GE(ops.size(), 3U) << j.dump(1);
  const auto& rest = ops.back();
  EXPECT_EQ(rest["name"].get<std::string>().rfind("rest finishing", 0), 0U) << rest["name"];
  EXPECT_EQ(rest["cutting_rapids"], 0);
  const double before = rest["rest_area_before_mm2"].get<double>(), after = rest["rest_area_after_mm2"].get<double>();
  EXPECT_LT(after, before / 2) << rest.dump(1);
  EXPECT_LE(rest["rest_area_missed_mm2"].get<double>(), after + 1e-9);
  for (const auto& op : ops) EXPECT_LE(op["max_gouge_mm"].get<double>(), 0.002) << op["name"];
  EXPECT_TRUE(linuxcnc_accepts((d / "out" / "pocket.job.nc").string(), (d / "out" / "pocket.tool.tbl").string()));
  // Against the z-map's reading (configs/presets/rest-stock-reading.json, the default before
  // 2026-12-07): another program, that misses less here (0.06 mm² against 0.10 on 0.1 mm cells).
  std::ofstream(d / "stock.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"},
                                         "rest": {"measure": "stock"}}})";
  ASSERT_EQ(run_millnet(base + "--config stock.json --out stock", d).code, 0);
  const std::string rest_nc = "pocket.op" + std::to_string(ops.size()) + ".rest.nc";
  EXPECT_NE(slurp(d / "out" / rest_nc), slurp(d / "stock" / rest_nc));
  const Json js = Json::parse(slurp(d / "stock" / "pocket.job.json"));
  EXPECT_LT(rest["rest_area_missed_mm2"].get<double>(), js["operations"].back()["rest_area_missed_mm2"].get<double>());
  std::ofstream(d / "bad.json") << R"({"finish": {"rest": {"measure": "zmap"}}})";
  const auto bad = run_millnet(base + "--config bad.json --out bad", d);
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("measure"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(d / "bad" / "pocket.job.nc"));
}

// A rest tool is held to what it machines (issue 41 in a job): it cuts as deep as its stick-out
// reaches from the stock top and no deeper (the rest below is left, said), and a rest operation its
// flutes cannot take is left out with a note naming where, the job written without it.
TEST(CliJob, ARestToolCutsWithinItsReachAndOneItsFlutesCannotTakeIsLeftOut) {
  const fs::path d = fresh_dir("cli_job_rest_reach");
  const fs::path mesh = write_pocket(d);
  // The pocket's floor (z 6) lies 2 mm + the top allowance below the stock top: a 2.2 mm stick-out
  // reaches the corners' upper part only; 0.05 mm of flutes take none of the rest.
  std::ofstream(d / "tools.json") << R"({"tools": [
      {"id": "bn1-reach", "type": "ball", "diameter": 1, "flutes": 2, "tool_material": "carbide",
       "flute_length": 1.5, "stickout": 2.2},
      {"id": "bn1-stub", "type": "ball", "diameter": 1, "flutes": 2, "tool_material": "carbide",
       "flute_length": 0.05, "stickout": 20}]})";
  std::ofstream(d / "c.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}},
                                     "cutting": {"tools_file": "tools.json"}})";
  const std::string base = "job --no-preview --config c.json --mesh '" + mesh.string() + "' --strategy 1 ";
  const auto r = run_millnet(base + "--rest-tool bn1-reach --out reach", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("beyond the tool's 2.2 mm stick-out: cut to its reach"), std::string::npos) << r.err;
  const Json j = Json::parse(slurp(d / "reach" / "pocket.job.json"));
  const auto& rest = j["operations"].back();
  ASSERT_EQ(rest["name"].get<std::string>().rfind("rest finishing", 0), 0U) << j.dump(1);
  double lowest = 0;
  const fs::path nc = d / "reach" / "pocket.op4.rest.nc";
  for (const gcode::Item& i : gcode::read(slurp(nc), nc.string()).items)
    if (const auto* m = std::get_if<gcode::Move>(&i); m != nullptr && m->motion != gcode::Motion::Rapid)
      lowest = std::min(lowest, m->to[2]);
  EXPECT_GE(lowest, -2.2 - 1e-9);
  EXPECT_LT(lowest, -1.5);  // it does go down to what it reaches
  EXPECT_LE(rest["max_depth_of_cut_mm"].get<double>(), 1.5);
  // The rest below the reach is counted apart from what the tool missed where it reaches.
  EXPECT_GT(rest["rest_area_beyond_reach_mm2"].get<double>(), 0) << rest.dump(1);
  // `millnet simulate` of the same two programs splits it alike.
  const auto sim = run_millnet("simulate --quiet --config c.json --mesh '" + mesh.string() +
                                   "' --gcode reach/pocket.op3.finishing.nc --tool bn2-2f-carbide"
                                   " --gcode reach/pocket.op4.rest.nc --tool bn1-reach --stock design --out sim",
                               d);
  ASSERT_EQ(sim.code, 0) << sim.err;
  const Json sr = Json::parse(slurp(d / "sim" / "pocket.sim.json"))["programs"][1];
  EXPECT_GT(sr["rest_area_beyond_reach_mm2"].get<double>(), 0) << sr.dump(1);
  EXPECT_LE(sr["rest_area_missed_mm2"].get<double>(),
            sr["rest_area_after_mm2"].get<double>() - sr["rest_area_beyond_reach_mm2"].get<double>() + 1e-9);

  const auto stub = run_millnet(base + "--rest-tool bn1-stub --out stub", d);
  ASSERT_EQ(stub.code, 0) << stub.err;
  const Json s = Json::parse(slurp(d / "stub" / "pocket.job.json"));
  EXPECT_EQ(s["operations"].size(), j["operations"].size() - 1);
  EXPECT_NE(s.dump().find("rest finishing left out: bn1-stub"), std::string::npos) << s["notes"].dump(1);
  EXPECT_NE(s.dump().find("beyond its 0.1 mm flutes"), std::string::npos) << s["notes"].dump(1);
}

TEST(CliJob, ACutDeeperThanTheToolsFlutesRefusesTheJob) {
  const fs::path d = fresh_dir("cli_job_flutes");
  const fs::path mesh = write_cavity(d);
  shop_ball(d, "stub", "bn2-stub", 2, 0.1, 45, 23);
  const std::string args =
      "job --quiet --no-preview --config stub.json --mesh '" + mesh.string() + "' --strategy 1 --out ";
  const auto bad = run_millnet(args + "o", d);
  EXPECT_EQ(bad.code, 1) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  for (const char* s : {"operation 4 (finishing", "mm deep at X", "cavity.job.nc line ",
                        "beyond the 0.1 mm flutes of bn2-stub", "no job is written"})
    EXPECT_NE(bad.err.find(s), std::string::npos) << s << "\n" << bad.err;
  EXPECT_FALSE(fs::exists(d / "o" / "cavity.job.nc"));
  const auto kept = run_millnet(args + "k --keep-deep-cuts", d);
  ASSERT_EQ(kept.code, 0) << kept.err;
  const Json j = Json::parse(slurp(d / "k" / "cavity.job.json"));
  ASSERT_EQ(j["operations"].size(), 4U);
  EXPECT_EQ(j["operations"][2]["tool"]["id"], "bn6-2f-carbide");
  EXPECT_GT(j["operations"][3]["max_depth_of_cut_mm"].get<double>(), 0.1);
  EXPECT_NE(j["notes"].dump().find("beyond the 0.1 mm flutes"), std::string::npos) << j["notes"];
}

// Issue 38: whether the finishing ball's flutes take what the roughing leaves is the depth the
// finishing would really cut (the finishing machined on the roughed stock), not the stock's height
// over the design: at the foot of a steep wall that height is the wall's (here > 3 mm, the Ø2 ball's
// flutes), and Z-level finishing takes it a step at a time. No semi-finishing, no refusal.
TEST(CliJob, AStockTallOverASteepWallIsNotADeepCutForZLevelFinishing) {
  const fs::path d = fresh_dir("cli_job_steep");
  // A 40 × 32 mm block 14 mm tall with a round-ended cavity 9 mm deep whose walls stand at ~84°.
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r = std::hypot((x - 20) / 1.25, y - 16);
        return r < 9 ? 5.0 : r < 10 ? 5 + 9 * (r - 9) : 14.0;
      },
      0, 40, 0, 32, 160, 128);
  const fs::path mesh = d / "steep.stl";
  ingest::save_stl_binary(m, mesh);
  std::ofstream(d / "fast.json") << kFast;
  const auto r =
      run_millnet("job --quiet --no-preview --config fast.json --mesh '" + mesh.string() + "' --strategy 4 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(slurp(d / "o" / "steep.job.json"));
  const auto& ops = j["operations"];
  ASSERT_GE(ops.size(), 2U) << j.dump(1);
  const Json& rough = ops[ops.size() - 2];
  const Json& finish = ops.back();
  EXPECT_EQ(rough["name"], "roughing");
  EXPECT_GT(rough["left_above_design_mm"].get<double>(), 3) << "the wall's stock, measured vertically";
  EXPECT_EQ(finish["tool"]["id"], "bn2-2f-carbide");
  EXPECT_LE(finish["max_depth_of_cut_mm"].get<double>(), 3) << "what the Ø2 ball really meets";
  for (const Json& op : ops) EXPECT_EQ(op["name"].get<std::string>().rfind("semi", 0), std::string::npos);
}

// Issue 38: an inch shop's job (/machine/program_units inch) and a job whose work origin is the
// stock's centre (/machine/work_origin) are the same job: G20 / moves translated by the origin, every
// program accepted by LinuxCNC, and machined from the block the same result as the millimetre job at
// the part's corner (times within 0.5 %, depths and what is left within 0.01 mm: an inch program's
// last decimal is 0.00254 mm).
TEST(CliJob, AnInchJobAndAJobAtTheStockCentreAreTheSameJob) {
  const fs::path d = fresh_dir("cli_job_units");
  const fs::path mesh = write_cavity(d);
  std::ofstream(d / "mm.json") << kFast;
  std::ofstream(d / "inch.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}},
    "machine": {"program_units": "inch"}})";
  std::ofstream(d / "centre.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}},
    "machine": {"work_origin": "stock_centre"}})";
  for (const std::string u : {"mm", "inch", "centre"}) {
    const auto r = run_millnet(
        "job --quiet --no-preview --config " + u + ".json --mesh '" + mesh.string() + "' --strategy 1 --out " + u, d);
    ASSERT_EQ(r.code, 0) << u << ": " << r.err;
    EXPECT_TRUE(linuxcnc_accepts((d / u / "cavity.job.nc").string(), (d / u / "cavity.tool.tbl").string())) << u;
  }
  const std::string inch = slurp(d / "inch" / "cavity.job.nc");
  EXPECT_NE(inch.find("G20 G90"), std::string::npos);
  EXPECT_EQ(inch.find("G21"), std::string::npos);
  // The stock is the 30 × 24 mm footprint grown by 5 mm: its centre is at X15 Y12 of the part's frame.
  auto x_range = [&](const std::string& u) {
    std::array<double, 4> r{1e9, -1e9, 1e9, -1e9};
    for (const gcode::Item& i : gcode::read(slurp(d / u / "cavity.job.nc"), u).items)
      if (const auto* m = std::get_if<gcode::Move>(&i)) {
        r[0] = std::min(r[0], m->to[0]), r[1] = std::max(r[1], m->to[0]);
        r[2] = std::min(r[2], m->to[1]), r[3] = std::max(r[3], m->to[1]);
      }
    return r;
  };
  const auto at_corner = x_range("mm"), at_centre = x_range("centre");
  EXPECT_NEAR(at_centre[0], at_corner[0] - 15, 1e-3);
  EXPECT_NEAR(at_centre[1], at_corner[1] - 15, 1e-3);
  EXPECT_NEAR(at_centre[2], at_corner[2] - 12, 1e-3);
  EXPECT_NEAR(at_centre[3], at_corner[3] - 12, 1e-3);
  const std::string centre = slurp(d / "centre" / "cavity.job.nc");
  EXPECT_NE(centre.find("work offset G54: X0 Y0 = the stock's centre"), std::string::npos);
  EXPECT_NE(slurp(d / "centre" / "cavity.setup.html").find("centre (the stock"), std::string::npos);
  const Json mm = Json::parse(slurp(d / "mm" / "cavity.job.json"));
  for (const std::string u : {"inch", "centre"}) {
    const Json other = Json::parse(slurp(d / u / "cavity.job.json"));
    ASSERT_EQ(mm["operations"].size(), other["operations"].size()) << u;
    for (std::size_t k = 0; k < mm["operations"].size(); ++k) {
      const Json& a = mm["operations"][k];
      const Json& b = other["operations"][k];
      EXPECT_EQ(a["name"], b["name"]) << u;
      EXPECT_NEAR(a["time_kinematic_min"].get<double>(), b["time_kinematic_min"].get<double>(),
                  0.005 * a["time_kinematic_min"].get<double>())
          << u << " " << a["name"];
      EXPECT_NEAR(a["max_depth_of_cut_mm"].get<double>(), b["max_depth_of_cut_mm"].get<double>(), 0.01)
          << u << " " << a["name"];
      EXPECT_NEAR(a["left_above_design_mm"].get<double>(), b["left_above_design_mm"].get<double>(), 0.01)
          << u << " " << a["name"];
      EXPECT_EQ(a["cutting_rapids"], b["cutting_rapids"]) << u << " " << a["name"];
    }
  }
}

}  // namespace
}  // namespace millnet::testing

namespace millnet::testing {
namespace {

// Issue 38: a stock as a model the job reads. The cavity's drilling and roughing machined by
// `simulate` and saved (--save-stock) are the stock of a second job: its drilling and roughing then
// remove nothing (every measured feed move is air, no depth of cut) and what follows machines the
// same surface as the job from the block. A stock that cuts into the design, or one on another
// grid, is one line, exit 1, no job written.
TEST(CliJob, AJobFromASavedStockMachinesOnlyWhatTheStockStillHolds) {
  const fs::path d = fresh_dir("cli_job_stock");
  const fs::path mesh = write_cavity(d);
  std::ofstream(d / "fast.json") << kFast;
  const std::string base = "job --quiet --no-preview --config fast.json --mesh '" + mesh.string() + "' --strategy 1 ";
  ASSERT_EQ(run_millnet(base + "--out a", d).code, 0);
  const Json a = Json::parse(slurp(d / "a" / "cavity.job.json"));
  ASSERT_EQ(a["operations"][1]["name"], "roughing");
  EXPECT_EQ(a["frame"]["stock_from"], "block");
  const std::string sim = "simulate --quiet --no-preview --config fast.json --mesh '" + mesh.string() + "' ";
  const auto s = run_millnet(sim +
                                 "--gcode a/cavity.op1.drilling.nc --gcode a/cavity.op2.roughing.nc --tool dr10-hss "
                                 "--tool em10-3f-carbide --save-stock --out roughed",
                             d);
  ASSERT_EQ(s.code, 0) << s.err;
  const auto r = run_millnet(base + "--stock roughed/cavity.zmap --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json b = Json::parse(slurp(d / "b" / "cavity.job.json"));
  EXPECT_EQ(b["frame"]["stock_from"], "roughed/cavity.zmap");
  // The saved stock carries the block's surround (the margin ring the z-map over the footprint does
  // not hold): nothing is left for a drilling or a roughing, none is planned.
  EXPECT_EQ(slurp(d / "roughed" / "cavity.zmap").rfind("millnet-zmap 2\n", 0), 0U);
  ASSERT_EQ(b["operations"].size(), a["operations"].size() - 2);
  EXPECT_NE(b["notes"].dump().find("roughing: none"), std::string::npos) << b["notes"];
  for (std::size_t i = 0; i < b["operations"].size(); ++i) {
    EXPECT_EQ(b["operations"][i]["name"], a["operations"][i + 2]["name"]);
    EXPECT_DOUBLE_EQ(b["operations"][i]["max_depth_of_cut_mm"].get<double>(),
                     a["operations"][i + 2]["max_depth_of_cut_mm"].get<double>());
  }
  EXPECT_LT(a["operations"][1]["air_cut_share"].get<double>(), 0.9);
  for (const char* k : {"uncut_area_mm2", "max_gouge_mm", "ra_median_um", "scallop_max_mm"})
    EXPECT_DOUBLE_EQ(b["simulated"][k].get<double>(), a["simulated"][k].get<double>()) << k;
  EXPECT_NE(b["notes"].dump().find("starts from the stock roughed/cavity.zmap"), std::string::npos);

  // A "stock" that a Ø10 flat end mill cut into the design along the finishing's ball path.
  const auto g = run_millnet(sim +
                                 "--stock design --gcode a/cavity.op4.finishing.nc --tool flat:10 --save-stock "
                                 "--out gouged",
                             d);
  ASSERT_EQ(g.code, 1) << g.err;  // the gouge is reported, the machined stock kept for inspection
  ASSERT_TRUE(fs::exists(d / "gouged" / "cavity.zmap"));
  const auto bad = run_millnet(base + "--stock gouged/cavity.zmap --out c", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("gouged/cavity.zmap"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("mm below the design at X"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(fs::exists(d / "c")) << "refused before any roughing, planning or simulation";
  // Saved on another grid (0.2 mm cells): refused, naming both grids.
  std::ofstream(d / "coarse.json") << R"({"simulate": {"cell_mm": 0.2}})";
  ASSERT_EQ(run_millnet("simulate --quiet --no-preview --config coarse.json --mesh '" + mesh.string() +
                            "' --gcode a/cavity.op2.roughing.nc --tool em10-3f-carbide --save-stock --out coarse",
                        d)
                .code,
            0);
  const auto other = run_millnet(base + "--stock coarse/cavity.zmap --out e", d);
  EXPECT_EQ(other.code, 1);
  EXPECT_NE(other.err.find("is not this part's"), std::string::npos) << other.err;
  EXPECT_FALSE(fs::exists(d / "e"));
}

// A stock mesh in the part file's coordinates: a box the block's size (footprint + 5 mm, up to the
// stock top 9 mm over the part's bottom: job.json's stock_mm) is the block, so the job is the same
// job, figure for figure; a box whose top lies below the part's top does not hold it, one 1 mm
// taller rises over Z 0: each refused with one line naming the file.
TEST(CliJob, AStockMeshTheBlocksSizeIsTheBlockAndOneThatDoesNotHoldThePartIsRefused) {
  const fs::path d = fresh_dir("cli_job_stock_mesh");
  const fs::path mesh = write_cavity(d);
  std::ofstream(d / "fast.json") << kFast;
  const std::string base = "job --quiet --no-preview --config fast.json --mesh '" + mesh.string() + "' --strategy 1 ";
  ASSERT_EQ(run_millnet(base + "--out a", d).code, 0);
  const Json a = Json::parse(slurp(d / "a" / "cavity.job.json"));
  ASSERT_EQ(a["frame"]["stock_mm"], Json::parse("[-5.0, -5.0, -9.0, 35.0, 29.0, 0.0]"));
  ingest::save_stl_binary(testing_ingest::box(-5, -5, 0, 35, 29, 9), d / "block.stl");
  const auto r = run_millnet(base + "--stock block.stl --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json b = Json::parse(slurp(d / "b" / "cavity.job.json"));
  ASSERT_EQ(b["operations"].size(), a["operations"].size());
  for (std::size_t i = 0; i < a["operations"].size(); ++i)
    for (const char* k : {"time_kinematic_min", "max_depth_of_cut_mm", "air_cut_share", "left_above_design_mm"})
      EXPECT_EQ(b["operations"][i][k], a["operations"][i][k]) << i << " " << k;
  EXPECT_EQ(b["simulated"], a["simulated"]);
  // The roughing plans from the stock (issue 38): a block already faced to 8.5 (the part's top 8 +
  // the 0.5 mm the finishing is left) has nothing for the top level (Z −0.498), so the roughing runs
  // one level fewer, sooner; a stock that is the part itself leaves the roughing nothing at all: no
  // drilling, no roughing, said so.
  ingest::save_stl_binary(testing_ingest::box(-5, -5, 0, 35, 29, 8.5), d / "faced.stl");
  const auto faced = run_millnet(base + "--stock faced.stl --out f", d);
  ASSERT_EQ(faced.code, 0) << faced.err;
  const Json fj = Json::parse(slurp(d / "f" / "cavity.job.json"));
  ASSERT_EQ(fj["operations"][1]["name"], "roughing");
  EXPECT_LT(fj["operations"][1]["time_kinematic_min"].get<double>(),
            a["operations"][1]["time_kinematic_min"].get<double>() - 0.05);
  EXPECT_NE(slurp(d / "a" / "cavity.op2.roughing.nc").find("Z-0.498"), std::string::npos);
  EXPECT_EQ(slurp(d / "f" / "cavity.op2.roughing.nc").find("Z-0.498"), std::string::npos);
  const auto itself = run_millnet(base + "--stock '" + mesh.string() + "' --out g", d);
  ASSERT_EQ(itself.code, 0) << itself.err;
  const Json gj = Json::parse(slurp(d / "g" / "cavity.job.json"));
  for (const Json& op : gj["operations"]) {
    EXPECT_NE(op["name"], "roughing");
    EXPECT_NE(op["name"], "drilling");
  }
  EXPECT_NE(gj["notes"].dump().find("roughing: none, the stock holds no material above any roughing level"),
            std::string::npos);
  ingest::save_stl_binary(testing_ingest::box(-5, -5, 0, 35, 29, 7), d / "low.stl");
  const auto low = run_millnet(base + "--stock low.stl --out c", d);
  EXPECT_EQ(low.code, 1);
  EXPECT_NE(low.err.find("low.stl"), std::string::npos) << low.err;
  EXPECT_NE(low.err.find("1.000 mm below the design"), std::string::npos) << low.err;
  EXPECT_FALSE(fs::exists(d / "c")) << "refused before any roughing, planning or simulation";
  ingest::save_stl_binary(testing_ingest::box(-5, -5, 0, 35, 29, 10), d / "tall.stl");
  const auto tall = run_millnet(base + "--stock tall.stl --out e", d);
  EXPECT_EQ(tall.code, 1);
  EXPECT_NE(tall.err.find("rises 1.000 mm above Z 0"), std::string::npos) << tall.err;
  EXPECT_FALSE(fs::exists(d / "e"));
}

}  // namespace
}  // namespace millnet::testing

namespace millnet::testing {
namespace {

/// A program's text after its first line (the "operation k of n" comment its place in the job names).
std::string body(const fs::path& f) {
  const std::string t = slurp(f);
  return t.substr(t.find('\n') + 1);
}

// Issue 38: a stock block "pre-squared or not". A sawn blank 1.5 mm taller than the squared block is
// faced first (operation 1, the roughing's end mill, no rapid into it, its depth of cut the 1.5 mm);
// what follows is the job from the pre-squared block, program for program and figure for figure; the
// setup sheet says how to touch off; LinuxCNC's interpreter accepts the job. A sawn top at the rapids'
// height, or a sawn blank with --stock, is one line, exit 1.
TEST(CliJob, ASawnBlankIsFacedFirstAndThenMachinedAsThePreSquaredBlock) {
  const fs::path d = fresh_dir("cli_job_sawn");
  const fs::path mesh = write_cavity(d);
  std::ofstream(d / "fast.json") << kFast;
  std::ofstream(d / "sawn.json") << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}},
    "rough": {"stock_squared": false, "facing_mm": 1.5}})";
  const std::string base = "job --quiet --no-preview --mesh '" + mesh.string() + "' --strategy 1 ";
  ASSERT_EQ(run_millnet(base + "--config fast.json --out a", d).code, 0);
  const auto r = run_millnet(base + "--config sawn.json --out b", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json a = Json::parse(slurp(d / "a" / "cavity.job.json"));
  const Json b = Json::parse(slurp(d / "b" / "cavity.job.json"));
  const auto &oa = a["operations"], &ob = b["operations"];
  ASSERT_EQ(ob.size(), oa.size() + 1);
  EXPECT_EQ(ob[0]["name"], "facing");
  EXPECT_EQ(ob[0]["tool"]["id"], "em10-3f-carbide");
  EXPECT_EQ(ob[0]["tool"]["number"], oa[1]["tool"]["number"]);  // the roughing's end mill
  EXPECT_NEAR(ob[0]["max_depth_of_cut_mm"].get<double>(), 1.5, 0.01);
  EXPECT_EQ(b["frame"]["blank_top_z_mm"], 1.5);
  EXPECT_EQ(b["frame"]["stock_mm"], Json::parse("[-5.0, -5.0, -9.0, 35.0, 29.0, 1.5]"));
  for (const auto& o : ob) EXPECT_EQ(o["cutting_rapids"], 0) << o["name"];
  for (std::size_t i = 0; i < oa.size(); ++i) {  // then the pre-squared block's job
    EXPECT_EQ(ob[i + 1]["name"], oa[i]["name"]);
    EXPECT_EQ(body(d / "b" / ob[i + 1]["program"].get<std::string>()),
              body(d / "a" / oa[i]["program"].get<std::string>()))
        << oa[i]["name"];
    for (const char* k : {"max_depth_of_cut_mm", "left_above_design_mm", "time_kinematic_min"})
      EXPECT_DOUBLE_EQ(ob[i + 1][k].get<double>(), oa[i][k].get<double>()) << oa[i]["name"] << " " << k;
  }
  for (const char* k : {"uncut_area_mm2", "max_gouge_mm", "ra_median_um", "scallop_max_mm"})
    EXPECT_DOUBLE_EQ(b["simulated"][k].get<double>(), a["simulated"][k].get<double>()) << k;
  const std::string sheet = slurp(d / "b" / "cavity.setup.html");
  EXPECT_NE(sheet.find("sawn blank 40.0 × 34.0 × 10.5 mm"), std::string::npos);
  EXPECT_NE(sheet.find("set Z +1.500"), std::string::npos);
  EXPECT_NE(sheet.find("facing-layer"), std::string::npos);
  EXPECT_NE(slurp(d / "a" / "cavity.setup.html").find("pre-squared block 40.0 × 34.0 × 9.0 mm"), std::string::npos);
  EXPECT_TRUE(linuxcnc_accepts((d / "b" / "cavity.job.nc").string(), (d / "b" / "cavity.tool.tbl").string()));
  EXPECT_NE(slurp(d / "b" / "cavity.job.nc").find("(sawn blank: its top at Z1.500, faced to Z0 by operation 1"),
            std::string::npos);

  std::ofstream(d / "high.json") << R"({"rough": {"stock_squared": false, "facing_mm": 4.5}})";
  const auto high = run_millnet(base + "--config high.json --out c", d);
  EXPECT_EQ(high.code, 1);
  EXPECT_NE(high.err.find("/rough/facing_mm 4.5"), std::string::npos) << high.err;
  EXPECT_EQ(std::count(high.err.begin(), high.err.end(), '\n'), 1) << high.err;
  const auto both = run_millnet(base + "--config sawn.json --stock b/cavity.job.json --out e", d);
  EXPECT_EQ(both.code, 1);
  EXPECT_NE(both.err.find("stock_squared false"), std::string::npos) << both.err;
  EXPECT_FALSE(fs::exists(d / "c"));
  EXPECT_FALSE(fs::exists(d / "e"));
}

// Issue 38: "a depth of cut beyond its tool's flute length (or /machine/max_depth_of_cut)". A machine
// that takes at most 4 mm at once: the roughing steps down 4 mm, not 5; the Ø6 ball that semi-finishes
// the cavity from the block would take 4.76 mm, so the Ø10 ball (2.76 mm) does; no milling cut
// deeper than 4 mm. At 2.5 mm no ball of the library fits: one line naming the depths, exit 1.
TEST(CliJob, TheMachinesDepthOfCutLimitCapsTheStepDownAndEveryMillingCut) {
  const fs::path d = fresh_dir("cli_job_max_cut");
  const fs::path mesh = write_cavity(d);
  const std::string base = "job --quiet --no-preview --mesh '" + mesh.string() + "' --strategy 1 ";
  for (const char* m : {"4", "2.5"})
    std::ofstream(d / ("m" + std::string(m) + ".json"))
        << R"({"simulate": {"cell_mm": 0.1}, "finish": {"tool": {"id": "bn2-2f-carbide"}}, "machine": {"max_depth_of_cut_mm": )"
        << m << "}}";
  const auto r = run_millnet(base + "--config m4.json --out a", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(slurp(d / "a" / "cavity.job.json"));
  const auto& ops = j["operations"];
  ASSERT_EQ(ops.size(), 4U);
  EXPECT_EQ(ops[2]["tool"]["id"], "bn10-2f-carbide");
  for (std::size_t k = 1; k < ops.size(); ++k) {
    EXPECT_LE(ops[k]["max_depth_of_cut_mm"].get<double>(), 4.0) << ops[k]["name"];
    EXPECT_EQ(ops[k]["cutting_rapids"], 0) << ops[k]["name"];
  }
  EXPECT_NE(slurp(d / "a" / ops[1]["program"].get<std::string>()).find("step-down 4 "), std::string::npos);
  EXPECT_NE(j["notes"].dump().find("steps down 4.00 mm instead of 5.00"), std::string::npos) << j["notes"];
  const auto low = run_millnet(base + "--config m2.5.json --out b", d);
  EXPECT_EQ(low.code, 1);
  EXPECT_NE(low.err.find("bn10-2f-carbide would cut 2.76 mm (flutes 2.5 mm)"), std::string::npos) << low.err;
  EXPECT_EQ(std::count(low.err.begin(), low.err.end(), '\n'), 1) << low.err;
  EXPECT_FALSE(fs::exists(d / "b" / "cavity.job.nc"));
}
}  // namespace
}  // namespace millnet::testing
