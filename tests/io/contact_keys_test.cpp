// The scene keys of contacts (docs/scenes.md): a collider's "friction" and "restitution", a body's "contact" object.
// Each key reaches the description and the worlds built from it in either precision, a world described back and
// rebuilt keeps its contact bodies and materials, and each bad value is an error naming the file and the key.
#include "error_checks.hpp"
#include "temp_dir.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <string>

namespace pbd {
namespace {

using test::replaced;

// One body of each type, three with a contact object (cloth, particles, mesh) and the rope without; colliders with
// each form of the material keys. Particles: cloth [0, 9), rope [9, 13), particles [13, 15), mesh [15, 47).
const std::string kContacts = R"({"name": "c", "dt": 0.01, "substeps": 2,
  "bodies": [
    {"type": "cloth", "resolution": 3, "pin": "none",
     "contact": {"radius": 0.05, "friction": {"static": 0.6, "kinetic": 0.4}, "restitution": 0.2, "self_collision": true}},
    {"type": "rope", "particles": 4, "origin": [2, 0, 1]},
    {"type": "particles", "positions": [[0, 0, 2], [0, 0, 3]], "contact": {"radius": 0.1, "friction": 0.3}},
    {"type": "mesh", "generator": {"type": "dodecahedron", "radius": 0.2}, "origin": [0, 0, 4], "contact": {}}
  ],
  "colliders": [
    {"type": "plane", "normal": [0, 0, 1], "offset": 0, "friction": 0.5, "restitution": 0.75},
    {"type": "sphere", "center": [0, 0, -1], "radius": 0.5, "friction": {"kinetic": 0.25}},
    {"type": "sphere", "center": [3, 0, 0], "radius": 0.5, "friction": {"static": 0.125}},
    {"type": "plane", "normal": [1, 0, 0], "offset": -10}
  ]
})";

void expect_material(const ContactMaterial<double>& m, double static_friction, double kinetic_friction,
                     double restitution, const char* what) {
  EXPECT_EQ(m.static_friction, static_friction) << what;
  EXPECT_EQ(m.kinetic_friction, kinetic_friction) << what;
  EXPECT_EQ(m.restitution, restitution) << what;
}

TEST(SceneContacts, ColliderFrictionAndRestitutionInEachForm) {
  const WorldDescription d = parse_scene(kContacts, "c.json").world;
  ASSERT_EQ(d.planes.size(), 2u);
  ASSERT_EQ(d.spheres.size(), 2u);
  expect_material(d.planes[0].material, 0.5, 0.5, 0.75, "a number: static and kinetic alike");
  expect_material(d.spheres[0].material, 0.25, 0.25, 0.0, "kinetic only: static takes its value");
  expect_material(d.spheres[1].material, 0.125, 0.125, 0.0, "static only: kinetic takes its value");
  expect_material(d.planes[1].material, 0.0, 0.0, 0.0, "no keys: no friction, no bounce");
  const WorldDescription both = parse_scene(
      replaced(kContacts, "\"friction\": 0.5", "\"friction\": {\"static\": 0.9, \"kinetic\": 0.7}"), "c.json").world;
  expect_material(both.planes[0].material, 0.9, 0.7, 0.75, "both given");
}

