#pragma once
// Shared by the libFuzzer targets (fuzz/README.md): the input bytes as a file with the extension a
// reader dispatches on, and the one outcome a reader may have besides success — millnet::Error.
// Anything else (a crash, a hang, unbounded memory, another exception type escaping) is a finding.
#include "millnet/core/error.hpp"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace millnet::fuzz {

/// The bytes written to <tmp>/millnet-fuzz-<pid>/input<ext> (one file per process, rewritten per
/// input; the folder is removed at exit).
inline std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, std::string_view ext) {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("millnet-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    static const std::filesystem::path keep = d;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(keep, ec);
    });
    return d;
  }();
  const std::filesystem::path p = dir / ("input" + std::string(ext));
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Runs `read`; millnet::Error is the expected refusal of a bad input.
template <class F>
int expect_clean(F&& read) {
  try {
    read();
  } catch (const millnet::Error&) {
  }
  return 0;
}

}  // namespace millnet::fuzz
