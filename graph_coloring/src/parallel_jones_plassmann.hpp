#pragma once
// Parallel Jones–Plassmann coloring with seeded random priorities (oneTBB).
#include <cstdint>
#include <span>

#include "node_items.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// Colors every regular item exactly as first_fit over random_order(g, seed) would, in parallel
/// rounds; wide items are left kUncolored and counted in num_wide. Returns the number of colors used.
std::uint32_t jones_plassmann(const Hypergraph& g, std::uint32_t wide_threshold, std::uint64_t seed,
                              const NodeItems& adj, std::span<std::uint32_t> color, std::uint32_t& num_wide);

}  // namespace pbd::coloring::detail
