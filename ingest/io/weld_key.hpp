#pragma once
// Vertices joined by the exact bits of their coordinates (binary STL's floats, a tessellation's
// doubles): the key of the index that welds a triangle soup into a shared-vertex mesh. Private to
// the ingest I/O adapter.
#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace millnet::ingest::detail {

/// The three coordinates' bit patterns (Word = std::uint32_t for floats, std::uint64_t for doubles).
template <class Word>
struct WeldKey {
  Word a, b, c;
  bool operator==(const WeldKey&) const = default;
};

struct WeldKeyHash {
  template <class Word>
  std::size_t operator()(const WeldKey<Word>& k) const noexcept {
    std::uint64_t h = static_cast<std::uint64_t>(k.a) * 0x9E3779B97F4A7C15ull;
    h ^= (static_cast<std::uint64_t>(k.b) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2));
    h ^= (static_cast<std::uint64_t>(k.c) + 0x94D049BB133111EBull + (h << 6) + (h >> 2));
    return static_cast<std::size_t>(h);
  }
};

/// Key → index of the welded vertex.
template <class Word>
using WeldIndex = std::unordered_map<WeldKey<Word>, std::int32_t, WeldKeyHash>;

}  // namespace millnet::ingest::detail
