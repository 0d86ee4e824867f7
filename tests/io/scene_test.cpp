// Scene files: the built-in scenes load; bad files give errors naming the file and the key.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace pbd {
namespace {

TEST(Scene, EveryBuiltInSceneLoadsAndStepsUnderEverySolver) {
  const auto names = scene_names(PBD_TEST_SCENE_DIR);
  for (const char* expected : {"balls", "cloth", "cloth-fold", "inflate", "inflate-mesh", "pile", "rope"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  for (const auto& name : names) {
    const Scene s = load_scene_by_name(name, PBD_TEST_SCENE_DIR);
    EXPECT_EQ(s.name, name) << "a built-in scene's name should match its file name";
    EXPECT_GT(s.world.num_particles(), 0u) << name;
    for (Solver solver : {Solver::serial, Solver::colored, Solver::jacobi}) {
      World<float> w = build_world<float>(s.world);
      StepParams<float> p = w.params();
      p.solver = solver;
      w.set_params(p);
      for (int i = 0; i < 5; ++i) w.step();
      EXPECT_TRUE(w.positions().allFinite()) << name << " " << pbd::name(solver);
    }
  }
}

TEST(Scene, ClothSceneHasWhatItAsksForAndNothingElse) {
  const Scene s = load_scene_by_name("cloth", PBD_TEST_SCENE_DIR);
  EXPECT_EQ(s.world.num_particles(), 900u);
  EXPECT_EQ(s.world.constraints<StretchConstraint<double>>().size(), std::size_t(2 * 30 * 29 + 29 * 29));
  EXPECT_EQ(s.world.constraints<BendingConstraint<double>>().size(), std::size_t(3 * 29 * 29 - 2 * 29));  // interior
  EXPECT_TRUE(s.world.constraints<AnchorConstraint<double>>().empty());
  EXPECT_TRUE(s.world.constraints<AreaConstraint<double>>().empty());
  EXPECT_TRUE(s.world.volumes.empty());
  EXPECT_EQ(s.world.spheres.size(), 1u);
  EXPECT_EQ(s.world.planes.size(), 1u);
  EXPECT_EQ(s.triangles.size(), std::size_t(2 * 29 * 29));
}

TEST(Scene, MeshScenesHaveTheirVolumesAndTriangles) {
  const Scene inflate = load_scene_by_name("inflate", PBD_TEST_SCENE_DIR);
  ASSERT_EQ(inflate.world.volumes.size(), 1u);
  EXPECT_DOUBLE_EQ(inflate.world.volumes[0].pressure.to, 3.0);
  EXPECT_EQ(inflate.triangles.size(), 60u);
  const Scene pig = load_scene_by_name("inflate-mesh", PBD_TEST_SCENE_DIR);
  ASSERT_EQ(pig.world.volumes.size(), 1u);
  EXPECT_EQ(pig.triangles.size(), pig.world.volumes[0].triangles.size());
  const Scene balls = load_scene_by_name("balls", PBD_TEST_SCENE_DIR);
  EXPECT_EQ(balls.world.volumes.size(), 5u);
  EXPECT_EQ(balls.triangles.size(), 5u * 320u);
  const Scene rope = load_scene_by_name("rope", PBD_TEST_SCENE_DIR);
  const auto& w = rope.world.inverse_masses;
  EXPECT_NEAR(w[1] / w[rope.world.num_particles() - 1], 1000.0, 1e-9) << "the rope keeps its 1000:1 end mass";
}

// Longest rest length of the stretch constraints on particles [first, first + count).
double longest_edge(const WorldDescription& d, Index first, Index count) {
  double longest = 0.0;
  for (const auto& s : d.constraints<StretchConstraint<double>>())
    if (s.particles[0] >= first && s.particles[0] < first + count) longest = std::max(longest, s.rest);
  return longest;
}

TEST(Scene, KeepsWhereEachBodyLandedInFileOrder) {
  const Scene s = parse_scene(R"({"name": "two", "dt": 0.01, "bodies": [
      {"type": "cloth", "resolution": 3},
      {"type": "rope", "particles": 4, "stretch": {}},
      {"type": "particles", "positions": [[0, 0, 0], [1, 0, 0]]}]})",
                              "two.json");
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[0].name, "cloth_0");
  EXPECT_EQ(s.bodies[1].name, "rope_1");
  EXPECT_EQ(s.bodies[2].name, "particles_2");
  EXPECT_EQ(s.bodies[0].first_particle, 0u);
  EXPECT_EQ(s.bodies[0].num_particles, 9u);
  EXPECT_EQ(s.bodies[1].first_particle, 9u);
  EXPECT_EQ(s.bodies[1].num_particles, 4u);
  EXPECT_EQ(s.bodies[2].first_particle, 13u);
  EXPECT_EQ(s.bodies[2].num_particles, 2u);
  EXPECT_EQ(s.bodies[0].triangles.size(), 8u);
  EXPECT_TRUE(s.bodies[1].triangles.empty());
  EXPECT_EQ(s.triangles, s.bodies[0].triangles) << "triangles still holds every body's triangles";
  const Scene balls = load_scene_by_name("balls", PBD_TEST_SCENE_DIR);
  Index next = 0;
  std::size_t triangles = 0;
  for (const SceneBody& b : balls.bodies) {
    EXPECT_EQ(b.first_particle, next) << b.name;
    next += b.num_particles;
    triangles += b.triangles.size();
  }
  EXPECT_EQ(next, balls.world.num_particles()) << "the bodies hold every particle";
  EXPECT_EQ(triangles, balls.triangles.size());
}

