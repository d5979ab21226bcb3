// libFuzzer target: model-vector tables, vectors.csv (datasets: read_table).
#include "fuzz_util.hpp"
#include "millnet/datasets/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)datasets::read_table(fuzz::as_file(data, size, ".csv")); });
}
