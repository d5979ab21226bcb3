#pragma once
// Content hashes recorded in manifests (FNV-1a, 64 bit: not cryptographic, but stable, dependency-free
// and enough to tell whether an input file changed since a table was built).
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace millnet::datasets {

/// FNV-1a 64 of the bytes, starting from `basis` (chain calls to hash in pieces). O(bytes).
[[nodiscard]] std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t basis = 0xCBF29CE484222325ULL);

/// FNV-1a 64 of a file's bytes; throws millnet::Error naming the file when it cannot be read.
[[nodiscard]] std::uint64_t fnv1a64_file(const std::filesystem::path& path, std::uintmax_t* size = nullptr);

/// 16 lower-case hex digits.
[[nodiscard]] std::string to_hex(std::uint64_t h);

}  // namespace millnet::datasets
