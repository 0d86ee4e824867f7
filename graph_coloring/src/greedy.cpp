// First-fit coloring with one 64-bit mask of used colors per node.
//
// Each node keeps a mask of the colors 0..63 already given to items touching it. An item's first
// free color is the lowest zero bit of the OR of its nodes' masks: a few loads and one count of
// trailing zeros per item, whatever the number of colors, O(incidences) in total. Fixed nodes are
// never read, so they never forbid a color. Colors from 64 on (only when many items share a node)
// live in per-node overflow words, allocated when first needed, with a per-node hint to the first
// word that still has a free color.
#include "greedy.hpp"

#include <algorithm>
#include <bit>
#include <memory>
#include <vector>

#include "common.hpp"

namespace pbd::coloring::detail {

namespace {

constexpr std::uint64_t kFull = ~std::uint64_t{0};

// Colors >= 64 of each node: word w - 1 holds colors [64w, 64w + 64).
struct Overflow {
  std::vector<std::vector<std::uint64_t>> words;
  std::vector<std::uint32_t> first_open;  // per node: every word below this one is full (>= 1)

  explicit Overflow(std::uint32_t num_nodes) : words(num_nodes), first_open(num_nodes, 1) {}

  std::uint64_t word(std::uint32_t node, std::uint32_t w) const {
    const auto& v = words[node];
    return w - 1 < v.size() ? v[w - 1] : 0;
  }
  void set(std::uint32_t node, std::uint32_t c) {
    const std::uint32_t w = c / 64;
    auto& v = words[node];
    if (v.size() < w) v.resize(w, 0);
    v[w - 1] |= std::uint64_t{1} << (c % 64);
    while (first_open[node] - 1 < v.size() && v[first_open[node] - 1] == kFull) ++first_open[node];
  }
};

// Lowest color >= 64 free at every non-fixed node of item.
template <bool kHasFixed>
std::uint32_t first_free_overflow(const Hypergraph& g, std::span<const std::uint32_t> item, const Overflow& of) {
  std::uint32_t w = 1;
  for (std::uint32_t node : item)
    if (!(kHasFixed && g.fixed[node])) w = std::max(w, of.first_open[node]);
  for (;; ++w) {
    std::uint64_t used = 0;
    for (std::uint32_t node : item)
      if (!(kHasFixed && g.fixed[node])) used |= of.word(node, w);
    if (used != kFull) return 64 * w + static_cast<std::uint32_t>(std::countr_one(used));
  }
}

template <bool kHasFixed, bool kHasOrder>
std::uint32_t run(const Hypergraph& g, std::uint32_t wide_threshold, std::span<const std::uint32_t> order,
                  std::span<std::uint32_t> color, std::uint32_t& num_wide) {
  num_wide = 0;
  std::vector<std::uint64_t> mask(g.num_nodes, 0);
  std::unique_ptr<Overflow> overflow;  // only when some item needs a color >= 64
  const std::uint32_t* off = g.offsets.data();
  const std::uint32_t* nodes = g.nodes.data();
  const std::uint32_t count = kHasOrder ? static_cast<std::uint32_t>(order.size()) : g.num_items();
  std::uint32_t num_colors = 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t i = kHasOrder ? order[k] : k;
    const std::uint32_t b = off[i], e = off[i + 1];
    if (e - b > wide_threshold) {
      color[i] = kUncolored;
      ++num_wide;
      continue;
    }
    if (e - b == 2) {  // the common case (distance constraints), without the inner loops
      const std::uint32_t u = nodes[b], v = nodes[b + 1];
      std::uint64_t& mu = mask[u];
      std::uint64_t& mv = mask[v];
      const std::uint64_t used = (kHasFixed && g.fixed[u] ? 0 : mu) | (kHasFixed && g.fixed[v] ? 0 : mv);
      if (used != kFull) {
        const auto c = static_cast<std::uint32_t>(std::countr_one(used));
        const std::uint64_t bit = std::uint64_t{1} << c;
        mu |= bit;
        mv |= bit;
        color[i] = c;
        num_colors = std::max(num_colors, c + 1);
        continue;
      }
    }
    std::uint64_t used = 0;
    for (std::uint32_t p = b; p < e; ++p)
      if (!(kHasFixed && g.fixed[nodes[p]])) used |= mask[nodes[p]];
    std::uint32_t c;
    if (used != kFull) {
      c = static_cast<std::uint32_t>(std::countr_one(used));
      const std::uint64_t bit = std::uint64_t{1} << c;
      for (std::uint32_t p = b; p < e; ++p) mask[nodes[p]] |= bit;  // fixed nodes' masks are never read
    } else {
      if (!overflow) overflow = std::make_unique<Overflow>(g.num_nodes);
      const auto item = g.nodes.subspan(b, e - b);
      c = first_free_overflow<kHasFixed>(g, item, *overflow);
      for (std::uint32_t node : item) overflow->set(node, c);
    }
    color[i] = c;
    num_colors = std::max(num_colors, c + 1);
  }
  return num_colors;
}

}  // namespace

std::uint32_t first_fit(const Hypergraph& g, std::uint32_t wide_threshold, std::span<const std::uint32_t> order,
                        std::span<std::uint32_t> color, std::uint32_t& num_wide) {
  const bool has_fixed = !g.fixed.empty();
  if (order.empty()) {
    return has_fixed ? run<true, false>(g, wide_threshold, order, color, num_wide)
                     : run<false, false>(g, wide_threshold, order, color, num_wide);
  }
  std::fill(color.begin(), color.end(), kUncolored);  // items outside order (wide ones) stay uncolored
  std::uint32_t ordered_wide = 0;
  const std::uint32_t num_colors = has_fixed ? run<true, true>(g, wide_threshold, order, color, ordered_wide)
                                             : run<false, true>(g, wide_threshold, order, color, ordered_wide);
  num_wide = g.num_items() - static_cast<std::uint32_t>(order.size()) + ordered_wide;
  return num_colors;
}

}  // namespace pbd::coloring::detail
