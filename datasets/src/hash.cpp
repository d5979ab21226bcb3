#include "millnet/datasets/hash.hpp"

#include "millnet/core/atomic_file.hpp"

namespace millnet::datasets {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t basis) {
  std::uint64_t h = basis;
  for (const char c : bytes) {  // O(bytes)
    h ^= static_cast<std::uint8_t>(c);
    h *= 0x100000001B3ULL;
  }
  return h;
}

std::uint64_t fnv1a64_file(const std::filesystem::path& path, std::uintmax_t* size) {
  const std::string content = read_file(path);  // throws naming the file
  if (size != nullptr) *size = content.size();
  return fnv1a64(content);
}

std::string to_hex(std::uint64_t h) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i) {
    s[static_cast<std::size_t>(i)] = digits[h & 0xFU];
    h >>= 4;
  }
  return s;
}

}  // namespace millnet::datasets
