// Balancing (after Fratarcangeli & Pellacini 2015; NVIDIA Warp balances to max/min <= 1.1).
//
// Greedy colorings are lopsided: the first colors are large, the last ones small. Let mean be the
// mean regular batch size, fill = ceil(mean) and cap = max(fill, floor(target x mean)). Visiting
// items in index order, an item whose color holds more than cap items may move to the smallest color
// (ties: lowest color) that holds fewer than fill items and that no item sharing one of its
// non-fixed nodes has. Donors never drop below cap and receivers never rise above fill, so no color
// empties and none is added; passes repeat until the largest batch is at most cap or a pass moves
// nothing.
// Which items move: a donor's excess is spread evenly over its items in index order (the t-th of its
// s items is due to move when floor((t + 1) x excess / s) exceeds the moves made so far; an item that
// finds no receiver passes its turn to the next). Items are usually numbered in a spatially coherent
// order, so every color then keeps the spread over the index range it had; moving the first items
// instead would leave donors without their first index range and receivers with nothing else, and a
// parallel loop that cuts each color into equal parts would cut each color in a different place. Conflicts are looked up in per-node 64-bit color masks when there are at most 64
// regular colors, otherwise through the node -> items adjacency.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common.hpp"
#include "group.hpp"
#include "node_items.hpp"
#include "pbd/graph_coloring/color.hpp"
#include "pbd/graph_coloring/error.hpp"

namespace pbd::coloring {

namespace {

double ratio(const std::vector<std::uint32_t>& size, std::uint64_t total) {
  if (size.empty() || total == 0) return 0.0;
  const double mean = static_cast<double>(total) / static_cast<double>(size.size());
  return *std::max_element(size.begin(), size.end()) / mean;
}

// Smallest allowed receiver for an item of color a, or kUncolored.
template <class Allowed>
std::uint32_t pick(const std::vector<std::uint32_t>& size, std::uint32_t a, std::uint32_t fill, Allowed allowed) {
  std::uint32_t best = detail::kUncolored;
  for (std::uint32_t b = 0; b < size.size(); ++b)
    if (b != a && size[b] < fill && (best == detail::kUncolored || size[b] < size[best]) && allowed(b)) best = b;
  return best;
}

}  // namespace

double balance(const Hypergraph& g, Coloring& coloring, double target) {
  if (!(target >= 1.0)) throw Error("graph_coloring: balance target must be >= 1, got " + std::to_string(target));
  const std::uint32_t k = coloring.num_regular_colors;
  std::vector<std::uint32_t> size(k);
  std::uint64_t total = 0;
  for (std::uint32_t c = 0; c < k; ++c) total += size[c] = coloring.size_of(c);
  if (k <= 1) return ratio(size, total);
  const double mean = static_cast<double>(total) / k;
  const auto fill = static_cast<std::uint32_t>(std::ceil(mean));
  const std::uint32_t cap = std::max(fill, static_cast<std::uint32_t>(std::floor(target * mean)));
  auto largest = [&] { return *std::max_element(size.begin(), size.end()); };
  if (largest() <= cap) return ratio(size, total);

  auto& color = coloring.color;
  const std::uint32_t n = g.num_items();
  constexpr int kMaxPasses = 8;
  // Per donor, this pass: its size and excess when the pass began, items visited, moves made.
  std::vector<std::uint64_t> start(k), excess(k), seen(k), made(k);
  auto begin_pass = [&] {
    for (std::uint32_t c = 0; c < k; ++c) {
      start[c] = size[c];
      excess[c] = size[c] > cap ? size[c] - cap : 0;
      seen[c] = made[c] = 0;
    }
  };
  auto due = [&](std::uint32_t a) {  // the next item of donor a is due to move (spread evenly over its items)
    const std::uint64_t t = seen[a]++;
    return (t + 1) * excess[a] / start[a] > made[a];
  };
  if (k <= 64) {
    std::vector<std::uint64_t> mask(g.num_nodes, 0);
    for (std::uint32_t i = 0; i < n; ++i)
      if (color[i] < k)
        for (std::uint32_t node : g.item(i)) mask[node] |= std::uint64_t{1} << color[i];
    for (int pass = 0; pass < kMaxPasses && largest() > cap; ++pass) {
      bool moved = false;
      begin_pass();
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t a = color[i];
        if (a >= k || size[a] <= cap || !due(a)) continue;
        std::uint64_t used = 0;
        for (std::uint32_t node : g.item(i))
          if (!g.is_fixed(node)) used |= mask[node];
        const std::uint32_t b = pick(size, a, fill, [&](std::uint32_t c) { return ((used >> c) & 1u) == 0; });
        if (b == detail::kUncolored) continue;
        const std::uint64_t flip = (std::uint64_t{1} << a) | (std::uint64_t{1} << b);
        for (std::uint32_t node : g.item(i)) mask[node] ^= flip;
        color[i] = b;
        --size[a];
        ++size[b];
        ++made[a];
        moved = true;
      }
      if (!moved) break;
    }
  } else {
    // Wide items are in the adjacency too (any threshold would do) but are skipped by color.
    const auto adj = detail::build_node_items(g, 0xFFFFFFFFu);
    std::vector<std::uint32_t> stamp(k, 0);  // stamp[c] == tick: a neighbor of the current item has color c
    std::uint32_t tick = 0;
    for (int pass = 0; pass < kMaxPasses && largest() > cap; ++pass) {
      bool moved = false;
      begin_pass();
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t a = color[i];
        if (a >= k || size[a] <= cap || !due(a)) continue;
        if (++tick == 0) {  // wrapped: forget every old mark
          std::fill(stamp.begin(), stamp.end(), 0);
          tick = 1;
        }
        for (std::uint32_t node : g.item(i))
          if (!g.is_fixed(node))
            for (std::uint32_t j : adj.at(node))
              if (color[j] < k) stamp[color[j]] = tick;
        const std::uint32_t b = pick(size, a, fill, [&](std::uint32_t c) { return stamp[c] != tick; });
        if (b == detail::kUncolored) continue;
        color[i] = b;
        --size[a];
        ++size[b];
        ++made[a];
        moved = true;
      }
      if (!moved) break;
    }
  }
  detail::group_by_color(coloring);
  return ratio(size, total);
}

}  // namespace pbd::coloring
