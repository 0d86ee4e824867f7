#include "pbd/graph_coloring/hypergraph.hpp"

#include <algorithm>
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
  // One pass over the items (the input is read once: this is memory-bound for large inputs).
  const std::uint32_t n = g.num_items();
  const std::uint32_t* off = g.offsets.data();
  const std::uint32_t* nodes = g.nodes.data();
  const std::uint32_t num_nodes = g.num_nodes;
  const std::size_t total = g.nodes.size();
  auto out_of_range = [&](std::uint32_t i, std::uint32_t node) {
    fail("item " + std::to_string(i) + " touches node " + std::to_string(node) + ", out of range (num_nodes " +
         std::to_string(num_nodes) + ")");
  };
  auto repeated = [&](std::uint32_t i, std::uint32_t node) {
    fail("item " + std::to_string(i) + " touches node " + std::to_string(node) + " twice");
  };
  std::vector<std::uint32_t> stamp;  // stamp[node] = item + 1 that last touched it (large items only)
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t b = off[i], e = off[i + 1];
    if (e < b || e > total)
      fail("offsets decrease at item " + std::to_string(i) + " (" + std::to_string(b) + " then " + std::to_string(e) +
           ")");
    const std::uint32_t k = e - b;
    if (k == 2) {  // the common case: distance constraints
      const std::uint32_t u = nodes[b], v = nodes[b + 1];
      if (u >= num_nodes || v >= num_nodes) out_of_range(i, u >= num_nodes ? u : v);
      if (u == v) repeated(i, u);
    } else if (k <= 8) {
      for (std::uint32_t x = 0; x < k; ++x) {
        if (nodes[b + x] >= num_nodes) out_of_range(i, nodes[b + x]);
        for (std::uint32_t y = 0; y < x; ++y)
          if (nodes[b + x] == nodes[b + y]) repeated(i, nodes[b + x]);
      }
    } else {
      if (stamp.empty()) stamp.assign(num_nodes, 0);
      for (std::uint32_t p = b; p < e; ++p) {
        if (nodes[p] >= num_nodes) out_of_range(i, nodes[p]);
        if (stamp[nodes[p]] == i + 1) repeated(i, nodes[p]);
        stamp[nodes[p]] = i + 1;
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
