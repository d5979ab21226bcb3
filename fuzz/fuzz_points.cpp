// libFuzzer target: point clouds, x y z text (ingest_io: load_mesh on .xyz).
#include "fuzz_util.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)ingest::load_mesh(fuzz::as_file(data, size, ".xyz")); });
}
