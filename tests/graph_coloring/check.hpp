#pragma once
// Checks shared by the graph_coloring tests: the validator plus bounds computed independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring::testing {

/// Largest conflict degree among regular items: the number of distinct other regular items sharing
/// a non-fixed node with it (computed by brute force over node lists, independent of the library).
inline std::uint32_t max_conflict_degree(const Hypergraph& g, std::uint32_t wide_threshold = 64) {
  const std::uint32_t n = g.num_items();
  auto regular = [&](std::uint32_t i) { return g.item(i).size() <= wide_threshold; };
  std::vector<std::vector<std::uint32_t>> at(g.num_nodes);
  for (std::uint32_t i = 0; i < n; ++i)
    if (regular(i))
      for (std::uint32_t v : g.item(i))
        if (g.fixed.empty() || !g.fixed[v]) at[v].push_back(i);
  std::uint32_t best = 0;
  std::vector<std::uint32_t> neighbors;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!regular(i)) continue;
    neighbors.clear();
    for (std::uint32_t v : g.item(i))
      if (g.fixed.empty() || !g.fixed[v])
        for (std::uint32_t j : at[v])
          if (j != i) neighbors.push_back(j);
    std::sort(neighbors.begin(), neighbors.end());
    best = std::max(best, static_cast<std::uint32_t>(std::unique(neighbors.begin(), neighbors.end()) - neighbors.begin()));
  }
  return best;
}

/// Number of items touching more than wide_threshold nodes.
inline std::uint32_t count_wide(const Hypergraph& g, std::uint32_t wide_threshold = 64) {
  std::uint32_t count = 0;
  for (std::uint32_t i = 0; i < g.num_items(); ++i) count += g.item(i).size() > wide_threshold ? 1 : 0;
  return count;
}

/// Proper, complete, wide items alone, and within the greedy bound.
inline void expect_good(const Hypergraph& g, const Coloring& c, std::uint32_t wide_threshold = 64) {
  EXPECT_EQ(find_coloring_error(g, c), std::nullopt);
  EXPECT_EQ(c.num_colors - c.num_regular_colors, count_wide(g, wide_threshold));
  EXPECT_LE(c.num_regular_colors, max_conflict_degree(g, wide_threshold) + 1);
  EXPECT_GE(c.num_regular_colors, color_lower_bound(g, wide_threshold));
}

}  // namespace pbd::coloring::testing
