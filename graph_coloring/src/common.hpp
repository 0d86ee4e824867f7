#pragma once
// Internal helpers shared by the coloring modules.
#include <cstdint>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// Marks an item that has no color yet.
inline constexpr std::uint32_t kUncolored = 0xFFFFFFFFu;

/// True when item i touches more than wide_threshold nodes.
inline bool is_wide(const Hypergraph& g, std::uint32_t i, std::uint32_t wide_threshold) {
  return g.offsets[i + 1] - g.offsets[i] > wide_threshold;
}

/// splitmix64 (Steele, Lea, Flood 2014): a fixed 64-bit mixer, identical on every platform.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Random priority of item i for a seed: items are processed in increasing (priority, index).
inline std::uint32_t priority(std::uint64_t seed, std::uint32_t i) {
  return static_cast<std::uint32_t>(splitmix64(splitmix64(seed) + i) >> 32);
}

}  // namespace pbd::coloring::detail
