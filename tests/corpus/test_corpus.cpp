// The regression corpus (tests/corpus/README.md): every case tests/corpus/<reader>/<case>.<ext> is a
// malformed input that its reader must refuse with a millnet::Error naming the case's file and
// containing every line of <case>.expect.
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
#include <sstream>
#include <string>
#include <vector>

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
      EXPECT_NE(msg.find(c.filename().string()), std::string::npos) << name << ": the message does not name the file:\n  " << msg;
      for (const std::string& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << name << ": expected the message to contain\n  " << p
                                                  << "\ngot\n  " << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": threw a std::exception that is not millnet::Error: " << e.what();
    }
  }
}
