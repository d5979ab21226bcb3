// libFuzzer target: a shop's tool library and material table (/cutting/tools_file,
// /cutting/materials_file): JSON parse, schema check, the tools' own checks, merge with the
// built-in ones (app: tool_library).
#include "fuzz_util.hpp"
#include "cutting.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  const std::string path = fuzz::as_file(data, size, ".json");
  return fuzz::expect_clean([&] {
    for (const char* key : {"tools_file", "materials_file"}) {
      app::Json config = {{"cutting", {{"tools_file", ""}, {"materials_file", ""}}}};
      config["cutting"][key] = path;
      try {
        (void)app::tool_library(config);
      } catch (const Error&) {
        if (key[0] == 'm') throw;  // report the last one as the input's outcome
      }
    }
  });
}
