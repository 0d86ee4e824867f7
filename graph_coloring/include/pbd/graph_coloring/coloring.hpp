#pragma once
/// \file coloring.hpp
/// The result: a color per item and the items grouped by color.
#include <cstdint>
#include <span>
#include <vector>

namespace pbd::coloring {

/// A coloring: no two items of one color share a non-fixed node.
///
/// Wide-item rule: an item touching more than Options::wide_threshold nodes (a volume constraint
/// spanning a mesh) is "wide". Wide items never take part in the first-fit coloring: colors
/// [0, num_regular_colors) hold only the regular items, and each wide item gets a color of its own
/// after them, in item-index order. A wide item therefore never raises the color count of the
/// others; the caller projects it alone, with parallelism inside the item.
struct Coloring {
  std::vector<std::uint32_t> color;          ///< color of each item
  std::vector<std::uint32_t> color_offsets;  ///< num_colors + 1 entries: color c holds items[color_offsets[c], color_offsets[c+1])
  std::vector<std::uint32_t> items;          ///< item indices sorted by color, then by index
  std::uint32_t num_colors = 0;              ///< total number of colors, wide ones included
  std::uint32_t num_regular_colors = 0;      ///< colors below this hold regular items; the rest one wide item each
  double seconds = 0.0;                      ///< wall time color() took, validation and grouping included

  /// Items of color c, in increasing index order.
  [[nodiscard]] std::span<const std::uint32_t> items_of(std::uint32_t c) const {
    return std::span<const std::uint32_t>(items).subspan(color_offsets[c], color_offsets[c + 1] - color_offsets[c]);
  }
  /// Number of items of color c.
  [[nodiscard]] std::uint32_t size_of(std::uint32_t c) const { return color_offsets[c + 1] - color_offsets[c]; }
  /// The wide items (each alone in its color), in increasing index order.
  [[nodiscard]] std::span<const std::uint32_t> wide_items() const {
    return std::span<const std::uint32_t>(items).subspan(color_offsets[num_regular_colors]);
  }
};

}  // namespace pbd::coloring