TEST(SceneContacts, ABodyWithAContactObjectIsAContactBodyOverExactlyItsParticles) {
  const WorldDescription d = parse_scene(kContacts, "c.json").world;
  ASSERT_EQ(d.num_particles(), 47u);
  ASSERT_EQ(d.contact_bodies.size(), 3u);  // the rope has no "contact": not a contact body
  const ContactBody<double>& cloth = d.contact_bodies[0];
  EXPECT_EQ(cloth.first, 0u);
  EXPECT_EQ(cloth.count, 9u);
  EXPECT_EQ(cloth.radius, 0.05);
  EXPECT_TRUE(cloth.self_collision);
  expect_material(cloth.material, 0.6, 0.4, 0.2, "cloth");
  const ContactBody<double>& particles = d.contact_bodies[1];
  EXPECT_EQ(particles.first, 13u);
  EXPECT_EQ(particles.count, 2u);
  EXPECT_EQ(particles.radius, 0.1);
  EXPECT_FALSE(particles.self_collision);
  expect_material(particles.material, 0.3, 0.3, 0.0, "particles");
  const ContactBody<double>& mesh = d.contact_bodies[2];  // an empty object: every default
  EXPECT_EQ(mesh.first, 15u);
  EXPECT_EQ(mesh.count, 32u);
  EXPECT_EQ(mesh.radius, 0.0);
  EXPECT_FALSE(mesh.self_collision);
  expect_material(mesh.material, 0.0, 0.0, 0.0, "mesh");

  const WorldDescription rope = parse_scene(
      replaced(kContacts, "\"origin\": [2, 0, 1]}", "\"origin\": [2, 0, 1], \"contact\": {\"radius\": 0.01}}"),
      "c.json").world;
  ASSERT_EQ(rope.contact_bodies.size(), 4u);
  EXPECT_EQ(rope.contact_bodies[1].first, 9u);
  EXPECT_EQ(rope.contact_bodies[1].count, 4u);
  EXPECT_EQ(rope.contact_bodies[1].radius, 0.01);
}

// The world built in Real holds Real(value) of every contact value; described back and rebuilt, it holds the same.
template <class Real> void expect_round_trip(const WorldDescription& d) {
  auto same_material = [](const ContactMaterial<Real>& a, const ContactMaterial<Real>& b) {
    return a.static_friction == b.static_friction && a.kinetic_friction == b.kinetic_friction &&
           a.restitution == b.restitution;
  };
  auto cast = [](const ContactMaterial<double>& m) {
    return ContactMaterial<Real>{Real(m.static_friction), Real(m.kinetic_friction), Real(m.restitution)};
  };
  const World<Real> w = build_world<Real>(d);
  const World<Real> again = build_world<Real>(describe_world(w));
  for (const World<Real>* world : {&w, &again}) {
    const char* which = world == &w ? "built" : "rebuilt";
    ASSERT_EQ(world->contact_bodies().size(), d.contact_bodies.size()) << which;
    for (std::size_t i = 0; i < d.contact_bodies.size(); ++i) {
      const ContactBody<Real>& b = world->contact_bodies()[i];
      EXPECT_EQ(b.first, d.contact_bodies[i].first) << which << " " << i;
      EXPECT_EQ(b.count, d.contact_bodies[i].count) << which << " " << i;
      EXPECT_EQ(b.radius, Real(d.contact_bodies[i].radius)) << which << " " << i;
      EXPECT_EQ(b.self_collision, d.contact_bodies[i].self_collision) << which << " " << i;
      EXPECT_TRUE(same_material(b.material, cast(d.contact_bodies[i].material))) << which << " " << i;
    }
    ASSERT_EQ(world->colliders().planes.size(), d.planes.size()) << which;
    for (std::size_t i = 0; i < d.planes.size(); ++i)
      EXPECT_TRUE(same_material(world->colliders().planes[i].material, cast(d.planes[i].material))) << which << i;
    ASSERT_EQ(world->colliders().spheres.size(), d.spheres.size()) << which;
    for (std::size_t i = 0; i < d.spheres.size(); ++i)
      EXPECT_TRUE(same_material(world->colliders().spheres[i].material, cast(d.spheres[i].material))) << which << i;
  }
}

TEST(SceneContacts, ContactBodiesAndMaterialsSurviveTheRoundTripInEitherPrecision) {
  // 0.3 and 0.1 are not floats: the float world holds their rounding, and its description gives that back.
  const WorldDescription d = parse_scene(kContacts, "c.json").world;
  expect_round_trip<float>(d);
  expect_round_trip<double>(d);
  const WorldDescription back = describe_world(build_world<double>(d));  // in double: exactly the description
  ASSERT_EQ(back.contact_bodies.size(), d.contact_bodies.size());
  for (std::size_t i = 0; i < d.contact_bodies.size(); ++i) {
    EXPECT_EQ(back.contact_bodies[i].radius, d.contact_bodies[i].radius) << i;
    EXPECT_EQ(back.contact_bodies[i].material.kinetic_friction, d.contact_bodies[i].material.kinetic_friction) << i;
  }
  EXPECT_EQ(back.planes[0].material.restitution, 0.75);
}

