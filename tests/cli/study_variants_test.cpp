// The study's variants edit a scene's JSON before it is parsed (cli/study/scene_variants.hpp): tethers on every
// body with pinned particles, the hierarchy at the top level, both together, and nothing where they do not apply.
#include "pbd/error.hpp"
#include "scene_variants.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// A vector, not a json: `json b = {rope}` is an array of one under GCC but a copy of `rope` under clang.
json scene_with(const std::vector<json>& bodies) { return {{"name", "s"}, {"dt", 0.01}, {"bodies", json(bodies)}}; }

json cloth(const char* pin) {
  return {{"type", "cloth"}, {"resolution", 4}, {"pin", pin}, {"stretch", {{"stiffness", 1.0}}}};
}

TEST(StudyVariants, PlainLeavesTheSceneAsItIs) {
  const json s = scene_with({cloth("corners")});
  EXPECT_EQ(apply_variant(s, "plain"), s);
}

TEST(StudyVariants, TethersGoOnEveryBodyWithPinsOnly) {
  const json mesh_pinned = {{"type", "mesh"}, {"pinned", {0, 3}}, {"stretch", json::object()}};
  const json mesh_free = {{"type", "mesh"}, {"stretch", json::object()}};
  const json rope = {{"type", "rope"}, {"particles", 5}};
  const json grains = {{"type", "grains"}};
  const json s = scene_with({cloth("corners"), cloth("none"), mesh_pinned, mesh_free, rope, grains});
  const json t = apply_variant(s, "tethers");
  EXPECT_EQ(t["bodies"][0]["tethers"], true);
  EXPECT_FALSE(t["bodies"][1].contains("tethers"));  // a cloth pinned nowhere
  EXPECT_EQ(t["bodies"][2]["tethers"], true);
  EXPECT_FALSE(t["bodies"][3].contains("tethers"));  // a mesh without pins
  EXPECT_EQ(t["bodies"][4]["tethers"], true);        // a rope pins its first particle
  EXPECT_FALSE(t["bodies"][5].contains("tethers"));
  EXPECT_FALSE(t.contains("hierarchy"));
  // Everything else is unchanged.
  json back = t;
  for (json& b : back["bodies"]) b.erase("tethers");
  EXPECT_EQ(back, s);
}

TEST(StudyVariants, ABodysOwnTethersAndASceneOwnHierarchyAreKept) {
  json c = cloth("corners");
  c["tethers"] = {{"to", "nearest"}};
  json s = scene_with({c});
  s["hierarchy"] = {{"levels", 2}};
  const json t = apply_variant(s, "tethers+hierarchy");
  EXPECT_EQ(t["bodies"][0]["tethers"], json({{"to", "nearest"}}));
  EXPECT_EQ(t["hierarchy"], json({{"levels", 2}}));
}

TEST(StudyVariants, HierarchyAtTheTopLevelWhenABodyHasStretch) {
  const json h = apply_variant(scene_with({cloth("none")}), "hierarchy");
  EXPECT_EQ(h["hierarchy"], true);
  EXPECT_FALSE(h["bodies"][0].contains("tethers"));
  const json both = apply_variant(scene_with({cloth("corners")}), "tethers+hierarchy");
  EXPECT_EQ(both["hierarchy"], true);
  EXPECT_EQ(both["bodies"][0]["tethers"], true);
}

TEST(StudyVariants, AVariantThatDoesNotApplyIsRefused) {
  const json no_stretch = scene_with({{{"type", "grains"}}});
  EXPECT_TRUE(variant_applies(no_stretch, "plain"));
  EXPECT_FALSE(variant_applies(no_stretch, "tethers"));
  EXPECT_FALSE(variant_applies(no_stretch, "hierarchy"));
  EXPECT_THROW(apply_variant(no_stretch, "hierarchy"), Error);
  const json unpinned = scene_with({cloth("none")});
  EXPECT_FALSE(variant_applies(unpinned, "tethers+hierarchy"));  // both need their bodies
  EXPECT_THROW(variant_applies(unpinned, "magic"), Error);
}

TEST(StudyVariants, NoTethersOnCompliantStretch) {
  // A compliant chain hangs α·T longer than its rest length; a tether at the rest length would stop that.
  const json rope = {{"type", "rope"}, {"particles", 5}, {"stretch", {{"compliance", 1e-3}}}};
  const json chain = scene_with({rope});
  EXPECT_FALSE(variant_applies(chain, "tethers"));
  EXPECT_TRUE(variant_applies(chain, "hierarchy"));
  const json mixed = scene_with({rope, cloth("corners")});
  const json both = apply_variant(mixed, "tethers");
  EXPECT_FALSE(both["bodies"][0].contains("tethers"));
  EXPECT_EQ(both["bodies"][1]["tethers"], true);
}

}  // namespace
}  // namespace pbd::cli
