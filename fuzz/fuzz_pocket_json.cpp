// libFuzzer target: pocket JSON (pocket_io: parse_pocket_json).
#include "fuzz_util.hpp"
#include "millnet/pocket/io/pocket_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean(
      [&] { (void)pocket::parse_pocket_json(std::string(fuzz::as_text(data, size)), "fuzz.json"); });
}
