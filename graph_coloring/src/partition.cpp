// partition() and cut_items(): validation, the nodes to split and their weights, the index-range baseline, the
// dispatch to METIS, and the final numbering of the blocks (by smallest node, empty blocks dropped).
#include "pbd/graph_coloring/partition.hpp"

#include <algorithm>
#include <string>

#include "partition_metis.hpp"
#include "pbd/graph_coloring/error.hpp"

namespace pbd::coloring {

namespace {

[[noreturn]] void fail(const std::string& message) { throw Error("graph_coloring: partition: " + message); }

detail::MovableNodes movable_touched_nodes(const Hypergraph& g) {
  std::vector<std::uint32_t> count(g.num_nodes, 0);
  for (std::uint32_t v : g.nodes)
    if (!g.is_fixed(v)) ++count[v];
  detail::MovableNodes m;
  m.local.assign(g.num_nodes, kNoBlock);
  for (std::uint32_t v = 0; v < g.num_nodes; ++v)
    if (count[v] > 0) {
      m.local[v] = static_cast<std::uint32_t>(m.node.size());
      m.node.push_back(v);
      m.weight.push_back(count[v]);
    }
  return m;
}

// Consecutive local nodes into `parts` ranges of about equal weight: a node goes to the range its weight's midpoint
// falls in (so a range may come out empty when single nodes outweigh a range's share).
std::vector<std::uint32_t> index_range_blocks(const detail::MovableNodes& m, std::uint32_t parts) {
  std::uint64_t total = 0;
  for (std::uint32_t w : m.weight) total += w;
  std::vector<std::uint32_t> blocks(m.node.size());
  std::uint64_t before = 0;  // weight of the nodes before this one
  for (std::size_t u = 0; u < m.node.size(); ++u) {
    const double middle = (static_cast<double>(before) + 0.5 * m.weight[u]) / static_cast<double>(total);
    blocks[u] = std::min(parts - 1, static_cast<std::uint32_t>(middle * parts));
    before += m.weight[u];
  }
  return blocks;
}

}  // namespace

Partition partition(const Hypergraph& g, const PartitionOptions& options) {
  validate(g);
  if (options.parts == 0) fail("parts is 0, expected at least 1");
  const detail::MovableNodes m = movable_touched_nodes(g);
  const auto n = static_cast<std::uint32_t>(m.node.size());
  const std::uint32_t parts = std::min(options.parts, n);

  std::vector<std::uint32_t> raw;  // block of each local node, before numbering
  if (parts <= 1) {
    raw.assign(n, 0);
  } else if (options.method == PartitionMethod::metis) {
    raw = detail::metis_blocks(g, m, parts);
  } else if (options.method == PartitionMethod::index_ranges) {
    raw = index_range_blocks(m, parts);
  } else {
    fail("unknown method " + std::to_string(static_cast<int>(options.method)));
  }

  // Number the blocks in order of their smallest node (local order is node order); unused numbers vanish.
  Partition result;
  result.block.assign(g.num_nodes, kNoBlock);
  std::vector<std::uint32_t> renumber(std::max(parts, 1u), kNoBlock);
  for (std::uint32_t u = 0; u < n; ++u) {
    std::uint32_t& b = renumber[raw[u]];
    if (b == kNoBlock) b = result.parts++;
    result.block[m.node[u]] = b;
  }
  return result;
}

std::size_t cut_items(const Hypergraph& g, const Partition& p) {
  validate(g);
  if (p.block.size() != g.num_nodes)
    fail("partition.block has " + std::to_string(p.block.size()) + " entries, expected num_nodes = " +
         std::to_string(g.num_nodes));
  std::size_t cut = 0;
  for (std::uint32_t i = 0; i < g.num_items(); ++i) {
    std::uint32_t first = kNoBlock;
    bool any = false;
    for (std::uint32_t v : g.item(i)) {
      if (g.is_fixed(v)) continue;
      if (!any) {
        first = p.block[v], any = true;
      } else if (p.block[v] != first) {
        ++cut;
        break;
      }
    }
  }
  return cut;
}

}  // namespace pbd::coloring
