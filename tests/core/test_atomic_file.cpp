// core: atomic outputs (nothing half-written is ever left) and shortest round-trip number text.
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "testing/tmp_dirs.hpp"

namespace fs = std::filesystem;

namespace {
const auto& fresh = millnet::testing::fresh_tmp_dir;
using millnet::testing::files_in;
}  // namespace

TEST(AtomicFile, WritesCreatesFoldersAndReplacesWhole) {
  const fs::path d = fresh("atomic_write");
  millnet::write_file_atomic(d / "a" / "b" / "x.txt", std::string_view("first version, longer"));
  millnet::write_file_atomic(d / "a" / "b" / "x.txt", std::string_view("second"));
  EXPECT_EQ(millnet::read_file(d / "a" / "b" / "x.txt"), "second");
  EXPECT_EQ(files_in(d), 1u);  // no temporary left beside it
}

TEST(AtomicFile, UncommittedStreamLeavesNothing) {
  const fs::path d = fresh("atomic_abandon");
  {
    millnet::AtomicOFStream out(d / "half.csv");
    out << "a,b\n1,";
    // an exception would unwind here: no commit
  }
  EXPECT_FALSE(fs::exists(d / "half.csv"));
  EXPECT_EQ(files_in(d), 0u);
}

TEST(AtomicFile, AbandonedRewriteKeepsTheOldFile) {
  const fs::path d = fresh("atomic_keep");
  millnet::write_file_atomic(d / "model.json", std::string_view("{\"old\": 1}"));
  {
    millnet::AtomicOFStream out(d / "model.json");
    out << "{\"new\":";
  }
  EXPECT_EQ(millnet::read_file(d / "model.json"), "{\"old\": 1}");
}

TEST(AtomicFile, ErrorsNameThePath) {
  const fs::path d = fresh("atomic_errors");
  try {
    (void)millnet::read_file(d / "missing.stl");
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.stl"), std::string::npos);
  }
  millnet::write_file_atomic(d / "plain", std::string_view("x"));
  try {  // a file where a folder is needed
    millnet::write_file_atomic(d / "plain" / "sub" / "y.txt", std::string_view("y"));
    FAIL();
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("plain"), std::string::npos) << e.what();
  }
}

TEST(FormatDouble, RoundTripsBitForBit) {
  const double values[] = {0.1,
                           1.0 / 3.0,
                           -0.0,
                           5e-324,
                           1e-300,
                           2.2250738585072014e-308,
                           123456789.123456789,
                           std::numeric_limits<double>::max(),
                           -std::numeric_limits<double>::max(),
                           42.0};
  for (double v : values) {
    const std::string s = millnet::format_double(v);
    double back = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), back);
    ASSERT_EQ(r.ec, std::errc()) << s;
    EXPECT_EQ(std::memcmp(&v, &back, sizeof v), 0) << s;
  }
  EXPECT_EQ(millnet::format_double(0.1), "0.1");  // shortest, not %.17g's 0.10000000000000001
  EXPECT_EQ(millnet::format_double(42.0), "42");
}
