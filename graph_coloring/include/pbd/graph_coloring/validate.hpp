#pragma once
/// \file validate.hpp
/// The validator: checks that a coloring is proper, complete and consistently grouped.
#include <optional>
#include <string>

#include "pbd/graph_coloring/coloring.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring {

/// The first problem found in coloring (two items of one color sharing a non-fixed node, an item
/// missing or listed twice, a wide color holding more than one item, inconsistent sizes), or
/// nullopt when the coloring is proper and complete. The graph must be valid.
[[nodiscard]] std::optional<std::string> find_coloring_error(const Hypergraph& graph, const Coloring& coloring);

}  // namespace pbd::coloring
