#include <gtest/gtest.h>

#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring {
namespace {

// Two items sharing node 1; node 3 is fixed.
inputs::Graph pair() {
  inputs::Graph g;
  g.num_nodes = 4;
  g.add({0, 1});
  g.add({1, 2});
  g.add({2, 3});
  g.fixed = {0, 0, 0, 1};
  return g;
}

Coloring make(std::vector<std::uint32_t> color, std::vector<std::uint32_t> offsets, std::vector<std::uint32_t> items,
              std::uint32_t regular) {
  Coloring c;
  c.color = std::move(color);
  c.num_colors = static_cast<std::uint32_t>(offsets.size() - 1);
  c.color_offsets = std::move(offsets);
  c.items = std::move(items);
  c.num_regular_colors = regular;
  return c;
}

TEST(Validate, AcceptsProperColoring) {
  const auto g = pair();
  EXPECT_EQ(find_coloring_error(g.view(), make({0, 1, 0}, {0, 2, 3}, {0, 2, 1}, 2)), std::nullopt);
}

TEST(Validate, RejectsItemsSharingANode) {
  const auto g = pair();
  EXPECT_EQ(find_coloring_error(g.view(), make({0, 0, 1}, {0, 2, 3}, {0, 1, 2}, 2)),
            "items 0 and 1 both have color 0 and share node 1");
}

TEST(Validate, FixedNodesDoNotConflict) {
  inputs::Graph g;
  g.num_nodes = 3;
  g.add({0, 1});
  g.add({1, 2});
  EXPECT_NE(find_coloring_error(g.view(), make({0, 0}, {0, 2}, {0, 1}, 1)), std::nullopt);
  g.fixed = {0, 1, 0};
  EXPECT_EQ(find_coloring_error(g.view(), make({0, 0}, {0, 2}, {0, 1}, 1)), std::nullopt);
}

TEST(Validate, RejectsIncompleteOrInconsistentGrouping) {
  const auto g = pair();
  // item 2 listed twice, item 1 missing
  EXPECT_NE(find_coloring_error(g.view(), make({0, 1, 0}, {0, 2, 3}, {0, 2, 2}, 2)), std::nullopt);
  // not in index order within a color
  EXPECT_NE(find_coloring_error(g.view(), make({0, 1, 0}, {0, 2, 3}, {2, 0, 1}, 2)), std::nullopt);
  // wrong number of colors
  EXPECT_NE(find_coloring_error(g.view(), make({0, 1}, {0, 2, 3}, {0, 2, 1}, 2)), std::nullopt);
  // an empty color
  EXPECT_NE(find_coloring_error(g.view(), make({0, 2, 0}, {0, 2, 2, 3}, {0, 2, 1}, 3)), std::nullopt);
  // a wide color holding two items
  EXPECT_NE(find_coloring_error(g.view(), make({0, 1, 1}, {0, 1, 3}, {0, 1, 2}, 1)), std::nullopt);
  // regular colors beyond the total
  EXPECT_NE(find_coloring_error(g.view(), make({0, 1, 0}, {0, 2, 3}, {0, 2, 1}, 3)), std::nullopt);
}

}  // namespace
}  // namespace pbd::coloring
