// libFuzzer target: dataset manifests, manifest.json (datasets_io: read_manifest).
#include "fuzz_util.hpp"
#include "millnet/datasets/io/manifest.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)datasets_io::read_manifest(fuzz::as_file(data, size, ".json")); });
}
