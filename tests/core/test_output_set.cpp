// core::OutputSet: a command's outputs are committed together or not at all (issue 15).
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "testing/tmp_dirs.hpp"

namespace fs = std::filesystem;
using millnet::OutputSet;

namespace {
const auto& fresh_set_dir = millnet::testing::fresh_tmp_dir;
using millnet::testing::files_in;
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
    millnet::write_file_atomic(d / "a.txt", "A2");    // written twice: the later content wins
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
