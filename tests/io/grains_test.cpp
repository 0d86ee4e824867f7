// The "grains" body (add_grains, generators.hpp): a jittered lattice of loose particles. Its keys reach the
// description, its jitter is the documented splitmix64 sequence (the same positions for the same seed, bit for bit, in
// every target), and each bad value is an error naming the file and the key.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>

namespace pbd {
namespace {

using test::replaced;

const std::string kGrains = R"({"name": "g", "dt": 0.01,
  "bodies": [
    {"type": "particles", "positions": [[5, 5, 5]]},
    {"type": "grains", "count": [4, 3, 2], "spacing": 0.1, "origin": [1, 2, 3], "jitter": 0.2, "seed": 7,
     "mass": 0.5, "velocity": [0, 0, -2], "contact": {"radius": 0.04, "friction": 0.4, "self_collision": true}}
  ]
})";

TEST(Grains, SplitMix64GivesItsReferenceSequence) {
  std::uint64_t state = 0;  // the reference outputs of splitmix64 from seed 0 (Vigna's splitmix64.c)
  EXPECT_EQ(splitmix64(state), 0xe220a8397b1dcdafull);
  EXPECT_EQ(splitmix64(state), 0x6e789e6aa1b965f4ull);
}

TEST(Grains, ParsesEveryKeyOntoTheLattice) {
  const Scene s = parse_scene(kGrains, "g.json");
  const WorldDescription& d = s.world;
  ASSERT_EQ(d.num_particles(), 1u + 24u);
  EXPECT_EQ(d.num_constraints(), 0u);
  EXPECT_TRUE(s.triangles.empty());
  ASSERT_EQ(d.contact_bodies.size(), 1u);
  EXPECT_EQ(d.contact_bodies[0].first, 1u);  // exactly the grains
  EXPECT_EQ(d.contact_bodies[0].count, 24u);
  EXPECT_EQ(d.contact_bodies[0].radius, 0.04);
  EXPECT_TRUE(d.contact_bodies[0].self_collision);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const Index p = 1 + Index((k * 3 + j) * 4 + i);  // (k·ny + j)·nx + i after the one particle before
        // Lattice point: the bottom layer's centre at origin, layers going up from it.
        const Eigen::Vector3d lattice(1 + (i - 1.5) * 0.1, 2 + (j - 1.0) * 0.1, 3 + k * 0.1);
        const Eigen::Vector3d off = d.positions.col(p) - lattice;
        EXPECT_LT(off.cwiseAbs().maxCoeff(), 0.2 * 0.1 + 1e-12) << p;  // within jitter × spacing per coordinate
        EXPECT_GT(off.norm(), 0.0) << p;
        EXPECT_DOUBLE_EQ(d.inverse_masses[p], 2.0) << p;
        EXPECT_EQ(d.velocities.col(p), Eigen::Vector3d(0, 0, -2)) << p;
      }
  EXPECT_EQ(d.velocities.col(0), Eigen::Vector3d::Zero());  // the body before keeps its own velocity
}

TEST(Grains, DefaultsAndNoJitterGiveTheExactLattice) {
  const Scene s = parse_scene(R"({"name": "g", "dt": 0.01,
    "bodies": [{"type": "grains", "count": [2, 1, 3], "spacing": 0.5, "jitter": 0}]})", "g.json");
  const WorldDescription& d = s.world;
  ASSERT_EQ(d.num_particles(), 6u);
  EXPECT_EQ(d.positions.col(0), Eigen::Vector3d(-0.25, 0, 0));
  EXPECT_EQ(d.positions.col(1), Eigen::Vector3d(0.25, 0, 0));
  EXPECT_EQ(d.positions.col(5), Eigen::Vector3d(0.25, 0, 1.0));
  for (Index i = 0; i < 6; ++i) EXPECT_EQ(d.inverse_masses[i], 1.0);  // mass 1 kg each
  EXPECT_TRUE(d.velocities.isZero());
  EXPECT_TRUE(d.contact_bodies.empty());  // no "contact": the grains touch colliders only as points
}

TEST(Grains, TheJitterIsTheDocumentedSplitMixSequence) {
  // One grain at the origin, spacing 1, jitter 1/4, seed 1: each coordinate is u/4 with u = k·2^-52 − 1 from the top
  // 53 bits of splitmix64's first three outputs (0x910a2dec89025cc1, 0xbeeb8da1658eec67, 0xf893a2eefb32555e).
  GrainsOptions g;
  g.spacing = 1.0;
  g.jitter = 0.25;
  DescriptionBuilder b;
  add_grains(b, g);
  EXPECT_EQ(b.positions().col(0), Eigen::Vector3d(0x1.10a2dec890258p-5, 0x1.f75c6d0b2c774p-4, 0x1.e24e8bbbecc94p-3));
}

