#include "pbd/graph_coloring/validate.hpp"

#include <string>
#include <vector>

namespace pbd::coloring {

namespace {
std::string str(std::uint64_t v) { return std::to_string(v); }
}  // namespace

std::optional<std::string> find_coloring_error(const Hypergraph& g, const Coloring& c) {
  const std::uint32_t n = g.num_items();
  if (c.color.size() != n) return "color has " + str(c.color.size()) + " entries for " + str(n) + " items";
  if (c.num_regular_colors > c.num_colors)
    return "num_regular_colors " + str(c.num_regular_colors) + " exceeds num_colors " + str(c.num_colors);
  if (c.color_offsets.size() != static_cast<std::size_t>(c.num_colors) + 1)
    return "color_offsets has " + str(c.color_offsets.size()) + " entries for " + str(c.num_colors) + " colors";
  if (c.items.size() != n) return "items has " + str(c.items.size()) + " entries for " + str(n) + " items";
  if (c.color_offsets.front() != 0 || c.color_offsets.back() != n) return std::string("color_offsets do not span the items");

  std::vector<std::uint32_t> owner(g.num_nodes, 0);       // item that holds the node in the current color
  std::vector<std::uint32_t> owner_color(g.num_nodes, 0);  // that color + 1 (0: none yet)
  for (std::uint32_t k = 0; k < c.num_colors; ++k) {
    const std::uint32_t begin = c.color_offsets[k], end = c.color_offsets[k + 1];
    if (end < begin || end > n) return "color_offsets decrease or overflow at color " + str(k);
    if (end == begin) return "color " + str(k) + " is empty";
    if (k >= c.num_regular_colors && end - begin != 1)
      return "wide color " + str(k) + " holds " + str(end - begin) + " items, expected 1";
    for (std::uint32_t p = begin; p < end; ++p) {
      const std::uint32_t i = c.items[p];
      if (i >= n) return "items lists item " + str(i) + ", out of range";
      if (c.color[i] != k)
        return "item " + str(i) + " is listed under color " + str(k) + " but has color " + str(c.color[i]);
      if (p > begin && c.items[p - 1] >= i) return "items of color " + str(k) + " are not in increasing index order";
      for (std::uint32_t node : g.item(i)) {
        if (g.is_fixed(node)) continue;
        if (owner_color[node] == k + 1)
          return "items " + str(owner[node]) + " and " + str(i) + " both have color " + str(k) + " and share node " +
                 str(node);
        owner_color[node] = k + 1;
        owner[node] = i;
      }
    }
  }
  return std::nullopt;
}

}  // namespace pbd::coloring
