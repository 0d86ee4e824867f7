#pragma once
// Node -> items adjacency (CSR) over regular items and non-fixed nodes.
#include <cstdint>
#include <span>
#include <vector>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// For each non-fixed node, the regular (non-wide) items touching it, in increasing index order.
struct NodeItems {
  std::vector<std::uint32_t> offsets;  // num_nodes + 1
  std::vector<std::uint32_t> items;

  std::span<const std::uint32_t> at(std::uint32_t node) const {
    return std::span<const std::uint32_t>(items).subspan(offsets[node], offsets[node + 1] - offsets[node]);
  }
  std::uint32_t count(std::uint32_t node) const { return offsets[node + 1] - offsets[node]; }
};

/// Builds the adjacency of a valid graph (counting sort, O(nodes + incidences)).
NodeItems build_node_items(const Hypergraph& g, std::uint32_t wide_threshold);

}  // namespace pbd::coloring::detail