TEST(Grains, TheSameSeedGivesTheSamePositionsInEveryTarget) {
  GrainsOptions g;
  g.count = {5, 4, 3};
  g.spacing = 0.03;
  g.origin = {0.1, -0.2, 0.05};
  g.jitter = 0.3;
  g.seed = 12345;
  g.mass = 0.01;
  g.velocity = {1, 0, 0};
  DescriptionBuilder a, b;
  World<double> wd;
  World<float> wf;
  const Body ba = add_grains(a, g);
  add_grains(b, g);
  add_grains(wd, g);
  add_grains(wf, g);
  EXPECT_EQ(ba.first_particle, 0u);
  EXPECT_EQ(ba.num_particles, 60u);
  EXPECT_TRUE(ba.triangles.empty());
  EXPECT_EQ(a.positions(), b.positions()) << "same options, same seed: the same bits";
  EXPECT_EQ(Matrix3X<double>(wd.positions()), a.positions()) << "World<double> and the description agree";
  EXPECT_EQ(Matrix3X<float>(wf.positions()), a.positions().cast<float>()) << "World<float> holds their cast";
  EXPECT_EQ(Matrix3X<double>(wd.velocities()), a.description().velocities);
  // Described back and rebuilt: the same positions, velocities and masses.
  const WorldDescription again = describe_world(build_world<double>(a.description()));
  EXPECT_EQ(again.positions, a.positions());
  EXPECT_EQ(again.velocities, a.description().velocities);
  EXPECT_EQ(again.inverse_masses, a.description().inverse_masses);
  // Another seed moves every grain.
  DescriptionBuilder c;
  g.seed = 12346;
  add_grains(c, g);
  for (Index i = 0; i < 60; ++i) EXPECT_NE(c.positions().col(i), a.positions().col(i)) << i;
}

TEST(Grains, AScenesGrainsAreTheSameOnEveryLoad) {
  const Scene s1 = parse_scene(kGrains, "g.json");
  const Scene s2 = parse_scene(kGrains, "g.json");
  EXPECT_EQ(s1.world.positions, s2.world.positions);
  const Scene other = parse_scene(replaced(kGrains, "\"seed\": 7", "\"seed\": 8"), "g.json");
  EXPECT_NE(other.world.positions, s1.world.positions);
  const Scene no_seed = parse_scene(replaced(kGrains, "\"seed\": 7,", ""), "g.json");  // the default seed is 1
  const Scene seed_1 = parse_scene(replaced(kGrains, "\"seed\": 7", "\"seed\": 1"), "g.json");
  EXPECT_EQ(no_seed.world.positions, seed_1.world.positions);
}

TEST(Grains, TheGeneratorRefusesBadOptionsAndAddsNothing) {
  auto refuses = [](auto edit, std::initializer_list<std::string> words) {
    GrainsOptions g;
    edit(g);
    DescriptionBuilder b;
    test::expect_words(test::error_of([&] { add_grains(b, g); }), words);
    EXPECT_EQ(b.num_particles(), 0u);
  };
  refuses([](GrainsOptions& g) { g.count = {3, 0, 3}; }, {"add_grains", "count[1]", ">= 1"});
  refuses([](GrainsOptions& g) { g.count = {100000, 100000, 1}; }, {"add_grains", "more than a world can index"});
  refuses([](GrainsOptions& g) { g.count = {60000, 60000, 2}; }, {"add_grains", "more than a world can index"});
  refuses([](GrainsOptions& g) { g.spacing = 0.0; }, {"add_grains", "spacing"});
  refuses([](GrainsOptions& g) { g.spacing = std::nan(""); }, {"add_grains", "spacing"});
  refuses([](GrainsOptions& g) { g.jitter = 0.5; }, {"add_grains", "jitter", "[0, 0.5)"});
  refuses([](GrainsOptions& g) { g.jitter = -0.1; }, {"add_grains", "jitter"});
  refuses([](GrainsOptions& g) { g.mass = 0.0; }, {"add_grains", "mass"});
  refuses([](GrainsOptions& g) { g.origin[2] = INFINITY; }, {"add_grains", "origin"});
  refuses([](GrainsOptions& g) { g.velocity[0] = std::nan(""); }, {"add_grains", "velocity"});
}

