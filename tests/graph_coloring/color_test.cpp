#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <span>
#include <string>

#include "check.hpp"
#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring {
namespace {

using testing::expect_good;

Options with(Algorithm a, bool balance, std::uint64_t seed = 7) {
  Options o;
  o.algorithm = a;
  o.balance = balance;
  o.seed = seed;
  return o;
}

void expect_same(const Coloring& a, const Coloring& b) {
  EXPECT_EQ(a.color, b.color);
  EXPECT_EQ(a.num_colors, b.num_colors);
  EXPECT_EQ(a.num_regular_colors, b.num_regular_colors);
  EXPECT_EQ(a.color_offsets, b.color_offsets);
  EXPECT_EQ(a.items, b.items);
}

// Every algorithm, balanced or not: proper, complete, within the greedy bound, deterministic.
void check_all(const Hypergraph& g, const std::string& what) {
  for (Algorithm a : all_algorithms)
    for (bool balance : {false, true}) {
      SCOPED_TRACE(what + " algorithm=" + std::string(name(a)) + " balance=" + std::to_string(balance));
      const Coloring c = color(g, with(a, balance));
      expect_good(g, c);
      expect_same(c, color(g, with(a, balance)));
    }
}

struct RandomCase {
  std::uint32_t items, nodes, min_degree, max_degree, pinned_percent;
};

TEST(Color, RandomHypergraphsAllAlgorithms) {
  const RandomCase cases[] = {
      {0, 5, 1, 2, 0},      {1, 5, 1, 4, 0},       {2, 3, 2, 2, 0},      {10, 8, 1, 4, 20},
      {100, 50, 2, 2, 0},   {100, 20, 1, 4, 50},   {300, 12, 3, 4, 0},   {500, 1000, 2, 4, 10},
      {1000, 300, 2, 3, 5}, {2000, 2000, 1, 4, 0}, {400, 8, 2, 3, 0},    {3000, 600, 4, 4, 30},
  };
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    for (const auto& k : cases) {
      const auto g = inputs::random_hypergraph(k.items, k.nodes, k.min_degree, k.max_degree, k.pinned_percent, seed);
      check_all(g.view(), "random items=" + std::to_string(k.items) + " nodes=" + std::to_string(k.nodes) +
                              " seed=" + std::to_string(seed));
    }
}

TEST(Color, ManyColorsUseTheOverflowPath) {
  // 400 items of 2-3 nodes among 8: far more than 64 colors.
  const auto g = inputs::random_hypergraph(400, 8, 2, 3, 0, 3);
  for (Algorithm a : all_algorithms) {
    const Coloring c = color(g.view(), with(a, true));
    expect_good(g.view(), c);
    EXPECT_GT(c.num_colors, 64u);
  }
}

TEST(Color, ClothMeshesAllAlgorithms) {
  for (std::uint32_t n : {2u, 3u, 10u, 40u}) {
    check_all(inputs::cloth_edges(n).view(), "cloth edges n=" + std::to_string(n));
    check_all(inputs::cloth_edges(n, true).view(), "pinned cloth edges n=" + std::to_string(n));
    check_all(inputs::cloth_triangles(n).view(), "cloth triangles n=" + std::to_string(n));
    check_all(inputs::cloth_bending(n).view(), "cloth bending n=" + std::to_string(n));
  }
}

TEST(Color, ClothStretchColorsWithinOneOfLowerBound) {
  for (std::uint32_t n : {10u, 64u, 200u}) {
    const auto g = inputs::cloth_edges(n);
    const Coloring c = color(g.view());  // default options
    const Stats s = compute_stats(g.view(), c);
    EXPECT_EQ(s.lower_bound, 6u);
    EXPECT_LE(s.num_colors, s.lower_bound + 1) << "n=" << n;
  }
}

TEST(Color, JonesPlassmannSameOnAnyThreadCountAndEqualsRandomGreedy) {
  const auto cloth = inputs::cloth_edges(60, true);
  const auto random = inputs::random_hypergraph(20000, 5000, 1, 4, 10, 11);
  for (const auto* g : {&cloth, &random})
    for (std::uint64_t seed : {0u, 1u, 99u}) {
      const Coloring serial = color(g->view(), with(Algorithm::greedy_random, false, seed));
      for (int threads = 1; threads <= 4; ++threads) {
        SCOPED_TRACE("threads=" + std::to_string(threads) + " seed=" + std::to_string(seed));
        tbb::task_arena arena(threads);
        Coloring jp;
        arena.execute([&] { jp = color(g->view(), with(Algorithm::jones_plassmann, true, seed)); });
        expect_good(g->view(), jp);
        Coloring unbalanced;
        arena.execute([&] { unbalanced = color(g->view(), with(Algorithm::jones_plassmann, false, seed)); });
        expect_same(unbalanced, serial);
        if (threads > 1) {
          Coloring again;
          tbb::task_arena one(1);
          one.execute([&] { again = color(g->view(), with(Algorithm::jones_plassmann, true, seed)); });
          expect_same(jp, again);
        }
      }
    }
}

TEST(Color, SeedChangesRandomOrder) {
  const auto g = inputs::random_hypergraph(2000, 500, 2, 3, 0, 5);
  EXPECT_NE(color(g.view(), with(Algorithm::greedy_random, false, 1)).color,
            color(g.view(), with(Algorithm::greedy_random, false, 2)).color);
}

TEST(Color, NoItems) {
  for (Algorithm a : all_algorithms) {
    const Coloring c = color(Hypergraph{}, with(a, true));
    EXPECT_EQ(c.num_colors, 0u);
    EXPECT_EQ(c.color_offsets, std::vector<std::uint32_t>{0});
    EXPECT_TRUE(c.items.empty());
    EXPECT_EQ(find_coloring_error(Hypergraph{}, c), std::nullopt);
  }
}

TEST(Color, OneItem) {
  inputs::Graph g;
  g.num_nodes = 3;
  g.add({2, 0});
  for (Algorithm a : all_algorithms) {
    const Coloring c = color(g.view(), with(a, true));
    EXPECT_EQ(c.num_colors, 1u);
    EXPECT_EQ(c.color, std::vector<std::uint32_t>{0});
    expect_good(g.view(), c);
  }
}

TEST(Color, ItemsTouchingOnlyPinnedNodesShareColorZero) {
  inputs::Graph g;
  g.num_nodes = 4;
  g.add({0, 1});
  g.add({0, 1});
  g.add({1, 2});
  g.add({2, 3});
  g.fixed = {1, 1, 0, 0};
  for (Algorithm a : all_algorithms) {
    const Coloring c = color(g.view(), with(a, true));
    expect_good(g.view(), c);
    EXPECT_EQ(c.num_colors, 2u);  // items 2 and 3 share node 2
  }
  g.fixed = {1, 1, 1, 1};
  for (Algorithm a : all_algorithms) {
    const Coloring c = color(g.view(), with(a, true));
    EXPECT_EQ(c.num_colors, 1u);
    EXPECT_EQ(compute_stats(g.view(), c).lower_bound, 1u);
  }
}

TEST(Color, WideItemsGetTheirOwnColorsAndLeaveOthersAlone) {
  // A cloth plus two "volume" items spanning all particles, one in the middle and one at the end;
  // the reference has empty items (which conflict with nothing) in their places, so every item
  // keeps its index, priority and order.
  const std::uint32_t n = 20, middle = 300;
  const auto cloth = inputs::cloth_edges(n);
  std::vector<std::uint32_t> all(cloth.num_nodes);
  for (std::uint32_t v = 0; v < cloth.num_nodes; ++v) all[v] = v;
  inputs::Graph g, reference;
  g.num_nodes = reference.num_nodes = cloth.num_nodes;
  auto append = [](inputs::Graph& h, std::span<const std::uint32_t> item) {
    h.nodes.insert(h.nodes.end(), item.begin(), item.end());
    h.offsets.push_back(static_cast<std::uint32_t>(h.nodes.size()));
  };
  for (std::uint32_t i = 0; i <= cloth.num_items(); ++i) {
    if (i == middle || i == cloth.num_items()) {
      append(g, all);
      append(reference, {});
    }
    if (i < cloth.num_items()) {
      append(g, cloth.view().item(i));
      append(reference, cloth.view().item(i));
    }
  }
  const std::uint32_t last = g.num_items() - 1;
  for (Algorithm a : all_algorithms) {
    SCOPED_TRACE(std::string(name(a)));
    const Coloring with_wide = color(g.view(), with(a, false));
    const Coloring without = color(reference.view(), with(a, false));
    expect_good(g.view(), with_wide);
    EXPECT_EQ(with_wide.num_regular_colors, without.num_colors);
    EXPECT_EQ(with_wide.num_colors, without.num_colors + 2);
    const auto wide = with_wide.wide_items();
    ASSERT_EQ(wide.size(), 2u);
    EXPECT_EQ(wide[0], middle);
    EXPECT_EQ(wide[1], last);
    EXPECT_EQ(with_wide.color[middle], without.num_colors);
    EXPECT_EQ(with_wide.color[last], without.num_colors + 1);
    for (std::uint32_t i = 0; i < g.num_items(); ++i) {
      if (i != middle && i != last) {
        EXPECT_EQ(with_wide.color[i], without.color[i]) << "item " << i;
      }
    }
    const Coloring balanced = color(g.view(), with(a, true));
    expect_good(g.view(), balanced);
    EXPECT_EQ(balanced.num_colors, with_wide.num_colors);
  }
  // With a higher threshold they are ordinary items and conflict with everything.
  Options o;
  o.wide_threshold = 1u << 20;
  const Coloring plain = color(g.view(), o);
  expect_good(g.view(), plain, o.wide_threshold);
  EXPECT_EQ(plain.num_regular_colors, plain.num_colors);
  EXPECT_GT(plain.num_colors, color(reference.view()).num_colors);
}

TEST(Color, AlgorithmNamesRoundTrip) {
  for (Algorithm a : all_algorithms) EXPECT_EQ(parse_algorithm(name(a)), a);
  EXPECT_EQ(parse_algorithm("nope"), std::nullopt);
}

TEST(Color, RejectsBadBalanceTarget) {
  Options o;
  o.balance_target = 0.5;
  EXPECT_THROW((void)color(inputs::cloth_edges(3).view(), o), Error);
}

}  // namespace
}  // namespace pbd::coloring
