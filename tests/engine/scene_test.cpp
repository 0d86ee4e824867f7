// Scene files: the built-in scenes load; bad files give errors naming the file and the key.
#include "pbd/metrics.hpp"
#include "pbd/scene.hpp"

#include <gtest/gtest.h>

namespace pbd {
namespace {

TEST(Scene, EveryBuiltInSceneLoadsAndSteps) {
  const auto names = builtin_scene_names();
  ASSERT_GE(names.size(), 2u);
  for (const auto& name : names) {
    const Scene s = load_scene_by_name(name);
    EXPECT_EQ(s.name, name) << "a built-in scene's name should match its file name";
    EXPECT_GT(s.world.num_particles(), 0u) << name;
    World<float> w(s.world);
    for (int i = 0; i < 5; ++i) w.step();
    EXPECT_TRUE(w.positions().allFinite()) << name;
  }
}

TEST(Scene, ClothSceneHasWhatItAsksForAndNothingElse) {
  const Scene s = load_scene_by_name("cloth");
  EXPECT_EQ(s.world.num_particles(), 900u);
  EXPECT_EQ(s.world.constraints().stretch.size(), std::size_t(2 * 30 * 29 + 29 * 29));
  EXPECT_TRUE(s.world.constraints().anchor.empty());
  EXPECT_TRUE(s.world.colliders().empty());
  EXPECT_EQ(s.triangles.size(), std::size_t(2 * 29 * 29));
}

const char* kMinimal = R"({
  "name": "t", "dt": 0.01, "iterations": 3, "substeps": 2, "gravity": [0, 0, -1], "damping": 0.5, "steps": 7,
  "bodies": [
    {"type": "particles", "positions": [[0,0,0],[1,0,0],[2,0,0]], "masses": [1, 2, 3], "pinned": [0],
     "velocities": [[0,0,0],[0,1,0],[0,0,0]],
     "stretch": {"pairs": [[0,1],[1,2]], "compliance": 1e-6},
     "anchors": {"particles": [2], "stiffness": 0.5, "iteration_independent": true}}
  ],
  "colliders": [{"type": "plane", "normal": [0, 0, 2], "offset": -1}, {"type": "sphere", "center": [0,0,5], "radius": 1}]
})";

