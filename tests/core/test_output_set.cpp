// core::OutputSet: a command's outputs are committed together or not at all (issue 15).
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/interrupt.hpp"
#include "millnet/core/output_set.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

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

// Issue 42 §9: a signal during the final renames left part of an output set. A signal held back by
// DeferInterrupts is acted on when the scope ends: the process still ends by it, after the scope.
TEST(Interrupts, DeferredSignalEndsTheProcessAfterTheScope) {
  const fs::path d = fresh_set_dir("defer_interrupts");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    {
      const millnet::DeferInterrupts hold;
      ::kill(::getpid(), SIGTERM);
      millnet::write_file_atomic(d / "after_the_signal.txt", "held back");
    }
    ::_exit(0);  // not reached: the held-back SIGTERM ends the process here
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_TRUE(fs::exists(d / "after_the_signal.txt"));
  EXPECT_EQ(files_in(d), 1u);
}

// SIGTERM sent (by another thread, which may also be the one to receive it) as soon as the first of
// 400 files is in place: the process ends by the signal with all 400 in place and no temporary.
TEST(OutputSet, ASignalDuringTheRenamesLeavesTheWholeSet) {
  const fs::path d = fresh_set_dir("output_set_signal");
  constexpr int kFiles = 400;
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    OutputSet set;
    for (int i = 0; i < kFiles; ++i) millnet::write_file_atomic(d / ("f" + std::to_string(i) + ".txt"), "x");
    std::thread killer([&] {
      while (!fs::exists(d / "f0.txt")) std::this_thread::yield();
      ::kill(::getpid(), SIGTERM);
    });
    killer.detach();
    set.commit();
    for (;;) ::pause();  // the held-back signal ended the process at the end of commit()
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  std::size_t finals = 0, temporaries = 0;
  for (const auto& e : fs::directory_iterator(d))
    (e.path().string().find(".tmp-") == std::string::npos ? finals : temporaries) += 1;
  EXPECT_EQ(finals, static_cast<std::size_t>(kFiles));
  EXPECT_EQ(temporaries, 0u);
}
