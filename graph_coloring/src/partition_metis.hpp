#pragma once
// The nodes partition() splits, and the METIS back end that splits them.
#include <cstdint>
#include <vector>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::detail {

/// The movable (non-fixed) nodes some item touches, renumbered compactly in increasing node order.
struct MovableNodes {
  std::vector<std::uint32_t> node;    ///< local index -> graph node (increasing)
  std::vector<std::uint32_t> local;   ///< graph node -> local index, or kNoBlock (fixed or untouched)
  std::vector<std::uint32_t> weight;  ///< local index -> number of items touching the node (≥ 1)
};

/// Items of more movable nodes than this add no edges to the METIS graph (their clique would have k² edges).
inline constexpr std::uint32_t kMetisCliqueLimit = 64;

/// METIS's block (in [0, parts), possibly leaving some empty) of every local node. 2 ≤ parts ≤ nodes.node.size().
/// Deterministic (fixed seed, serial). Throws Error when the graph exceeds METIS's index type or METIS fails.
std::vector<std::uint32_t> metis_blocks(const Hypergraph& g, const MovableNodes& nodes, std::uint32_t parts);

}  // namespace pbd::coloring::detail
