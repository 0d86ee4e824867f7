#include "order.hpp"

#include <algorithm>
#include <functional>
#include <queue>

#include "common.hpp"

namespace pbd::coloring::detail {

std::uint32_t incidence_degree(const Hypergraph& g, const NodeItems& adj, std::uint32_t i) {
  std::uint32_t d = 0;
  for (std::uint32_t node : g.item(i))
    if (!g.is_fixed(node)) d += adj.count(node) - 1;
  return d;
}

std::vector<std::uint32_t> largest_first_order(const Hypergraph& g, const NodeItems& adj, std::uint32_t wide_threshold) {
  // Counting sort by degree (descending); scanning items in index order keeps ties by index.
  const std::uint32_t n = g.num_items();
  std::vector<std::uint32_t> degree(n, 0);
  std::uint32_t max_degree = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_wide(g, i, wide_threshold)) continue;
    degree[i] = incidence_degree(g, adj, i);
    max_degree = std::max(max_degree, degree[i]);
  }
  std::vector<std::uint32_t> start(static_cast<std::size_t>(max_degree) + 2, 0);
  std::uint32_t regular = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_wide(g, i, wide_threshold)) continue;
    ++start[max_degree - degree[i] + 1];
    ++regular;
  }
  for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
  std::vector<std::uint32_t> order(regular);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!is_wide(g, i, wide_threshold)) order[start[max_degree - degree[i]]++] = i;
  return order;
}

std::vector<std::uint32_t> smallest_last_order(const Hypergraph& g, const NodeItems& adj, std::uint32_t wide_threshold) {
  // Min-heap of (degree << 32 | index) with lazy deletion: an entry is stale once the item is
  // removed or its degree dropped below the entry's.
  const std::uint32_t n = g.num_items();
  std::vector<std::uint32_t> degree(n, 0);
  std::vector<std::uint8_t> removed(n, 0);
  std::vector<std::uint64_t> heap;
  heap.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_wide(g, i, wide_threshold)) {
      removed[i] = 1;
      continue;
    }
    degree[i] = incidence_degree(g, adj, i);
    heap.push_back((std::uint64_t{degree[i]} << 32) | i);
  }
  std::make_heap(heap.begin(), heap.end(), std::greater<>{});
  std::vector<std::uint32_t> order;
  order.reserve(heap.size());
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>{});
    const std::uint64_t top = heap.back();
    heap.pop_back();
    const auto i = static_cast<std::uint32_t>(top);
    if (removed[i] || degree[i] != static_cast<std::uint32_t>(top >> 32)) continue;
    removed[i] = 1;
    order.push_back(i);
    for (std::uint32_t node : g.item(i)) {
      if (g.is_fixed(node)) continue;
      for (std::uint32_t j : adj.at(node)) {
        if (removed[j]) continue;
        --degree[j];
        heap.push_back((std::uint64_t{degree[j]} << 32) | j);
        std::push_heap(heap.begin(), heap.end(), std::greater<>{});
      }
    }
  }
  std::reverse(order.begin(), order.end());
  return order;
}

std::vector<std::uint32_t> random_order(const Hypergraph& g, std::uint64_t seed, std::uint32_t wide_threshold) {
  // Stable LSD radix sort of the regular items (already in index order) by 32-bit priority.
  const std::uint32_t n = g.num_items();
  std::vector<std::uint32_t> order, prio;
  order.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!is_wide(g, i, wide_threshold)) order.push_back(i);
  prio.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) prio[k] = priority(seed, order[k]);
  std::vector<std::uint32_t> order2(order.size()), prio2(order.size());
  for (int shift = 0; shift < 32; shift += 16) {
    std::vector<std::uint32_t> start((1u << 16) + 1, 0);
    for (std::uint32_t p : prio) ++start[((p >> shift) & 0xFFFFu) + 1];
    for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::uint32_t at = start[(prio[k] >> shift) & 0xFFFFu]++;
      order2[at] = order[k];
      prio2[at] = prio[k];
    }
    order.swap(order2);
    prio.swap(prio2);
  }
  return order;
}

}  // namespace pbd::coloring::detail
