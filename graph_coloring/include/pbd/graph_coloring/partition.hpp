#pragma once
/// \file partition.hpp
/// Graph partitioning: splits the nodes (particles) into blocks of about equal item count, cutting few items, for
/// block Gauss-Seidel (items inside one block are processed by that block's task, cut items are colored apart).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring {

/// How partition() splits the nodes.
enum class PartitionMethod : std::uint8_t {
  metis,         ///< METIS k-way on the nodes' adjacency (edge weight = hyperedges shared by the pair)
  index_ranges,  ///< contiguous ranges of node indices of about equal weight (the baseline: no graph algorithm)
};

/// "This node is in no block": fixed nodes and nodes no hyperedge touches.
inline constexpr std::uint32_t kNoBlock = ~std::uint32_t(0);

/// What partition() does.
struct PartitionOptions {
  PartitionMethod method = PartitionMethod::metis;  ///< the algorithm
  std::uint32_t parts = 1;                          ///< blocks wanted, ≥ 1 (clamped to the number of movable touched nodes)
};

/// The result: a block per node.
struct Partition {
  std::vector<std::uint32_t> block;  ///< per node: its block in [0, parts), or kNoBlock
  std::uint32_t parts = 0;           ///< number of blocks (every block in [0, parts) holds at least one node)
};

/// Splits the movable (non-fixed) nodes touched by some item of `graph` into `options.parts` blocks of about equal
/// weight (a node's weight = the number of items touching it, so blocks hold about equal numbers of items), cutting
/// few items (an item is cut when its movable nodes lie in more than one block). Deterministic. Blocks are numbered
/// in order of their smallest node; a block left empty is dropped, so `parts` may come out below the request (and is
/// 0 when no movable node is touched). Items of more than 64 movable nodes weigh on their nodes but add no edges for
/// METIS (a clique of k² edges; such an item spans many blocks anyway). Throws Error (graph_coloring's exception,
/// error.hpp) on an invalid graph, parts == 0, or a METIS failure (message says which).
[[nodiscard]] Partition partition(const Hypergraph& graph, const PartitionOptions& options);

/// The items of `graph` whose movable nodes lie in more than one block (an item with at most one movable node is
/// never cut). Throws Error on an invalid graph or a partition whose block vector is not num_nodes long.
[[nodiscard]] std::size_t cut_items(const Hypergraph& graph, const Partition& partition);

}  // namespace pbd::coloring
