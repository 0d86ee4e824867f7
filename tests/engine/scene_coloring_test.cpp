// graph_coloring on the engine's own scenes: every algorithm gives a proper, complete coloring of every constraint
// type of every built-in scene, within the greedy bound, and the same coloring twice.
#include "pbd/detail/constraint_store.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>
#include <pbd/graph_coloring/graph_coloring.hpp>

#include <algorithm>
#include <set>

namespace pbd {
namespace {

// Largest number of other constraints one constraint shares a movable particle with (computed independently).
std::uint32_t max_conflict_degree(const detail::ConstraintGraph& g) {
  std::vector<std::vector<std::uint32_t>> at(g.num_particles);
  const coloring::Hypergraph h = g.view();
  for (std::uint32_t i = 0; i < h.num_items(); ++i)
    for (std::uint32_t p : h.item(i))
      if (!g.fixed[p]) at[p].push_back(i);
  std::uint32_t worst = 0;
  for (std::uint32_t i = 0; i < h.num_items(); ++i) {
    std::set<std::uint32_t> others;
    for (std::uint32_t p : h.item(i))
      if (!g.fixed[p])
        for (std::uint32_t j : at[p])
          if (j != i) others.insert(j);
    worst = std::max(worst, std::uint32_t(others.size()));
  }
  return worst;
}

TEST(SceneColoring, EveryAlgorithmOnEveryBuiltInSceneIsProperCompleteDeterministicAndWithinTheGreedyBound) {
  for (const std::string& name : scene_names(PBD_TEST_SCENE_DIR)) {
    const World<double> world = build_world<double>(load_scene_by_name(name, PBD_TEST_SCENE_DIR).world);
    std::vector<std::uint8_t> fixed;
    for (Index i = 0; i < world.num_particles(); ++i) fixed.push_back(world.inverse_masses()[i] == 0.0);
    world.for_each_builtin([&](const auto& array) {
      using Constraint = typename std::decay_t<decltype(array)>::value_type;
      if (array.empty()) return;
      const std::vector<Constraint> items(array.begin(), array.end());
      const detail::ConstraintGraph g = detail::constraint_graph(std::span<const Constraint>(items), fixed);
      const std::uint32_t bound = max_conflict_degree(g) + 1;
      for (coloring::Algorithm a : coloring::all_algorithms) {
        coloring::Options o;
        o.algorithm = a;
        const coloring::Coloring c = coloring::color(g.view(), o);
        const std::string what = name + " / " + Constraint::kName + " / " + std::string(coloring::name(a));
        EXPECT_EQ(coloring::find_coloring_error(g.view(), c), std::nullopt) << what;
        EXPECT_EQ(c.color.size(), array.size()) << what;
        EXPECT_EQ(c.items.size(), array.size()) << what;
        EXPECT_LE(c.num_colors, bound) << what;
        EXPECT_EQ(coloring::color(g.view(), o).color, c.color) << what << ": not deterministic";
      }
    });
  }
}

}  // namespace
}  // namespace pbd
