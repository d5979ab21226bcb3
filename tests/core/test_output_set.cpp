// core::OutputSet: a command's outputs are committed together or not at all (issue 15).
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;
using millnet::OutputSet;

namespace {
fs::path fresh_set_dir(const std::string& name) {
  const fs::path d = fs::path(MILLNET_BINARY_DIR) / "test_tmp" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::size_t files_in(const fs::path& d) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(d)) n += e.is_regular_file() ? 1U : 0U;
  return n;
}
}  // namespace

TEST(OutputSet, FilesAppearOnlyOnCommitAndCanBeReadBackBefore) {
  const fs::path d = fresh_set_dir("output_set_commit");
  {
    OutputSet set;
    millnet::write_file_atomic(d / "a.txt", "A");
    millnet::write_file_atomic(d / "sub" / "b.txt", "B");
    EXPECT_FALSE(fs::exists(d / "a.txt"));
    EXPECT_FALSE(fs::exists(d / "sub" / "b.txt"));
    EXPECT_EQ(millnet::read_file(d / "a.txt"), "A");  // read back before the commit
    millnet::write_file_atomic(d / "a.txt", "A2");   // written twice: the later content wins
    set.commit();
  }
  EXPECT_EQ(millnet::read_file(d / "a.txt"), "A2");
  EXPECT_EQ(millnet::read_file(d / "sub" / "b.txt"), "B");
  EXPECT_EQ(files_in(d), 2u) << "temporaries left";
}

TEST(OutputSet, AFailureLeavesNothing) {
  const fs::path d = fresh_set_dir("output_set_fail");
  try {
    OutputSet set;
    millnet::write_file_atomic(d / "model.json", "{}");
    millnet::AtomicOFStream s(d / "curve.csv");
    s << "x\n";
    s.commit();
    throw std::runtime_error("the chart failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(files_in(d), 0u);
}

TEST(OutputSet, AFolderWhereAFileGoesFailsBeforeAnythingIsInPlace) {
  const fs::path d = fresh_set_dir("output_set_folder");
  fs::create_directories(d / "b.png");
  OutputSet set;
  millnet::write_file_atomic(d / "a.csv", "a");
  EXPECT_THROW(millnet::write_file_atomic(d / "b.png", "b"), millnet::Error);
  EXPECT_FALSE(fs::exists(d / "a.csv"));
}

TEST(OutputSet, NestedSetsCommitEachGoodPartAndDropABadOne) {
  const fs::path d = fresh_set_dir("output_set_nested");
  {
    OutputSet batch;
    {
      OutputSet good;
      millnet::write_file_atomic(d / "good.nc", "G0");
      good.commit();
    }
    try {
      OutputSet bad;
      millnet::write_file_atomic(d / "bad.nc", "G0");
      throw std::runtime_error("bad part");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(fs::exists(d / "good.nc")) << "committed before the batch";
    millnet::write_file_atomic(d / "summary.json", "[]");
    batch.commit();
  }
  EXPECT_TRUE(fs::exists(d / "good.nc"));
  EXPECT_TRUE(fs::exists(d / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "bad.nc"));
  EXPECT_EQ(files_in(d), 2u);
}

TEST(OutputSet, WithoutASetWritesAreImmediate) {
  const fs::path d = fresh_set_dir("output_set_none");
  millnet::write_file_atomic(d / "a.txt", "A");
  EXPECT_TRUE(fs::exists(d / "a.txt"));
}
