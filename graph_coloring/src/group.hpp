#pragma once
// Grouping of items by color (CSR).
#include "pbd/graph_coloring/coloring.hpp"

namespace pbd::coloring::detail {

/// Rebuilds color_offsets and items from color and num_colors (counting sort: by color, then index).
void group_by_color(Coloring& coloring);

}  // namespace pbd::coloring::detail
