#pragma once
// Orders in which first-fit visits the regular items.
#include <cstdint>
#include <vector>

#include "node_items.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// Conflict count of item i used for ordering: the number of (other regular item, shared non-fixed
/// node) pairs, i.e. its conflict degree counting an item that shares two nodes twice.
std::uint32_t incidence_degree(const Hypergraph& g, const NodeItems& adj, std::uint32_t i);

/// Regular items by decreasing incidence degree, ties by increasing index.
std::vector<std::uint32_t> largest_first_order(const Hypergraph& g, const NodeItems& adj, std::uint32_t wide_threshold);

/// Smallest-last order (Matula & Beck 1983): repeatedly remove the item of smallest remaining
/// incidence degree (ties: smallest index); color in reverse removal order.
std::vector<std::uint32_t> smallest_last_order(const Hypergraph& g, const NodeItems& adj, std::uint32_t wide_threshold);

/// Regular items by increasing (priority(seed, i), i): the order Jones–Plassmann reproduces.
std::vector<std::uint32_t> random_order(const Hypergraph& g, std::uint64_t seed, std::uint32_t wide_threshold);

}  // namespace pbd::coloring::detail
