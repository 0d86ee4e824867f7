#include "group.hpp"

namespace pbd::coloring::detail {

void group_by_color(Coloring& c) {
  const auto n = static_cast<std::uint32_t>(c.color.size());
  c.color_offsets.assign(static_cast<std::size_t>(c.num_colors) + 1, 0);
  c.items.resize(n);
  const std::uint32_t* color = c.color.data();
  std::uint32_t* offsets = c.color_offsets.data();
  std::uint32_t* items = c.items.data();
  for (std::uint32_t i = 0; i < n; ++i) ++offsets[color[i] + 1];
  for (std::uint32_t k = 0; k < c.num_colors; ++k) offsets[k + 1] += offsets[k];
  std::vector<std::uint32_t> cursor(c.color_offsets.begin(), c.color_offsets.end() - 1);
  std::uint32_t* next = cursor.data();
  for (std::uint32_t i = 0; i < n; ++i) items[next[color[i]]++] = i;
}

}  // namespace pbd::coloring::detail