TEST(Scene, ContactScenesHaveRadiiThatLeaveNoGapsAndTheirColliders) {
  const Scene balls = load_scene_by_name("balls", PBD_TEST_SCENE_DIR);
  ASSERT_EQ(balls.world.contact_bodies.size(), 5u);
  for (const auto& b : balls.world.contact_bodies) {
    EXPECT_EQ(b.count, 162u);
    EXPECT_GE(2 * b.radius, longest_edge(balls.world, b.first, b.count)) << "no ball passes between another's particles";
    EXPECT_GT(b.material.static_friction, 0.0);
  }
  const Scene fold = load_scene_by_name("cloth-fold", PBD_TEST_SCENE_DIR);
  ASSERT_EQ(fold.world.contact_bodies.size(), 1u);
  const auto& cloth = fold.world.contact_bodies[0];
  EXPECT_EQ(cloth.count, 1600u);
  EXPECT_TRUE(cloth.self_collision);
  EXPECT_GE(2 * cloth.radius, 1.0 / 39.0) << "radius at least half the rest edge";
  EXPECT_EQ(fold.primary_error, "stretch");
  const Scene pile = load_scene_by_name("pile", PBD_TEST_SCENE_DIR);
  EXPECT_GE(pile.world.num_particles(), 10000u);
  EXPECT_EQ(pile.world.num_constraints(), 0u);
  ASSERT_EQ(pile.world.contact_bodies.size(), 1u);
  EXPECT_TRUE(pile.world.contact_bodies[0].self_collision);
  EXPECT_EQ(pile.world.contact_bodies[0].count, pile.world.num_particles());
  EXPECT_EQ(pile.world.planes.size(), 5u);  // floor and four walls
  EXPECT_EQ(pile.primary_error, "overlap");
  for (const Scene* s : {&balls, &fold, &pile}) {
    for (const auto& p : s->world.planes) EXPECT_GT(p.material.static_friction, 0.0) << s->name;
    for (const auto& p : s->world.spheres) EXPECT_GT(p.material.static_friction, 0.0) << s->name;
  }
}

const char* kMesh = R"({"name": "m", "dt": 0.01, "bodies": [
  {"type": "mesh", "generator": {"type": "icosphere", "level": 1, "radius": 0.5}, "origin": [0, 0, 1], "scale": 2,
   "mass": 3, "pinned": [0], "stretch": {"compliance": 1e-6}, "bending": {"stiffness": 0.5}, "area": {},
   "volume": {"stiffness": 1, "pressure": {"from": 1, "to": 2, "duration": 3}}},
  {"type": "mesh", "generator": {"type": "tube", "segments": 8, "rings": 3, "radius": 0.1, "length": 1, "capped": true},
   "volume": {}},
  {"type": "mesh", "generator": {"type": "grid", "resolution": 4, "size": 1}, "bending": {}},
  {"type": "mesh", "generator": {"type": "dodecahedron", "radius": 0.2}},
  {"type": "cloth", "resolution": 3, "bending": {"stiffness": 0.1}, "area": {"compliance": 0}}
]})";

