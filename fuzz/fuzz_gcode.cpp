// libFuzzer target: G-code (gcode: read).
#include "fuzz_util.hpp"
#include "millnet/gcode/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)gcode::read(fuzz::as_text(data, size), "fuzz.nc"); });
}
