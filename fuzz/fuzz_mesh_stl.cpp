// libFuzzer target: STL, binary (millnet's own reader) or ASCII (ingest_io: load_mesh).
#include "fuzz_util.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)ingest::load_mesh(fuzz::as_file(data, size, ".stl")); });
}
