#include "pbd/graph_coloring/hypergraph.hpp"

#include <string>

#include "pbd/graph_coloring/error.hpp"

namespace pbd::coloring {

namespace {
[[noreturn]] void fail(const std::string& message) { throw Error("graph_coloring: " + message); }
}  // namespace

void validate(const Hypergraph& g) {
  if (!g.fixed.empty() && g.fixed.size() != g.num_nodes)
    fail("fixed mask has " + std::to_string(g.fixed.size()) + " entries, expected 0 or num_nodes = " +
         std::to_string(g.num_nodes));
  if (g.offsets.empty()) {
    if (!g.nodes.empty()) fail("no offsets but " + std::to_string(g.nodes.size()) + " node indices");
    return;
  }
  if (g.offsets.size() - 1 >= 0xFFFFFFFFull) fail("too many items");
  if (g.offsets.front() != 0) fail("offsets[0] is " + std::to_string(g.offsets.front()) + ", expected 0");
  if (g.offsets.back() != g.nodes.size())
    fail("offsets end at " + std::to_string(g.offsets.back()) + " but there are " +
         std::to_string(g.nodes.size()) + " node indices");
  const std::uint32_t n = g.num_items();
  for (std::uint32_t i = 0; i < n; ++i)
    if (g.offsets[i + 1] < g.offsets[i])
      fail("offsets decrease at item " + std::to_string(i) + " (" + std::to_string(g.offsets[i]) + " then " +
           std::to_string(g.offsets[i + 1]) + ")");
  std::vector<std::uint32_t> stamp;  // stamp[node] = item + 1 that last touched it (large items only)
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto item = g.item(i);
    for (std::uint32_t node : item)
      if (node >= g.num_nodes)
        fail("item " + std::to_string(i) + " touches node " + std::to_string(node) + ", out of range (num_nodes " +
             std::to_string(g.num_nodes) + ")");
    if (item.size() <= 8) {
      for (std::size_t a = 1; a < item.size(); ++a)
        for (std::size_t b = 0; b < a; ++b)
          if (item[a] == item[b]) fail("item " + std::to_string(i) + " touches node " + std::to_string(item[a]) + " twice");
    } else {
      if (stamp.empty()) stamp.assign(g.num_nodes, 0);
      for (std::uint32_t node : item) {
        if (stamp[node] == i + 1) fail("item " + std::to_string(i) + " touches node " + std::to_string(node) + " twice");
        stamp[node] = i + 1;
      }
    }
  }
}

std::vector<std::uint32_t> uniform_offsets(std::uint32_t num_items, std::uint32_t nodes_per_item) {
  std::vector<std::uint32_t> offsets(static_cast<std::size_t>(num_items) + 1);
  for (std::uint32_t i = 0; i <= num_items; ++i) offsets[i] = i * nodes_per_item;
  return offsets;
}

}  // namespace pbd::coloring
