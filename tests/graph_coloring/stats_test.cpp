#include <gtest/gtest.h>

#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring {
namespace {

TEST(Stats, FiguresOfASmallColoring) {
  inputs::Graph g;  // a path 0-1-2-3 plus an isolated item
  g.num_nodes = 6;
  g.add({0, 1});
  g.add({1, 2});
  g.add({2, 3});
  g.add({4, 5});
  Options o;
  o.balance = false;
  const Coloring c = color(g.view(), o);
  const Stats s = compute_stats(g.view(), c);
  EXPECT_EQ(s.num_items, 4u);
  EXPECT_EQ(s.num_colors, 2u);
  EXPECT_EQ(s.lower_bound, 2u);
  EXPECT_EQ(s.num_wide, 0u);
  EXPECT_EQ(s.min_batch, 1u);
  EXPECT_EQ(s.max_batch, 3u);
  EXPECT_DOUBLE_EQ(s.mean_batch, 2.0);
  EXPECT_DOUBLE_EQ(s.max_over_mean, 1.5);
  EXPECT_GT(c.seconds, 0.0);  // color() timed itself
  EXPECT_EQ(s.seconds, c.seconds);
  EXPECT_EQ(color_lower_bound(g.view()), 2u);
}

TEST(Stats, LowerBoundSkipsFixedAndWide) {
  inputs::Graph g;
  g.num_nodes = 3;
  g.add({0, 1});
  g.add({0, 2});
  g.add({0, 1, 2});
  EXPECT_EQ(color_lower_bound(g.view()), 3u);
  EXPECT_EQ(color_lower_bound(g.view(), 2), 2u);
  g.fixed = {1, 0, 0};
  EXPECT_EQ(color_lower_bound(g.view()), 2u);
  EXPECT_EQ(color_lower_bound(Hypergraph{}), 0u);
}

TEST(Stats, FormatsATable) {
  const auto g = inputs::cloth_edges(10);
  const Coloring c = color(g.view());
  const NamedStats rows[] = {{"stretch", compute_stats(g.view(), c)}, {"overall", compute_stats(g.view(), c)}};
  const std::string table = format_stats(rows);
  EXPECT_NE(table.find("colors"), std::string::npos);
  EXPECT_NE(table.find("stretch"), std::string::npos);
  EXPECT_NE(table.find("overall"), std::string::npos);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 3);
}

}  // namespace
}  // namespace pbd::coloring
