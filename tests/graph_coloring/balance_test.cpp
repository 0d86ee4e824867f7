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

TEST(Balance, RejectsTargetBelowOne) {
  const auto g = inputs::cloth_edges(4);
  Coloring c = color(g.view());
  EXPECT_THROW(balance(g.view(), c, 0.9), Error);
}

}  // namespace
}  // namespace pbd::coloring