TEST(SceneContacts, ASceneWithContactsStepsInEitherPrecision) {
  const WorldDescription d = parse_scene(kContacts, "c.json").world;
  World<float> f = build_world<float>(d);
  World<double> w = build_world<double>(d);
  for (int i = 0; i < 20; ++i) {
    f.step();
    w.step();
  }
  EXPECT_TRUE(f.positions().allFinite());
  EXPECT_TRUE(w.positions().allFinite());
}

// End to end: the friction of a scene reaches the engine, mixed as docs/scenes.md says. One particle slides at 1 m/s
// on the ground; after 0.5 s a friction of 1 (µg = 9.81 m/s² of deceleration) has stopped it, while without friction,
// or in a contact body whose own friction is 0 (√(1 · 0) = 0), it keeps its speed.
TEST(SceneContacts, FrictionMixesAsTheGeometricMeanOfBothSides) {
  const std::string slide = R"({"name": "s", "dt": 0.01, "substeps": 4,
    "bodies": [{"type": "particles", "positions": [[0, 0, 0]], "velocities": [[1, 0, 0]]}],
    "colliders": [{"type": "plane", "normal": [0, 0, 1], "offset": 0, "friction": 1}]})";
  auto speed_after = [](const std::string& text) {
    World<double> w = build_world<double>(parse_scene(text, "s.json").world);
    for (int i = 0; i < 50; ++i) w.step();
    return w.velocities()(0, 0);
  };
  EXPECT_NEAR(speed_after(slide), 0.0, 1e-9);  // a particle in no contact body: the plane's friction alone
  EXPECT_NEAR(speed_after(replaced(slide, "\"friction\": 1", "\"friction\": 0")), 1.0, 1e-9);
  const std::string body = replaced(slide, "\"velocities\": [[1, 0, 0]]",
                                    "\"velocities\": [[1, 0, 0]], \"contact\": {\"friction\": 0}");
  EXPECT_NEAR(speed_after(body), 1.0, 1e-9);
  EXPECT_NEAR(speed_after(replaced(body, "{\"friction\": 0}", "{\"friction\": 4}")), 0.0, 1e-9);  // √(1·4) = 2
}

// Parses `text` as "bad.json" and expects a pbd::Error naming the file, the key path and every one of `words`.
void expect_error(const std::string& text, const std::string& key, std::initializer_list<std::string> words) {
  const std::string msg = test::error_of([&] { parse_scene(text, "bad.json"); });
  EXPECT_EQ(msg.rfind("bad.json: " + key + ": ", 0), 0u) << "should start with the file and " << key << ": " << msg;
  test::expect_words(msg, words);
}

TEST(SceneContactErrors, OutOfRangeValuesNameTheFileAndTheKey) {
  expect_error(replaced(kContacts, "\"radius\": 0.05", "\"radius\": -0.05"), "/bodies/0/contact/radius",
               {"out of range [0, 1000000]"});
  expect_error(replaced(kContacts, "\"radius\": 0.05", "\"radius\": 1e7"), "/bodies/0/contact/radius", {"out of range"});
  expect_error(replaced(kContacts, "\"static\": 0.6", "\"static\": -0.6"), "/bodies/0/contact/friction/static",
               {"out of range [0, inf]"});
  expect_error(replaced(kContacts, "\"kinetic\": 0.4", "\"kinetic\": -1e-9"), "/bodies/0/contact/friction/kinetic",
               {"out of range"});
  expect_error(replaced(kContacts, "\"friction\": 0.3", "\"friction\": -0.3"), "/bodies/2/contact/friction",
               {"out of range"});
  expect_error(replaced(kContacts, "\"restitution\": 0.2", "\"restitution\": 1.01"), "/bodies/0/contact/restitution",
               {"out of range [0, 1]"});
  expect_error(replaced(kContacts, "\"friction\": 0.5", "\"friction\": -2"), "/colliders/0/friction", {"out of range"});
  expect_error(replaced(kContacts, "\"kinetic\": 0.25", "\"kinetic\": -0.25"), "/colliders/1/friction/kinetic",
               {"out of range"});
  expect_error(replaced(kContacts, "\"static\": 0.125", "\"static\": -1"), "/colliders/2/friction/static",
               {"out of range"});
  expect_error(replaced(kContacts, "\"restitution\": 0.75", "\"restitution\": -0.1"), "/colliders/0/restitution",
               {"out of range [0, 1]"});
  expect_error(replaced(kContacts, "\"restitution\": 0.75", "\"restitution\": 2"), "/colliders/0/restitution",
               {"out of range [0, 1]"});
}

