// The regression corpus (tests/corpus/README.md): every case tests/corpus/<reader>/<case>.<ext> is a
// malformed input that its reader must refuse with a millnet::Error naming the case's file and
// containing every line of <case>.expect.
#include "app/cli_runner.hpp"
#include "config.hpp"  // app/: load_config
#include "millnet/classifier/io/model_file.hpp"
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/io/manifest.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/pocket/io/pocket_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/stat.h>

namespace fs = std::filesystem;

namespace {

using Reader = std::function<void(const fs::path&)>;

/// One reader per corpus folder.
const std::map<std::string, Reader>& readers() {
  static const std::map<std::string, Reader> r = {
      {"config", [](const fs::path& p) { (void)millnet::app::load_config(p); }},
      {"gcode", [](const fs::path& p) { (void)millnet::gcode::read(millnet::read_file(p), p.string()); }},
      {"manifest", [](const fs::path& p) { (void)millnet::datasets_io::read_manifest(p); }},
      {"mesh", [](const fs::path& p) { (void)millnet::ingest::load_mesh(p); }},
      {"model", [](const fs::path& p) { (void)millnet::classifier_io::load_model(p); }},
      {"pocket", [](const fs::path& p) { (void)millnet::pocket::read_pocket(p); }},
      {"vectors", [](const fs::path& p) { (void)millnet::datasets::read_table(p); }},
  };
  return r;
}

/// The non-empty lines of a .expect file: each must occur in the error message.
std::vector<std::string> expected_parts(const fs::path& expect) {
  std::vector<std::string> parts;
  std::istringstream in(millnet::read_file(expect));
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) parts.push_back(line);
  return parts;
}

}  // namespace

TEST(Corpus, EveryCaseThrowsItsExpectedError) {
  const fs::path root = fs::path(MILLNET_SOURCE_DIR) / "tests" / "corpus";
  std::vector<fs::path> cases;
  for (const auto& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory()) continue;
    const std::string reader = dir.path().filename().string();
    if (reader == "cli") continue;  // whole runs of the executable: EveryCliCaseFailsWithOneLine
    if (!readers().count(reader)) {
      ADD_FAILURE() << dir.path() << ": no reader for this folder (add one to readers() in test_corpus.cpp)";
      continue;
    }
    for (const auto& f : fs::directory_iterator(dir.path()))
      if (f.is_regular_file() && f.path().extension() != ".expect") cases.push_back(f.path());
  }
  std::sort(cases.begin(), cases.end());
  ASSERT_GE(cases.size(), 10u) << "the corpus at " << root << " looks incomplete";
  for (const fs::path& c : cases) {
    const std::string name = c.parent_path().filename().string() + "/" + c.filename().string();
    SCOPED_TRACE(name);
    const fs::path expect = fs::path(c).replace_extension(".expect");
    if (!fs::exists(expect)) {
      ADD_FAILURE() << name << ": no " << expect.filename() << " beside it";
      continue;
    }
    const auto parts = expected_parts(expect);
    if (parts.empty()) ADD_FAILURE() << expect << " is empty";
    try {
      readers().at(c.parent_path().filename().string())(c);
      ADD_FAILURE() << name << ": read without an error";
    } catch (const millnet::Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.filename().string()), std::string::npos)
          << name << ": the message does not name the file:\n  " << msg;
      for (const std::string& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos)
            << name << ": expected the message to contain\n  " << p << "\ngot\n  " << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": threw a std::exception that is not millnet::Error: " << e.what();
    }
  }
}