TEST(Scene, ParsesEveryFieldOfTheFormat) {
  const Scene s = parse_scene(kMinimal, "mini.json");
  const auto& w = s.world;
  EXPECT_EQ(s.steps, 7);
  EXPECT_EQ(w.params().substeps, 2);
  EXPECT_EQ(w.params().iterations, 3);
  EXPECT_DOUBLE_EQ(w.params().damping, 0.5);
  EXPECT_EQ(w.num_particles(), 3u);
  EXPECT_EQ(w.inverse_masses()[0], 0.0);
  EXPECT_DOUBLE_EQ(w.inverse_masses()[2], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(w.velocities()(1, 1), 1.0);
  ASSERT_EQ(w.constraints().stretch.size(), 2u);
  EXPECT_EQ(w.constraints().sets[0].mode, StiffnessMode::xpbd);
  EXPECT_EQ(w.constraints().sets[1].mode, StiffnessMode::pbd_iteration_independent);
  ASSERT_EQ(w.constraints().anchor.size(), 1u);
  EXPECT_EQ(w.constraints().anchor[0].particles[0], 2u);
  ASSERT_EQ(w.colliders().planes.size(), 1u);
  EXPECT_DOUBLE_EQ(w.colliders().planes[0].offset, -1.0);  // normal normalized, offset is n·x with the unit normal
  EXPECT_EQ(w.colliders().spheres.size(), 1u);
}

// Parses `text` and expects a pbd::Error whose message contains every one of `words`.
void expect_error(const std::string& text, std::initializer_list<const char*> words) {
  try {
    parse_scene(text, "bad.json");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
    for (const char* w : words) EXPECT_NE(msg.find(w), std::string::npos) << msg;
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SceneErrors, UnknownKeysAnywhere) {
  expect_error(replaced(kMinimal, "\"steps\"", "\"stepz\""), {"/stepz", "unknown key"});
  expect_error(replaced(kMinimal, "\"pinned\"", "\"pined\""), {"/bodies/0/pined", "unknown key"});
  expect_error(replaced(kMinimal, "\"compliance\"", "\"compliancy\""), {"/bodies/0/stretch/compliancy"});
  expect_error(replaced(kMinimal, "\"radius\"", "\"r\""), {"/colliders/1/"});
}

TEST(SceneErrors, WrongTypes) {
  expect_error(replaced(kMinimal, "\"iterations\": 3", "\"iterations\": \"3\""), {"/iterations", "integer"});
  expect_error(replaced(kMinimal, "\"iterations\": 3", "\"iterations\": 2.5"), {"/iterations", "integer"});
  expect_error(replaced(kMinimal, "\"dt\": 0.01", "\"dt\": [1]"), {"/dt", "number"});
  expect_error(replaced(kMinimal, "[0, 0, -1]", "[0, 0]"), {"/gravity", "3 numbers"});
  expect_error(replaced(kMinimal, "\"bodies\": [", "\"bodies\": 1, \"x\": ["), {"/bodies", "array"});
  expect_error("[1, 2]", {"expected an object"});
}

TEST(SceneErrors, OutOfRangeValues) {
  expect_error(replaced(kMinimal, "\"dt\": 0.01", "\"dt\": 0"), {"/dt", "out of range"});
  expect_error(replaced(kMinimal, "\"dt\": 0.01", "\"dt\": -1"), {"/dt", "out of range"});
  expect_error(replaced(kMinimal, "\"substeps\": 2", "\"substeps\": 0"), {"/substeps"});
  expect_error(replaced(kMinimal, "\"stiffness\": 0.5", "\"stiffness\": 1.5"), {"/bodies/0/anchors/stiffness"});
  expect_error(replaced(kMinimal, "\"compliance\": 1e-6", "\"compliance\": -1"), {"/bodies/0/stretch/compliance"});
  expect_error(replaced(kMinimal, "\"masses\": [1, 2, 3]", "\"masses\": [1, -2, 3]"), {"/bodies/0/masses/1"});
  expect_error(replaced(kMinimal, "\"pinned\": [0]", "\"pinned\": [3]"), {"/bodies/0/pinned/0", "out of range"});
  expect_error(replaced(kMinimal, "[[0,1],[1,2]]", "[[0,1],[1,7]]"), {"/bodies/0/stretch/pairs/1/1"});
  expect_error(replaced(kMinimal, "[[0,1],[1,2]]", "[[0,1],[1,1]]"), {"/bodies/0/stretch/pairs/1", "twice"});
  expect_error(replaced(kMinimal, "\"radius\": 1", "\"radius\": 0"), {"/colliders/1/radius"});
  expect_error(replaced(kMinimal, "[0, 0, 2]", "[0, 0, 0]"), {"/colliders/0/normal"});
  expect_error(replaced(kMinimal, "\"masses\": [1, 2, 3]", "\"masses\": [1, 2]"), {"/bodies/0/masses", "2 entries"});
}

TEST(SceneErrors, MissingKeysAndUnknownTypes) {
  expect_error(replaced(kMinimal, "\"name\": \"t\",", ""), {"/name", "missing"});
  expect_error(replaced(kMinimal, "\"type\": \"particles\"", "\"type\": \"jelly\""), {"/bodies/0/type", "jelly"});
  expect_error(replaced(kMinimal, "\"type\": \"plane\"", "\"type\": \"torus\""), {"/colliders/0/type", "torus"});
  expect_error(replaced(kMinimal, "\"compliance\": 1e-6", "\"compliance\": 1e-6, \"stiffness\": 1"), {"not both"});
}

TEST(SceneErrors, MalformedAndTruncatedJsonNamesTheLine) {
  const std::string text = kMinimal;
  expect_error(text.substr(0, text.size() / 2), {"line"});
  expect_error(replaced(kMinimal, "\"steps\": 7", "\"steps\": 7,,"), {"line 2"});
  expect_error("", {"parse error"});
}

TEST(SceneErrors, MissingFileAndUnknownBuiltInName) {
  EXPECT_THROW(load_scene("/nonexistent/scene.json"), Error);
  try {
    load_scene_by_name("no-such-scene");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cloth"), std::string::npos) << "lists the built-in scenes: " << e.what();
  }
}

}  // namespace
}  // namespace pbd
