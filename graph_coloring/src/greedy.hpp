#pragma once
// Serial first-fit coloring in a given order.
#include <cstdint>
#include <span>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// Gives each regular item of order (all items in index order if order is empty) the smallest color
/// no earlier item at one of its non-fixed nodes has. Wide items are left kUncolored. color must
/// have num_items entries. Returns the number of colors used and counts wide items in num_wide.
std::uint32_t first_fit(const Hypergraph& g, std::uint32_t wide_threshold, std::span<const std::uint32_t> order,
                        std::span<std::uint32_t> color, std::uint32_t& num_wide);

}  // namespace pbd::coloring::detail
