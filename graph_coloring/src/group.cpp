#include "group.hpp"

namespace pbd::coloring::detail {

void group_by_color(Coloring& c) {
  c.color_offsets.assign(static_cast<std::size_t>(c.num_colors) + 1, 0);
  for (std::uint32_t col : c.color) ++c.color_offsets[col + 1];
  for (std::uint32_t k = 0; k < c.num_colors; ++k) c.color_offsets[k + 1] += c.color_offsets[k];
  c.items.resize(c.color.size());
  std::vector<std::uint32_t> cursor(c.color_offsets.begin(), c.color_offsets.end() - 1);
  const auto n = static_cast<std::uint32_t>(c.color.size());
  for (std::uint32_t i = 0; i < n; ++i) c.items[cursor[c.color[i]]++] = i;
}

}  // namespace pbd::coloring::detail