// A 20×20×20 lattice of grains 40 mm apart (8,000 particles) with the contact radius and margin given.
std::string grain_scene(const std::string& radius, const std::string& margin) {
  return R"({"name": "g", "dt": 0.01, "collision_margin": )" + margin + R"(,
    "bodies": [{"type": "grains", "count": [20, 20, 20], "spacing": 0.04, "origin": [0, 0, 1],
                "contact": {"radius": )" + radius + R"(, "self_collision": true}}]})";
}

TEST(SceneContactErrors, ARadiusOrMarginFarBeyondTheSpacingIsRefusedBeforeTheRun) {
  // Each would make every grain touch every other (n²/2 pairs: gigabytes); a pile's values load.
  EXPECT_NO_THROW(parse_scene(grain_scene("0.015", "0.003"), "ok.json"));
  expect_error(grain_scene("1e6", "0.003"), "/bodies/0/contact", {"radius 1000000", "cover", "spacing"});
  expect_error(grain_scene("0.5", "0.003"), "/bodies/0/contact", {"cover"});
  expect_error(grain_scene("0.015", "1e6"), "/bodies/0/contact", {"collision_margin 1000000", "cover"});
}

TEST(SceneContactErrors, ColliderLengthsWhoseSquaresOverflowFloatNameTheKey) {
  const std::string sphere = R"({"type": "sphere", "center": [0, 0, -1], "radius": 0.5, "friction": {"kinetic": 0.25}})";
  expect_error(replaced(kContacts, sphere, R"({"type": "sphere", "center": [0, 0, -1], "radius": 3e38})"),
               "/colliders/1/radius", {"out of range"});
  expect_error(replaced(kContacts, sphere, R"({"type": "sphere", "center": [0, 0, -3e38], "radius": 1})"),
               "/colliders/1/center", {"at most"});
  expect_error(replaced(kContacts, "\"offset\": -10", "\"offset\": -3e38"), "/colliders/3/offset", {"at most"});
}

TEST(SceneContactErrors, ABodyStartingInsideAColliderIsRefusedNamingTheBodyAndTheParticle) {
  // A dodecahedron half inside the ground: its first step would push it out at once and keep the push as velocity.
  const std::string half_in = replaced(kContacts, R"("origin": [0, 0, 4], "contact": {})", R"("origin": [0, 0, 0.05], "contact": {})");
  const std::string msg = test::error_of([&] { parse_scene(half_in, "bad.json"); });
  EXPECT_EQ(msg.rfind("bad.json: /bodies/3: particle ", 0), 0u) << msg;
  test::expect_words(msg, {"inside the collider at /colliders/0", "place the body outside"});
  // Resting on it loads, its contact radius overlapping the ground (a resting contact the first sub-step settles).
  const std::string on = replaced(kContacts, R"("origin": [0, 0, 4], "contact": {})",
                                  R"("origin": [0, 0, 0.2], "contact": {"radius": 0.05})");
  EXPECT_NO_THROW(parse_scene(on, "ok.json"));
}

TEST(SceneContactErrors, NonFiniteFrictionNamesTheKey) {
  // JSON has no NaN or infinity: the one non-finite number it can carry is one beyond double range.
  expect_error(replaced(kContacts, "\"friction\": 0.3", "\"friction\": 1e400"), "/bodies/2/contact/friction",
               {"line 6", "1e400"});
  expect_error(replaced(kContacts, "\"friction\": 0.5", "\"friction\": -1e999"), "/colliders/0/friction",
               {"-1e999"});
  expect_error(replaced(kContacts, "\"kinetic\": 0.25", "\"kinetic\": 1e400"), "/colliders/1/friction/kinetic",
               {"1e400"});
  expect_error(replaced(kContacts, "\"restitution\": 0.2", "\"restitution\": 1e400"), "/bodies/0/contact/restitution",
               {"1e400"});
  expect_error(replaced(kContacts, "\"radius\": 0.1", "\"radius\": 1e400"), "/bodies/2/contact/radius", {"1e400"});
}

