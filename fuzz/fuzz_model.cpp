// libFuzzer target: trained models, model.json (classifier_io: load_model).
#include "fuzz_util.hpp"
#include "millnet/classifier/io/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  return fuzz::expect_clean([&] { (void)classifier_io::load_model(fuzz::as_file(data, size, ".json")); });
}
