#include <gtest/gtest.h>

#include <string>

#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace pbd::coloring {
namespace {

std::string error_of(const Hypergraph& g) {
  try {
    validate(g);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Hypergraph, EmptyInputsAreValid) {
  EXPECT_EQ(error_of(Hypergraph{}), "");
  const std::vector<std::uint32_t> offsets{0};
  EXPECT_EQ(error_of(Hypergraph{offsets, {}, 5, {}}), "");
  EXPECT_EQ(Hypergraph{}.num_items(), 0u);
}

TEST(Hypergraph, RejectsRepeatedNodeNamingItemAndNode) {
  inputs::Graph g;
  g.num_nodes = 10;
  g.add({0, 1});
  g.add({2, 3, 2});
  EXPECT_EQ(error_of(g.view()), "graph_coloring: item 1 touches node 2 twice");
  EXPECT_THROW((void)color(g.view()), Error);
}

TEST(Hypergraph, RejectsRepeatedNodeInLargeItem) {
  inputs::Graph g;
  g.num_nodes = 100;
  g.add({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 7});
  EXPECT_EQ(error_of(g.view()), "graph_coloring: item 0 touches node 7 twice");
}

TEST(Hypergraph, RejectsNodeOutOfRange) {
  inputs::Graph g;
  g.num_nodes = 4;
  g.add({0, 1});
  g.add({3, 4});
  EXPECT_EQ(error_of(g.view()), "graph_coloring: item 1 touches node 4, out of range (num_nodes 4)");
  EXPECT_THROW((void)color(g.view()), Error);
}

TEST(Hypergraph, RejectsNonMonotoneOffsets) {
  const std::vector<std::uint32_t> offsets{0, 2, 1, 3};
  const std::vector<std::uint32_t> nodes{0, 1, 2};
  EXPECT_NE(error_of(Hypergraph{offsets, nodes, 3, {}}).find("offsets decrease at item 1"), std::string::npos);
  EXPECT_THROW((void)color(Hypergraph{offsets, nodes, 3, {}}), Error);
}

TEST(Hypergraph, RejectsOffsetsNotSpanningNodes) {
  const std::vector<std::uint32_t> nodes{0, 1, 2};
  const std::vector<std::uint32_t> short_end{0, 2};
  const std::vector<std::uint32_t> bad_start{1, 3};
  EXPECT_NE(error_of(Hypergraph{short_end, nodes, 3, {}}), "");
  EXPECT_NE(error_of(Hypergraph{bad_start, nodes, 3, {}}), "");
  EXPECT_NE(error_of(Hypergraph{{}, nodes, 3, {}}), "");
}

TEST(Hypergraph, RejectsFixedMaskOfWrongSize) {
  inputs::Graph g;
  g.num_nodes = 3;
  g.add({0, 1});
  g.fixed = {0, 1};
  EXPECT_NE(error_of(g.view()).find("fixed mask"), std::string::npos);
}

TEST(Hypergraph, UniformOffsets) {
  EXPECT_EQ(uniform_offsets(3, 2), (std::vector<std::uint32_t>{0, 2, 4, 6}));
  EXPECT_EQ(uniform_offsets(0, 4), (std::vector<std::uint32_t>{0}));
}

}  // namespace
}  // namespace pbd::coloring
