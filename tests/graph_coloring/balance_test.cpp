#include <gtest/gtest.h>

#include <string>

#include "check.hpp"
#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring {
namespace {

Options unbalanced(Algorithm a) {
  Options o;
  o.algorithm = a;
  o.balance = false;
  return o;
}

TEST(Balance, NeverAddsAColorNorBreaksProperness) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
    for (std::uint32_t nodes : {10u, 100u, 2000u})
      for (Algorithm a : all_algorithms) {
        SCOPED_TRACE("seed=" + std::to_string(seed) + " nodes=" + std::to_string(nodes) + " " + std::string(name(a)));
        const auto g = inputs::random_hypergraph(1500, nodes, 1, 4, seed % 3 == 0 ? 20 : 0, seed);
        Coloring c = color(g.view(), unbalanced(a));
        const std::uint32_t before = c.num_colors;
        const double ratio = balance(g.view(), c, 1.1);
        testing::expect_good(g.view(), c);
        EXPECT_EQ(c.num_colors, before);
        const Stats s = compute_stats(g.view(), c);
        EXPECT_DOUBLE_EQ(ratio, s.max_over_mean);
        EXPECT_EQ(s.min_batch > 0, true);
      }
}

TEST(Balance, ClothReachesTarget) {
  for (std::uint32_t n : {30u, 100u})
    for (Algorithm a : all_algorithms) {
      SCOPED_TRACE("n=" + std::to_string(n) + " " + std::string(name(a)));
      const auto g = inputs::cloth_edges(n, true);
      Coloring c = color(g.view(), unbalanced(a));
      const double ratio = balance(g.view(), c, 1.1);
      testing::expect_good(g.view(), c);
      EXPECT_LE(ratio, 1.1);
    }
}

TEST(Balance, IsDeterministicAndIdempotentOnceBalanced) {
  const auto g = inputs::random_hypergraph(3000, 800, 2, 3, 0, 42);
  Coloring a = color(g.view(), unbalanced(Algorithm::greedy_input));
  Coloring b = a;
  balance(g.view(), a);
  balance(g.view(), b);
  EXPECT_EQ(a.color, b.color);
  if (compute_stats(g.view(), a).max_over_mean <= 1.1) {
    const auto before = a.color;
    balance(g.view(), a);
    EXPECT_EQ(a.color, before);
  }
}

// Balancing keeps each color spread over the item indices (items are usually numbered along the mesh, so a color's
// index range is its place on the mesh, and a parallel loop that cuts every color at half its count then cuts every
// color near the same place). On a 100² cloth's bending items, every color's first and last quarter of items (by
// index) lie in the first and last 40% of all items; moving each donor's first items instead leaves the receivers
// with early items only (their last quarter then starts before 25%).
TEST(Balance, EveryColorKeepsItsSpreadOverTheItemIndices) {
  for (const auto& g : {inputs::cloth_bending(100), inputs::cloth_edges(100, true)}) {
    Options o;  // greedy_input, balanced to 1.1
    Coloring c = color(g.view(), o);
    const double n = g.view().num_items();
    for (std::uint32_t k = 0; k < c.num_regular_colors; ++k) {
      const auto items = c.items_of(k);
      ASSERT_FALSE(items.empty());
      const double q1 = items[items.size() / 4] / n, q3 = items[3 * items.size() / 4] / n;
      EXPECT_LT(q1, 0.4) << "color " << k << " of " << c.num_regular_colors;
      EXPECT_GT(q3, 0.6) << "color " << k << " of " << c.num_regular_colors;
    }
  }
}

TEST(Balance, RejectsTargetBelowOne) {
  const auto g = inputs::cloth_edges(4);
  Coloring c = color(g.view());
  EXPECT_THROW(balance(g.view(), c, 0.9), Error);
}

}  // namespace
}  // namespace pbd::coloring
