// libFuzzer target: configs: JSON parse, schema check, defaults (app: load_config).
#include "fuzz_util.hpp"
#include "config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)app::load_config(fuzz::as_file(data, size, ".json")); });
}
