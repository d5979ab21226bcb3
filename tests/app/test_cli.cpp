// The command-line contract: exit codes (0 ok, 1 bad input, 2 usage), one clear error line naming
// the file or key, and no output left behind on failure.
#include "cli_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <fstream>

using millnet::testing::fresh_dir;
using millnet::testing::list_files;
using millnet::testing::run_millnet;

TEST(Cli, HelpExitsZeroForEveryCommand) {
  const auto d = fresh_dir("cli_help");
  for (const char* cmd : {"", "sample", "dataset", "train", "predict", "pocket", "compare", "rough", "run"}) {
    const auto r = run_millnet(std::string(cmd) + " --help", d);
    EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_NE(r.out.find("--help"), std::string::npos) << cmd;
    if (*cmd && std::string(cmd) != "run") {
      EXPECT_NE(r.out.find("--quiet"), std::string::npos) << cmd;
    }
  }
}

TEST(Cli, UsageErrorsExitTwo) {
  const auto d = fresh_dir("cli_usage");
  EXPECT_EQ(run_millnet("", d).code, 2);
  EXPECT_EQ(run_millnet("frobnicate", d).code, 2);
  EXPECT_EQ(run_millnet("sample --out x", d).code, 2);  // --mesh missing
  // A flag's value out of its range is bad input like a bad config value: exit 1, one line naming it.
  const auto bad = run_millnet("sample --mesh a.stl --out x --grid abc", d);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("--grid"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

TEST(Cli, MissingMeshIsBadInputNamingTheFile) {
  const auto d = fresh_dir("cli_missing");
  const auto r = run_millnet("sample --mesh nowhere.stl --out o", d);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("nowhere.stl"), std::string::npos) << r.err;
  EXPECT_EQ(list_files(d / "o"), "");
}

TEST(Cli, GarbageStlIsBadInputAndLeavesNothing) {
  const auto d = fresh_dir("cli_garbage");
  {
    std::ofstream f(d / "junk.stl", std::ios::binary);
    for (int i = 0; i < 1000; ++i) f.put(static_cast<char>((i * 7919) % 251));
  }
  const auto r = run_millnet("sample --mesh junk.stl --out o", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("junk.stl"), std::string::npos) << r.err;
  EXPECT_EQ(list_files(d / "o"), "");
}

TEST(Cli, ConfigWithUnknownKeyIsRejectedNamingTheKey) {
  const auto d = fresh_dir("cli_badconfig");
  std::ofstream(d / "c.json") << R"({"train": {"loo": "part", "alpah": 3}})";
  const auto r = run_millnet("train --dataset nothing.csv --config c.json --out o", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("/train/alpah"), std::string::npos) << r.err;
  EXPECT_EQ(list_files(d / "o"), "");
  std::ofstream(d / "t.json") << R"({"pocket": {"stepover": "5"}})";
  const auto r2 = run_millnet("pocket --pocket p.json --config t.json --out o", d);
  EXPECT_NE(r2.code, 0);
}