// Parses `text` and expects a pbd::Error naming the file and every one of `words`.
void expect_error(const std::string& text, std::initializer_list<std::string> words) {
  const std::string msg = test::error_of([&] { parse_scene(text, "bad.json"); });
  test::expect_words(msg, {"bad.json"});
  test::expect_words(msg, words);
}

TEST(GrainsErrors, EachBadKeyIsNamed) {
  const std::string count = "\"count\": [4, 3, 2]";
  expect_error(replaced(kGrains, count + ", ", ""), {"/bodies/1/count", "missing"});
  expect_error(replaced(kGrains, count, "\"count\": [4, 3]"), {"/bodies/1/count", "[nx, ny, nz]"});
  expect_error(replaced(kGrains, count, "\"count\": [4, 3, 2, 1]"), {"/bodies/1/count", "[nx, ny, nz]"});
  expect_error(replaced(kGrains, count, "\"count\": 24"), {"/bodies/1/count", "array"});
  expect_error(replaced(kGrains, count, "\"count\": [4, 0, 2]"), {"/bodies/1/count/1", "out of range"});
  expect_error(replaced(kGrains, count, "\"count\": [4, -3, 2]"), {"/bodies/1/count/1", "out of range"});
  expect_error(replaced(kGrains, count, "\"count\": [4, 3, 2.5]"), {"/bodies/1/count/2", "integer"});
  expect_error(replaced(kGrains, count, "\"count\": [4, \"3\", 2]"), {"/bodies/1/count/1", "integer"});
  expect_error(replaced(kGrains, count, "\"count\": [10000, 10000, 1]"), {"/bodies/1/count", "100000000 particles", "limit"});
  expect_error(replaced(kGrains, count, "\"count\": [5000, 5000, 3]"), {"/bodies/1/count", "75000000", "limit"});
  expect_error(replaced(kGrains, count, "\"count\": [50000000, 50000000, 50000000]"), {"/bodies/1/count", "limit"});
  expect_error(replaced(kGrains, "\"spacing\": 0.1, ", ""), {"/bodies/1/spacing", "missing"});
  expect_error(replaced(kGrains, "\"spacing\": 0.1", "\"spacing\": 0"), {"/bodies/1/spacing", "out of range"});
  expect_error(replaced(kGrains, "\"spacing\": 0.1", "\"spacing\": -1"), {"/bodies/1/spacing", "out of range"});
  expect_error(replaced(kGrains, "\"jitter\": 0.2", "\"jitter\": 0.5"), {"/bodies/1/jitter", "below 0.5"});
  expect_error(replaced(kGrains, "\"jitter\": 0.2", "\"jitter\": 0.7"), {"/bodies/1/jitter", "out of range"});
  expect_error(replaced(kGrains, "\"jitter\": 0.2", "\"jitter\": -0.01"), {"/bodies/1/jitter", "out of range"});
  expect_error(replaced(kGrains, "\"seed\": 7", "\"seed\": -1"), {"/bodies/1/seed", "out of range"});
  expect_error(replaced(kGrains, "\"seed\": 7", "\"seed\": 1.5"), {"/bodies/1/seed", "integer"});
  expect_error(replaced(kGrains, "\"mass\": 0.5", "\"mass\": 0"), {"/bodies/1/mass", "out of range"});
  expect_error(replaced(kGrains, "\"origin\": [1, 2, 3]", "\"origin\": [1, 2]"), {"/bodies/1/origin"});
  expect_error(replaced(kGrains, "\"velocity\": [0, 0, -2]", "\"velocity\": [0, \"a\", 0]"), {"/bodies/1/velocity/1"});
  expect_error(replaced(kGrains, "\"seed\": 7", "\"sead\": 7"), {"/bodies/1/sead", "unknown key"});
  expect_error(replaced(kGrains, "\"seed\": 7", "\"stretch\": {}"), {"/bodies/1/stretch", "unknown key"});
  expect_error(replaced(kGrains, "\"grains\"", "\"grain\""), {"/bodies/1/type", "\"grains\""});
  // The particles before count against the scene's limit too.
  expect_error(replaced(kGrains, count, "\"count\": [1000, 1000, 50]"), {"/bodies/1/count", "with the 1 of the bodies before it"});
}

}  // namespace
}  // namespace pbd
