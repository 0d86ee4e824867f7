#pragma once
/// \file hypergraph.hpp
/// The input: items (constraints) each touching a few nodes (particles), as a non-owning CSR view.
#include <cstdint>
#include <span>
#include <vector>

namespace pbd::coloring {

/// Non-owning CSR view of items and the nodes they touch; two items conflict when they share a
/// node that is not fixed.
struct Hypergraph {
  std::span<const std::uint32_t> offsets;  ///< num_items + 1 entries (or empty: no items); item i touches nodes[offsets[i], offsets[i+1])
  std::span<const std::uint32_t> nodes;    ///< node indices of every item, item after item
  std::uint32_t num_nodes = 0;             ///< valid node indices are 0 .. num_nodes - 1
  std::span<const std::uint8_t> fixed;     ///< empty (none fixed) or num_nodes flags; nonzero = node never conflicts (pinned)

  /// Number of items.
  [[nodiscard]] std::uint32_t num_items() const {
    return offsets.empty() ? 0u : static_cast<std::uint32_t>(offsets.size() - 1);
  }
  /// Nodes touched by item i.
  [[nodiscard]] std::span<const std::uint32_t> item(std::uint32_t i) const {
    return nodes.subspan(offsets[i], offsets[i + 1] - offsets[i]);
  }
  /// True when node n never conflicts.
  [[nodiscard]] bool is_fixed(std::uint32_t n) const { return !fixed.empty() && fixed[n] != 0; }
};

/// Throws Error unless offsets start at 0, never decrease and end at nodes.size(), every node index
/// is below num_nodes, no item repeats a node, and fixed is empty or has num_nodes entries.
void validate(const Hypergraph& graph);

/// Offsets for num_items items of nodes_per_item nodes each (e.g. 2 for distance constraints).
[[nodiscard]] std::vector<std::uint32_t> uniform_offsets(std::uint32_t num_items,
                                                         std::uint32_t nodes_per_item);

}  // namespace pbd::coloring
