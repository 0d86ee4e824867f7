#include "node_items.hpp"

#include "common.hpp"

namespace pbd::coloring::detail {

NodeItems build_node_items(const Hypergraph& g, std::uint32_t wide_threshold) {
  NodeItems adj;
  adj.offsets.assign(static_cast<std::size_t>(g.num_nodes) + 1, 0);
  const std::uint32_t n = g.num_items();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_wide(g, i, wide_threshold)) continue;
    for (std::uint32_t node : g.item(i))
      if (!g.is_fixed(node)) ++adj.offsets[node + 1];
  }
  for (std::uint32_t v = 0; v < g.num_nodes; ++v) adj.offsets[v + 1] += adj.offsets[v];
  adj.items.resize(adj.offsets[g.num_nodes]);
  std::vector<std::uint32_t> cursor(adj.offsets.begin(), adj.offsets.end() - 1);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_wide(g, i, wide_threshold)) continue;
    for (std::uint32_t node : g.item(i))
      if (!g.is_fixed(node)) adj.items[cursor[node]++] = i;
  }
  return adj;
}

}  // namespace pbd::coloring::detail
