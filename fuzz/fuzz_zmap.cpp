// libFuzzer target: saved stock z-maps, .zmap (simulate_io: read_zmap).
#include "fuzz_util.hpp"
#include "millnet/simulate/io/zmap_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)simulate::io::read_zmap(fuzz::as_file(data, size, ".zmap")); });
}
