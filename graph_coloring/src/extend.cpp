// first_fit_extend(): first fit against per-node masks of the colors already in use (incremental coloring).
#include "pbd/graph_coloring/color.hpp"

#include <bit>

namespace pbd::coloring {

bool first_fit_extend(const Hypergraph& g, std::span<std::uint64_t> used, std::uint32_t max_colors,
                      std::span<std::uint32_t> color) {
  for (std::uint32_t i = 0; i < g.num_items(); ++i) {
    std::uint64_t taken = 0;
    for (std::uint32_t node : g.item(i))
      if (!g.is_fixed(node)) taken |= used[node];
    const auto c = static_cast<std::uint32_t>(std::countr_one(taken));
    if (c >= max_colors || c >= 64) return false;
    for (std::uint32_t node : g.item(i))
      if (!g.is_fixed(node)) used[node] |= std::uint64_t{1} << c;
    color[i] = c;
  }
  return true;
}

}  // namespace pbd::coloring
