#pragma once
// An undirected edge between two vertex indices as one 64-bit key (the
// smaller index in the high half), for hash and ordered maps over edges.

#include <algorithm>
#include <cstdint>
#include <utility>

namespace lhr {

inline std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t{lo} << 32) | hi;
}

inline std::pair<int, int> edge_of(std::uint64_t key) {
  return {static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu)};
}

}  // namespace lhr