TEST(SceneContactErrors, WrongTypesNameTheFileAndTheKey) {
  expect_error(replaced(kContacts, "\"self_collision\": true", "\"self_collision\": 1"),
               "/bodies/0/contact/self_collision", {"expected true or false", "got 1"});
  expect_error(replaced(kContacts, "\"self_collision\": true", "\"self_collision\": \"yes\""),
               "/bodies/0/contact/self_collision", {"expected true or false", "\"yes\""});
  expect_error(replaced(kContacts, "\"radius\": 0.05", "\"radius\": \"half_edge\""), "/bodies/0/contact/radius",
               {"expected a number"});
  expect_error(replaced(kContacts, "\"friction\": 0.5", "\"friction\": \"high\""), "/colliders/0/friction",
               {"expected a number or an object", "\"high\""});
  expect_error(replaced(kContacts, "\"friction\": 0.5", "\"friction\": [0.5, 0.4]"), "/colliders/0/friction",
               {"expected a number or an object", "an array"});
  expect_error(replaced(kContacts, "\"friction\": 0.3", "\"friction\": null"), "/bodies/2/contact/friction",
               {"expected a number or an object", "null"});
  expect_error(replaced(kContacts, "\"static\": 0.6", "\"static\": true"), "/bodies/0/contact/friction/static",
               {"expected a number"});
  expect_error(replaced(kContacts, "\"restitution\": 0.75", "\"restitution\": \"0.75\""), "/colliders/0/restitution",
               {"expected a number"});
  expect_error(replaced(kContacts, "\"contact\": {}", "\"contact\": true"), "/bodies/3/contact",
               {"expected an object"});
  expect_error(replaced(kContacts, "\"static\": 0.125", ""), "/colliders/2/friction",
               {"give \"static\", \"kinetic\" or both"});
}

TEST(SceneContactErrors, UnknownKeysInsideContactAndFriction) {
  expect_error(replaced(kContacts, "\"self_collision\"", "\"self_colision\""), "/bodies/0/contact/self_colision",
               {"unknown key"});
  expect_error(replaced(kContacts, "\"contact\": {}", "\"contact\": {\"mu\": 1}"), "/bodies/3/contact/mu",
               {"unknown key"});
  expect_error(replaced(kContacts, "\"kinetic\": 0.4", "\"dynamic\": 0.4"), "/bodies/0/contact/friction/dynamic",
               {"unknown key"});
  expect_error(replaced(kContacts, "{\"kinetic\": 0.25}", "{\"kinetic\": 0.25, \"rolling\": 0}"),
               "/colliders/1/friction/rolling", {"unknown key"});
  expect_error(replaced(kContacts, "\"restitution\": 0.75", "\"bounce\": 0.75"), "/colliders/0/bounce",
               {"unknown key"});
  // A collider has no contact object, and a body no collider keys: each is an unknown key where it is.
  expect_error(replaced(kContacts, "\"offset\": -10", "\"offset\": -10, \"contact\": {}"), "/colliders/3/contact",
               {"unknown key"});
  expect_error(replaced(kContacts, "\"origin\": [2, 0, 1]", "\"origin\": [2, 0, 1], \"friction\": 1"),
               "/bodies/1/friction", {"unknown key"});
}

TEST(SceneContactErrors, AFileNamesItsPathAndNothingIsLoaded) {
  test::TempDir dir("pbd_contact_keys");
  const auto file = dir / "bad.json";
  std::ofstream(file) << replaced(kContacts, "\"radius\": 0.05", "\"radius\": -1");
  const std::string msg = test::error_of([&] { load_scene(file); });
  test::expect_words(msg, {file.string() + ": /bodies/0/contact/radius: "});
}

}  // namespace
}  // namespace pbd