namespace {

/// Inputs that cannot be committed (a FIFO, a symlink to a device, 140 KB of brackets, a 100,000-vertex
/// boundary) are made by the case's generator in its scratch folder {tmp} before the run.
using Generator = std::function<void(const fs::path& tmp)>;

/// A closed 20 × 20 × 10 mm box as ASCII STL: a good part for the cases whose other input is bad.
void write_box_stl(const fs::path& p) {
  const double v[8][3] = {{0, 0, 0},  {20, 0, 0},  {20, 20, 0},  {0, 20, 0},
                          {0, 0, 10}, {20, 0, 10}, {20, 20, 10}, {0, 20, 10}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::ostringstream s;
  s << "solid box\n";
  for (const auto& t : f) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) s << "   vertex " << v[t[k]][0] << " " << v[t[k]][1] << " " << v[t[k]][2] << "\n";
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid box\n";
  millnet::write_file_atomic(p, s.str());
}

/// A small vectors.csv (2×2 grid, 3 parts × 2 rows, labels 1…3) that `train` accepts.
void write_small_vectors(const fs::path& p) {
  std::string csv =
      "id,source,label,axis,angle,flip,in_1_1,in_1_2,in_2_1,in_2_2,out_1,out_2,out_3,out_4,out_5,out_6,out_7,out_8\n";
  for (int part = 1; part <= 3; ++part)
    for (int r = 0; r < 2; ++r) {
      csv += "p" + std::to_string(part) + "#" + std::to_string(r + 1) + ",p" + std::to_string(part) + "," +
             std::to_string(part) + ",x," + std::to_string(90 * r) + ",0";
      for (int k = 0; k < 4; ++k) csv += "," + std::to_string(part * (k + 1) + r);
      for (int k = 1; k <= 8; ++k) csv += k == part ? ",1" : ",0";
      csv += "\n";
    }
  millnet::write_file_atomic(p, csv);
}

const std::map<std::string, Generator>& generators() {
  static const std::map<std::string, Generator> g = {
      // Outputs are committed together or not at all (issue 15): the second output cannot be
      // written (a folder stands at its name), so the first must not be left either.
      {"sample_picture_fails",
       [](const fs::path& t) {
         write_box_stl(t / "part.stl");
         fs::create_directories(t / "out" / "part.png");
       }},
      {"train_chart_fails",
       [](const fs::path& t) {
         write_small_vectors(t / "vectors.csv");
         millnet::write_file_atomic(t / "c.json", R"({"train": {"fixed_alpha": 1}})");  // no scan: no edge warning
         fs::create_directories(t / "out" / "loo_curve.png");
       }},
      {"limits_train_loo_pairs", [](const fs::path& t) { write_small_vectors(t / "vectors.csv"); }},
      {"sample_footprint_zero",
       [](const fs::path& t) {
         millnet::write_file_atomic(t / "wall.stl",
                                    "solid wall\n facet normal 0 1 0\n  outer loop\n   vertex 0 0 0\n"
                                    "   vertex 10 0 0\n   vertex 0 0 10\n  endloop\n endfacet\nendsolid wall\n");
       }},
      {"rough_second_mesh_missing", [](const fs::path& t) { write_box_stl(t / "part.stl"); }},
      {"out_of_memory", [](const fs::path& t) { write_box_stl(t / "part.stl"); }},
      {"not_a_regular_file_dev_zero", [](const fs::path& t) { fs::create_symlink("/dev/zero", t / "x.stl"); }},
      {"not_a_regular_file_fifo", [](const fs::path& t) { ASSERT_EQ(::mkfifo((t / "x.stl").c_str(), 0600), 0); }},
      {"not_a_regular_file_folder", [](const fs::path& t) { fs::create_directories(t / "x.stl"); }},
      {"config_fifo", [](const fs::path& t) { ASSERT_EQ(::mkfifo((t / "c.json").c_str(), 0600), 0); }},
      {"view_dev_zero", [](const fs::path& t) { fs::create_symlink("/dev/zero", t / "x.nc"); }},
      // The 65 levels of tests/corpus/mesh/step_nested_65_levels.step made 70,000 (140 KB, issue 42).
      {"sample_step_nested_70000_levels",
       [](const fs::path& t) {
         std::string s =
             millnet::read_file(fs::path(MILLNET_SOURCE_DIR) / "tests/corpus/mesh/step_nested_65_levels.step");
         const std::size_t at = s.find(std::string(65, '('));
         ASSERT_NE(at, std::string::npos);
         s.replace(s.find(std::string(65, ')'), at), 65, std::string(70000, ')'));
         s.replace(at, 65, std::string(70000, '('));
         millnet::write_file_atomic(t / "deep.step", s);
       }},
      {"config_nested_70000_levels",
       [](const fs::path& t) {
         millnet::write_file_atomic(t / "deep.json", "{\"pocket\": {\"som\": {\"w\": " + std::string(70000, '[') +
                                                         std::string(70000, ']') + "}}}");
       }},
  };
  return g;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

}  // namespace

// tests/corpus/cli/<case>.args: one hostile run of the executable (README.md). Every case must exit
// with its code (1 = bad input; "# exit 2" in the .args for a usage error), print exactly one line on
// stderr containing every line of <case>.expect, leave its output folder empty, finish within 60 s
// and stay under 1 GB resident.
TEST(Corpus, EveryCliCaseFailsWithOneLine) {
  const fs::path root = fs::path(MILLNET_SOURCE_DIR) / "tests" / "corpus";
  std::vector<fs::path> cases;
  for (const auto& f : fs::directory_iterator(root / "cli"))
    if (f.path().extension() == ".args") cases.push_back(f.path());
  std::sort(cases.begin(), cases.end());
  ASSERT_GE(cases.size(), 10u);
  for (const fs::path& c : cases) {
    const std::string name = c.stem().string();
    SCOPED_TRACE("cli/" + name);
    const fs::path tmp = millnet::testing::fresh_dir("corpus_cli/" + name);
    const fs::path out = tmp / "out";
    if (generators().count(name)) generators().at(name)(tmp);
    int expected_code = 1;
    long memory_kib = 0;
    std::string args;
    std::istringstream in(millnet::read_file(c));
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("# exit ", 0) == 0)
        expected_code = std::stoi(line.substr(7));
      else if (line.rfind("# ulimit -v ", 0) == 0)
        memory_kib = std::stol(line.substr(12));
      else if (!line.empty() && line[0] != '#')
        args += (args.empty() ? "" : " ") + line;
    }
#if defined(__SANITIZE_ADDRESS__)
    // AddressSanitizer reserves terabytes of shadow address space at start: under `ulimit -v` it
    // aborts before main, so an out-of-memory case can only be checked in the plain build.
    if (memory_kib > 0) continue;
#endif
    args = replace_all(replace_all(replace_all(args, "{corpus}", root.string()), "{tmp}", tmp.string()), "{out}",
                       out.string());
    const fs::path expect = fs::path(c).replace_extension(".expect");
    ASSERT_TRUE(fs::exists(expect)) << name << ": no " << expect.filename() << " beside it";
    // Nothing may be written outside the output folder either (`--out ""` wrote into the current folder).
    const std::string before = millnet::testing::list_files(tmp);
    const auto r = millnet::testing::run_millnet(args + " --quiet", tmp, 60, memory_kib);
    EXPECT_EQ(r.code, expected_code) << name << ": " << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << name << ": expected one line on stderr, got\n"
                                                               << r.err;
    for (const std::string& p : expected_parts(expect))
      EXPECT_NE(r.err.find(p), std::string::npos)
          << name << ": expected stderr to contain\n  " << p << "\ngot\n  " << r.err;
    EXPECT_EQ(millnet::testing::list_files(out), "") << name << ": files left in the output folder";
    std::set<std::string> added;
    {
      std::istringstream after(millnet::testing::list_files(tmp)), was(before);
      for (std::string f; std::getline(after, f);) added.insert(f);
      for (std::string f; std::getline(was, f);) added.erase(f);
      added.erase("cli.stdout");
      added.erase("cli.stderr");
    }
    std::string stray;
    for (const auto& f : added) stray += f + "\n";
    EXPECT_EQ(stray, "") << name << ": files written outside the output folder (in the working folder " << tmp << ")";
    rusage ru{};
    ::getrusage(RUSAGE_CHILDREN, &ru);  // the largest child so far, in KiB
    EXPECT_LT(ru.ru_maxrss, 1024L * 1024L) << name << ": peak memory of a run ≥ 1 GB";
  }
}
