// The z-map file (simulate_io): heights round-trip bit for bit; a header that promises more cells
// than the file holds, or more than the memory limit, is refused before anything is allocated.
#include "millnet/simulate/io/zmap_file.hpp"

#include "millnet/core/error.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

using namespace millnet;
using namespace millnet::simulate;
namespace fs = std::filesystem;

namespace {
fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millnet_zmap_file_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / name;
}
std::string error_of(const fs::path& p) {
  try {
    (void)io::read_zmap(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ZMapFile, HeightsAndGridRoundTripBitForBit) {
  const GridSpec g{-3.25, 0.1, 0.02, 7, 5};
  std::vector<double> h(g.cells());
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = 0.1 * static_cast<double>(i) - 1.7;
  h[0] = -0.0;
  h[1] = std::numeric_limits<double>::denorm_min();
  h[2] = 1e300;
  const ZMap z = ZMap::from_heights(g, h);
  const fs::path p = scratch("a.zmap");
  io::write_zmap(p, z);
  const ZMap back = io::read_zmap(p);
  EXPECT_EQ(back.spec().nx, g.nx);
  EXPECT_EQ(back.spec().ny, g.ny);
  EXPECT_EQ(back.spec().x0, g.x0);
  EXPECT_EQ(back.spec().y0, g.y0);
  EXPECT_EQ(back.spec().cell, g.cell);
  ASSERT_EQ(back.heights().size(), h.size());
  EXPECT_EQ(std::memcmp(back.heights().data(), z.heights().data(), h.size() * sizeof(double)), 0);
  for (const auto s : back.stamps()) EXPECT_EQ(s, 0u);  // no move history
  EXPECT_EQ(fs::file_size(p),
            std::string("millnet-zmap 1\n").size() +
                std::string(R"({"cell":0.02,"heights":"float64le","nx":7,"ny":5,"x0":-3.25,"y0":0.1})").size() + 1 +
                h.size() * 8);
}

TEST(ZMapFile, BadFilesAreRefusedWithTheirReason) {
  const fs::path huge = scratch("huge.zmap");
  std::ofstream(huge, std::ios::binary)
      << "millnet-zmap 1\n{\"x0\":0,\"y0\":0,\"cell\":0.01,\"nx\":100000,\"ny\":100000,\"heights\":\"float64le\"}\n";
  EXPECT_NE(error_of(huge).find("above the"), std::string::npos) << error_of(huge);
  const fs::path few = scratch("few.zmap");
  std::ofstream(few, std::ios::binary)
      << "millnet-zmap 1\n{\"x0\":0,\"y0\":0,\"cell\":0.01,\"nx\":3,\"ny\":2,\"heights\":\"float64le\"}\n12345678";
  EXPECT_NE(error_of(few).find("expected 48 bytes of heights after the header, found 8"), std::string::npos)
      << error_of(few);
  const fs::path neg = scratch("neg.zmap");
  std::ofstream(neg, std::ios::binary)
      << "millnet-zmap 1\n{\"x0\":0,\"y0\":0,\"cell\":-1,\"nx\":3,\"ny\":2,\"heights\":\"float64le\"}\n";
  EXPECT_NE(error_of(neg).find("line 2"), std::string::npos) << error_of(neg);
  const fs::path nan = scratch("nan.zmap");
  {
    std::ofstream out(nan, std::ios::binary);
    out << "millnet-zmap 1\n{\"x0\":0,\"y0\":0,\"cell\":1,\"nx\":1,\"ny\":1,\"heights\":\"float64le\"}\n";
    const double v = std::numeric_limits<double>::quiet_NaN();
    out.write(reinterpret_cast<const char*>(&v), 8);
  }
  EXPECT_NE(error_of(nan).find("not finite"), std::string::npos) << error_of(nan);
  const fs::path noline = scratch("noline.zmap");
  std::ofstream(noline, std::ios::binary) << "millnet-zmap 1\n" << std::string(5000, '{');
  EXPECT_NE(error_of(noline).find("longer than 4096"), std::string::npos) << error_of(noline);
  EXPECT_NE(error_of(scratch("")).find("not a regular file"), std::string::npos);
}

// Issue 38: a saved stock carries the block's surround (version 2) — both grids and both height
// arrays round-trip bit for bit; a version-1 file reads back without one; a surround the header
// promises but the file lacks, or one in a version-1 file, is refused naming it.
TEST(ZMapFile, TheBlocksSurroundRoundTripsAndIsRefusedWhenTheFileDisagreesWithItsHeader) {
  const GridSpec g{0, 0, 0.1, 4, 3}, sg{-5, -5, 0.25, 9, 7};
  std::vector<double> h(g.cells()), sh(sg.cells());
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = -0.01 * static_cast<double>(i);
  for (std::size_t i = 0; i < sh.size(); ++i) sh[i] = -0.5 * static_cast<double>(i % 5);
  const ZMap z = ZMap::from_heights(g, h), s = ZMap::from_heights(sg, sh);
  const fs::path p = scratch("surround.zmap");
  io::write_zmap(p, z, &s);
  const io::SavedStock back = io::read_saved_stock(p);
  ASSERT_TRUE(back.surround.has_value());
  EXPECT_EQ(back.surround->spec().x0, -5);
  EXPECT_EQ(back.surround->spec().cell, 0.25);
  EXPECT_EQ(back.surround->spec().nx, 9U);
  EXPECT_EQ(std::memcmp(back.zmap.heights().data(), z.heights().data(), h.size() * 8), 0);
  EXPECT_EQ(std::memcmp(back.surround->heights().data(), s.heights().data(), sh.size() * 8), 0);
  EXPECT_EQ(io::read_zmap(p).heights(), z.heights());
  const fs::path v1 = scratch("v1.zmap");
  io::write_zmap(v1, z);
  EXPECT_FALSE(io::read_saved_stock(v1).surround.has_value());

  const fs::path missing = scratch("missing.zmap");
  {
    std::ofstream out(missing, std::ios::binary);
    out << "millnet-zmap 2\n{\"x0\":0,\"y0\":0,\"cell\":1,\"nx\":1,\"ny\":1,\"heights\":\"float64le\"}\n";
    const double v = 0;
    out.write(reinterpret_cast<const char*>(&v), 8);
  }
  EXPECT_NE(error_of(missing).find("\"surround\" missing"), std::string::npos) << error_of(missing);
  const fs::path short_ = scratch("short.zmap");
  {
    std::ofstream out(short_, std::ios::binary);
    out << "millnet-zmap 2\n{\"x0\":0,\"y0\":0,\"cell\":1,\"nx\":1,\"ny\":1,\"heights\":\"float64le\","
           "\"surround\":{\"x0\":-1,\"y0\":-1,\"cell\":1,\"nx\":3,\"ny\":3}}\n";
    const double v = 0;
    out.write(reinterpret_cast<const char*>(&v), 8);
  }
  EXPECT_NE(error_of(short_).find("expected 80 bytes of heights after the header, found 8"), std::string::npos)
      << error_of(short_);
  const fs::path bad = scratch("bad_surround.zmap");
  std::ofstream(bad, std::ios::binary) << "millnet-zmap 2\n{\"x0\":0,\"y0\":0,\"cell\":1,\"nx\":1,\"ny\":1,"
                                          "\"heights\":\"float64le\",\"surround\":{\"x0\":0,\"y0\":0,\"cell\":-1,"
                                          "\"nx\":1,\"ny\":1}}\n";
  EXPECT_NE(error_of(bad).find("surround."), std::string::npos) << error_of(bad);
}