TEST(Scene, ParsesMeshBodies) {
  const Scene s = parse_scene(kMesh, "mesh.json");
  const WorldDescription& c = s.world;
  EXPECT_EQ(s.world.num_particles(), 42u + 26u + 16u + 32u + 9u);
  EXPECT_EQ(c.volumes.size(), 2u);
  EXPECT_DOUBLE_EQ(c.volumes[0].pressure.at(1.5), 1.5);
  EXPECT_EQ(c.constraints<StretchConstraint<double>>().size(), 120u);
  EXPECT_EQ(c.constraints<AreaConstraint<double>>().size(), 80u + 8u);
  // sphere edges, 4x4 grid interior edges, 3x3 cloth interior edges
  EXPECT_EQ(c.constraints<BendingConstraint<double>>().size(), 120u + 21u + 8u);
  EXPECT_EQ(s.world.inverse_masses[0], 0.0);
  EXPECT_NEAR(s.world.positions.col(1).norm(), 0.0, 3.0);
  EXPECT_EQ(s.triangles.size(), 80u + 48u + 18u + 60u + 8u);
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
  const WorldDescription& w = s.world;
  EXPECT_EQ(s.steps, 7);
  EXPECT_EQ(w.params.substeps, 2);
  EXPECT_EQ(w.params.iterations, 3);
  EXPECT_DOUBLE_EQ(w.params.damping, 0.5);
  EXPECT_EQ(w.num_particles(), 3u);
  EXPECT_EQ(w.inverse_masses[0], 0.0);
  EXPECT_DOUBLE_EQ(w.inverse_masses[2], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(w.velocities(1, 1), 1.0);
  ASSERT_EQ(w.constraints<StretchConstraint<double>>().size(), 2u);
  EXPECT_EQ(w.sets[0].mode, StiffnessMode::xpbd);
  EXPECT_EQ(w.sets[1].mode, StiffnessMode::pbd_iteration_independent);
  ASSERT_EQ(w.constraints<AnchorConstraint<double>>().size(), 1u);
  EXPECT_EQ(w.constraints<AnchorConstraint<double>>()[0].particles[0], 2u);
  ASSERT_EQ(w.planes.size(), 1u);
  EXPECT_DOUBLE_EQ(w.planes[0].offset, -1.0);  // normal normalized, offset is n·x with the unit normal
  EXPECT_EQ(w.spheres.size(), 1u);
}

// Parses `text` and expects a pbd::Error whose message names the source ("bad.json") and every one of `words`.
void expect_error(const std::string& text, std::initializer_list<const char*> words) {
  const std::string msg = test::error_of([&] { parse_scene(text, "bad.json"); });
  EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
  for (const char* w : words) EXPECT_NE(msg.find(w), std::string::npos) << msg;
}

using test::replaced;

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

TEST(SceneErrors, MeshBodies) {
  expect_error(replaced(kMesh, "\"level\": 1", "\"level\": 9"), {"/bodies/0/generator/level", "out of range"});
  expect_error(replaced(kMesh, "\"type\": \"icosphere\"", "\"type\": \"torus\""), {"/bodies/0/generator/type", "torus"});
  expect_error(replaced(kMesh, "\"duration\": 3", "\"duraton\": 3"), {"/bodies/0/volume/pressure/duraton"});
  expect_error(replaced(kMesh, "\"pinned\": [0]", "\"pinned\": [42]"), {"/bodies/0/pinned/0"});
  expect_error(replaced(kMesh, "\"bending\": {}}", "\"volume\": {}}"), {"/bodies/2/generator", "open"});
  expect_error(replaced(kMesh, "\"generator\": {\"type\": \"grid\"", "\"obj\": \"x.obj\", \"generator\": {\"type\": \"grid\""),
               {"/bodies/2/generator", "exactly one"});
  expect_error(replaced(kMesh, "\"generator\": {\"type\": \"grid\", \"resolution\": 4, \"size\": 1}",
                        "\"obj\": \"no/such.obj\""),
               {"/bodies/2/obj", "no/such.obj"});
  expect_error(replaced(kMesh, "\"area\": {\"compliance\": 0}", "\"volume\": {}"), {"/bodies/4/volume", "unknown key"});
}

TEST(SceneErrors, MissingFileAndUnknownBuiltInName) {
  EXPECT_THROW(load_scene("/nonexistent/scene.json"), Error);
  try {
    load_scene_by_name("no-such-scene", PBD_TEST_SCENE_DIR);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cloth"), std::string::npos) << "lists the built-in scenes: " << e.what();
  }
}

}  // namespace
}  // namespace pbd
