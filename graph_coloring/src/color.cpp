// color(): validation, the chosen algorithm, the wide-item colors, grouping, optional balancing.
#include "pbd/graph_coloring/color.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "common.hpp"
#include "greedy.hpp"
#include "group.hpp"
#include "node_items.hpp"
#include "order.hpp"
#include "parallel_jones_plassmann.hpp"
#include "pbd/graph_coloring/error.hpp"

namespace pbd::coloring {

Coloring color(const Hypergraph& g, const Options& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(g);
  if (!(options.balance_target >= 1.0))
    throw Error("graph_coloring: balance_target must be >= 1, got " + std::to_string(options.balance_target));
  const std::uint32_t wide = options.wide_threshold;
  Coloring out;
  out.color.resize(g.num_items());
  std::uint32_t regular = 0;
  std::uint32_t num_wide = 0;
  switch (options.algorithm) {
    case Algorithm::greedy_input:
      regular = detail::first_fit(g, wide, {}, out.color, num_wide);
      break;
    case Algorithm::greedy_largest_first: {
      const auto adj = detail::build_node_items(g, wide);
      regular = detail::first_fit(g, wide, detail::largest_first_order(g, adj, wide), out.color, num_wide);
      break;
    }
    case Algorithm::greedy_smallest_last: {
      const auto adj = detail::build_node_items(g, wide);
      regular = detail::first_fit(g, wide, detail::smallest_last_order(g, adj, wide), out.color, num_wide);
      break;
    }
    case Algorithm::greedy_random:
      regular = detail::first_fit(g, wide, detail::random_order(g, options.seed, wide), out.color, num_wide);
      break;
    case Algorithm::jones_plassmann: {
      const auto adj = detail::build_node_items(g, wide);
      regular = detail::jones_plassmann(g, wide, options.seed, adj, out.color, num_wide);
      break;
    }
    default:
      throw Error("graph_coloring: unknown algorithm " + std::to_string(static_cast<int>(options.algorithm)));
  }
  std::uint32_t next = regular;  // wide items: one color each, after the regular ones, in index order
  if (num_wide > 0)
    for (auto& c : out.color)
      if (c == detail::kUncolored) c = next++;
  out.num_regular_colors = regular;
  out.num_colors = next;
  detail::group_by_color(out);
  if (options.balance) balance(g, out, options.balance_target);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pbd::coloring
