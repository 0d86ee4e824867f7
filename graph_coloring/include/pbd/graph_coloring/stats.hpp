#pragma once
/// \file stats.hpp
/// Statistics of a coloring and a human-readable table of them.
#include <cstdint>
#include <span>
#include <string>

#include "pbd/graph_coloring/coloring.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring {

/// Figures that describe a coloring. Batch sizes cover the regular colors only.
struct Stats {
  std::uint32_t num_items = 0;       ///< items colored
  std::uint32_t num_colors = 0;      ///< colors, wide ones included
  std::uint32_t num_wide = 0;        ///< wide items (one color each)
  std::uint32_t lower_bound = 0;     ///< most regular items sharing one non-fixed node (at least 1 if any regular item)
  std::uint32_t min_batch = 0;       ///< smallest regular color
  double mean_batch = 0.0;           ///< mean regular color size
  std::uint32_t max_batch = 0;       ///< largest regular color
  double max_over_mean = 0.0;        ///< max_batch / mean_batch (1 is perfectly balanced; 0 if no regular color)
  double seconds = 0.0;              ///< time color() took
};

/// Statistics of a coloring of graph.
[[nodiscard]] Stats compute_stats(const Hypergraph& graph, const Coloring& coloring);

/// Lower bound on the regular colors: most items of at most wide_threshold nodes sharing one non-fixed node.
[[nodiscard]] std::uint32_t color_lower_bound(const Hypergraph& graph, std::uint32_t wide_threshold = 64);

/// One row of a statistics table.
struct NamedStats {
  std::string name;  ///< row label, e.g. a constraint type or "overall"
  Stats stats;       ///< its figures
};

/// A fixed-width text table, one line per row, with a header line; ends with a newline.
[[nodiscard]] std::string format_stats(std::span<const NamedStats> rows);

}  // namespace pbd::coloring
