#pragma once
// Scratch folders for tests: a fresh, empty folder under the build tree, and a count of the files in it.
#include <cstddef>
#include <filesystem>
#include <string>

namespace millnet::testing {

inline std::filesystem::path fresh_tmp_dir(const std::string& name) {
  const auto d = std::filesystem::path(MILLNET_BINARY_DIR) / "test_tmp" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::size_t files_in(const std::filesystem::path& d) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(d)) n += e.is_regular_file() ? 1U : 0U;
  return n;
}

}  // namespace millnet::testing
