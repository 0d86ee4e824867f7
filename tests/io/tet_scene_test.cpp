// Tet bodies in scenes: a box, a ball and an OBJ filled by tetgen, and a TetGen file, each built with the constraints
// its keys ask for; every malformed key is an error naming the body's key path.
#include "error_checks.hpp"
#include "temp_dir.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

namespace pbd {
namespace {

using test::error_of;
using test::expect_words;
using test::replaced;

const std::string kBar = R"({"name": "bar", "dt": 0.01,
  "bodies": [{"type": "tets", "generator": {"type": "box", "cells": [4, 1, 1], "size": [0.4, 0.1, 0.1]},
              "density": 500, "clamped": "x_min", "neo_hookean": {"young": 1e6, "poisson": 0.3},
              "tet_volume": {"compliance": 1e-9}}]
})";

TEST(TetScene, ABoxBarIsBuiltWithItsTetsClampedFaceAndMasses) {
  const Scene s = parse_scene(kBar, "bar.json");
  const World<double> w = build_world<double>(s.world);
  ASSERT_EQ(w.num_particles(), 5u * 2 * 2);
  EXPECT_EQ(w.constraints<NeoHookeanConstraint<double>>().size(), 24u);
  EXPECT_EQ(w.constraints<TetVolumeConstraint<double>>().size(), 24u);
  double mass = 0;
  int pinned = 0;
  for (Index i = 0; i < w.num_particles(); ++i) {
    if (w.inverse_masses()[i] == 0) {
      ++pinned;
      EXPECT_EQ(w.positions()(0, i), 0.0);
    } else {
      mass += 1 / w.inverse_masses()[i];
    }
  }
  EXPECT_EQ(pinned, 4);
  EXPECT_NEAR(mass, 500 * 0.4 * 0.01 * (1.0 - 0.25 * 0.5), 1e-12);  // the pinned corners' lumped share is gone
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].triangles.size(), std::size_t(4 * (4 + 4 + 1)));  // the boundary: 2 per cell face
  // μ/λ and the compliance 1/μ from E and ν (neo_hookean.hpp): μ = E / 2.6, λ = E / (2.6 · 0.4).
  const auto& c = w.constraints<NeoHookeanConstraint<double>>()[0];
  EXPECT_NEAR(c.ratio, 0.4, 1e-12);
  EXPECT_NEAR(w.constraint_sets()[c.set].compliance, 2.6 / 1e6, 1e-18);
}

// "stretch" on a tet body: a constraint on every edge of its tets, each once (a cube of the box has 12 edges, 6
// face diagonals and its long diagonal: 4 cells in a row share 4 x-faces of 4 edges and 1 diagonal each): stretch
// constraints from a stiffness, fibers from a curve.
TEST(TetScene, StretchOnATetBodyPutsOneConstraintOnEveryEdge) {
  const std::size_t edges = 4 * 19 - 3 * 5;
  const Scene plain = parse_scene(replaced(kBar, R"("tet_volume": {"compliance": 1e-9})",
                                           R"("tet_volume": {"compliance": 1e-9}, "stretch": {"compliance": 0})"),
                                  "bar.json");
  const World<double> a = build_world<double>(plain.world);
  EXPECT_EQ(a.constraints<StretchConstraint<double>>().size(), edges);
  EXPECT_EQ(a.constraints<FiberConstraint<double>>().size(), 0u);
  const Scene fibers = parse_scene(
      replaced(kBar, R"("tet_volume": {"compliance": 1e-9})",
               R"("tet_volume": {"compliance": 1e-9}, "stretch": {"material": {"stiffness": 5, "rupture_strain": 0.2}})"),
      "bar.json");
  const World<double> b = build_world<double>(fibers.world);
  ASSERT_EQ(b.constraints<FiberConstraint<double>>().size(), edges);
  std::vector<std::array<Index, 2>> seen;
  for (const auto& c : b.constraints<FiberConstraint<double>>()) {
    EXPECT_LT(c.particles[0], c.particles[1]);
    seen.push_back(c.particles);
  }
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());
}

// "tet_fibers": {"direction", a stiffness or a material}: one tet fiber on every tet, in the body's tet order, along
// that direction (its unit vector: b = Dm⁻¹·a0); a missing or zero direction names the key.
TEST(TetScene, TetFibersPutOneOnEveryTetAlongTheirDirection) {
  const Scene s = parse_scene(
      replaced(kBar, R"("tet_volume": {"compliance": 1e-9})",
               R"("tet_volume": {"compliance": 1e-9}, "tet_fibers": {"direction": [0, 3, 0], "material": {"stiffness": 2e4, "rupture_strain": 0.2}})"),
      "bar.json");
  const World<double> w = build_world<double>(s.world);
  const auto& tets = w.constraints<TetVolumeConstraint<double>>();
  const auto& fibers = w.constraints<TetFiberConstraint<double>>();
  ASSERT_EQ(fibers.size(), tets.size());
  for (std::size_t i = 0; i < fibers.size(); ++i) {
    EXPECT_EQ(fibers[i].particles, tets[i].particles);
    EXPECT_NEAR(fibers[i].volume, tets[i].rest, 1e-15);
    Eigen::Matrix3d dm;
    const auto& p = fibers[i].particles;
    dm << w.positions().col(p[1]) - w.positions().col(p[0]), w.positions().col(p[2]) - w.positions().col(p[0]),
        w.positions().col(p[3]) - w.positions().col(p[0]);
    EXPECT_LT((dm * fibers[i].weights - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);  // F·a0 = a0 at rest
  }
  EXPECT_EQ(w.constraint_sets()[fibers[0].set].mode, StiffnessMode::material);
  for (const char* bad : {R"("tet_fibers": {"compliance": 0})", R"("tet_fibers": {"direction": [0, 0, 0]})"}) {
    const std::string e = error_of([&] {
      parse_scene(replaced(kBar, R"("tet_volume": {"compliance": 1e-9})",
                           std::string(R"("tet_volume": {"compliance": 1e-9}, )") + bad),
                  "bar.json");
    });
    EXPECT_NE(e.find("bar.json: /bodies/0/tet_fibers"), std::string::npos) << e;
  }
}

// A tet body's contact body: its inner particles (on none of its boundary faces) are points (ContactBody::interior),
// so it touches other bodies and itself through its surface only: in a box of 4 × 2 × 2 cells, the 3 vertices off
// every face.
TEST(TetScene, ATetBodyTouchesOtherBodiesThroughItsSurface) {
  const std::string scene = replaced(replaced(kBar, "[4, 1, 1]", "[4, 2, 2]"), "\"density\": 500,",
                                     "\"density\": 500, \"contact\": {\"radius\": 0.01},");
  const World<double> w = build_world<double>(parse_scene(scene, "bar.json").world);
  ASSERT_EQ(w.num_particles(), 5u * 3 * 3);
  ASSERT_EQ(w.contact_bodies().size(), 1u);
  const std::vector<Index>& interior = w.contact_bodies()[0].interior;
  ASSERT_EQ(interior.size(), 3u);
  for (Index i : interior) {
    EXPECT_GT(w.positions()(0, i), 0.05);
    EXPECT_LT(w.positions()(0, i), 0.35);
    for (int d : {1, 2}) EXPECT_NEAR(w.positions()(d, i), w.positions()(d, 0) + 0.05, 1e-12);  // the middle of 0.1 m
  }
  EXPECT_TRUE(std::is_sorted(interior.begin(), interior.end()));
}

// A tet body touches itself through its surface: one body of two unit cubes (a TetGen file of two components), the
// upper one 0.5 m above the lower, falls onto it and rests corner on corner with self-collision (radius 0.05 m, the
// lower cube on the ground, damped); without it, it falls through to the ground.
TEST(TetScene, ASelfCollidingTetBodyRestsOnItself) {
  test::TempDir dir("tet_self");
  {
    std::ofstream node(dir.path() / "two.node");
    node << "16 3 0 0\n";
    const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int k = 0; k < 2; ++k)
      for (int i = 0; i < 8; ++i)
        node << 8 * k + i << " " << corner[i][0] << " " << corner[i][1] << " " << corner[i][2] + 1.5 * k + 0.1 << "\n";
    std::ofstream ele(dir.path() / "two.ele");
    ele << "10 4 0\n";
    const int tet[5][4] = {{0, 1, 3, 4}, {1, 2, 3, 6}, {1, 3, 4, 6}, {1, 4, 5, 6}, {3, 4, 6, 7}};
    for (int k = 0; k < 2; ++k)
      for (int t = 0; t < 5; ++t)
        ele << 5 * k + t << " " << 8 * k + tet[t][0] << " " << 8 * k + tet[t][1] << " " << 8 * k + tet[t][2] << " "
            << 8 * k + tet[t][3] << "\n";
  }
  for (bool self : {true, false}) {
    std::ofstream(dir.path() / "s.json")
        << R"({"name": "s", "dt": 0.01, "substeps": 10, "gravity": [0, 0, -9.81], "damping": 2, "bodies": [
      {"type": "tets", "file": "two.node", "neo_hookean": {"young": 1e6, "poisson": 0.3},
       "contact": {"radius": 0.05, "friction": 0.5, "self_collision": )"
        << (self ? "true" : "false") << R"(}}],
      "colliders": [{"type": "plane", "normal": [0, 0, 1], "offset": 0}]})";
    World<double> w = build_world<double>(load_scene(dir.path() / "s.json").world);
    for (int step = 0; step < 200; ++step) w.step();  // 2 s: the upper cube lands at about 0.4 s
    ASSERT_TRUE(w.positions().allFinite());
    for (Index i = 0; i < 4; ++i) {  // the upper cube's bottom corners 8..11 above the lower's top corners 4..7
      const double apart = (w.positions().col(8 + i) - w.positions().col(4 + i)).norm();
      if (self) EXPECT_NEAR(apart, 0.1, 0.01) << i;  // touching: two radii apart
      else EXPECT_LT(w.positions()(2, 8 + i), 0.6) << i;  // through the lower cube, near the ground
    }
  }
}

TEST(TetScene, BallsFilesAndObjSurfacesAreFilled) {
  test::TempDir dir("tet_scene");
  {
    std::ofstream(dir.path() / "cube.node") << "8 3 0 0\n0 0 0 0\n1 1 0 0\n2 1 1 0\n3 0 1 0\n4 0 0 1\n5 1 0 1\n6 1 1 1\n7 0 1 1\n";
    std::ofstream(dir.path() / "cube.ele") << "5 4 0\n0 0 1 3 4\n1 1 2 3 6\n2 1 3 4 6\n3 1 4 5 6\n4 3 4 6 7\n";
    std::ofstream(dir.path() / "tetra.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::ofstream(dir.path() / "s.json") << R"({"name": "s", "dt": 0.01, "bodies": [
      {"type": "tets", "file": "cube.node", "tet_volume": {}},
      {"type": "tets", "obj": "tetra.obj", "neo_hookean": {"young": 1e5, "poisson": 0.45}},
      {"type": "tets", "generator": {"type": "ball", "level": 1, "radius": 0.1}, "neo_hookean": {"young": 1e5, "poisson": 0}}]})";
  }
  const Scene s = load_scene(dir.path() / "s.json");
  const World<double> w = build_world<double>(s.world);
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[0].num_particles, 8u);
  EXPECT_EQ(w.constraints<TetVolumeConstraint<double>>().size(), 5u);
  EXPECT_EQ(s.bodies[1].num_particles, 4u);  // one tet: tetgen adds no point to a tetrahedron
  EXPECT_EQ(s.bodies[2].triangles.size(), 80u);  // the level-1 icosphere kept as the ball's surface
  EXPECT_GT(w.constraints<NeoHookeanConstraint<double>>().size(), 1u + 20u);
}

TEST(TetScene, ShapeMatchingMakesOneClusterPerVertex) {
  const std::string text = replaced(kBar, R"("tet_volume": {"compliance": 1e-9})",
                                    R"("shape_matching": {"stiffness": 0.5, "beta": 0.25})");
  const World<double> w = build_world<double>(parse_scene(text, "bar.json").world);
  const auto& clusters = w.constraints<ShapeMatchConstraint<double>>();
  ASSERT_EQ(clusters.size(), w.num_particles());
  EXPECT_EQ(clusters[3].beta, 0.25);
  EXPECT_EQ(w.constraint_sets()[clusters[3].set].k, 0.5);
  expect_words(error_of([&] { parse_scene(replaced(text, "0.25", "1.5"), "bar.json"); }),
               {"/bodies/0/shape_matching/beta"});
  expect_words(error_of([&] { parse_scene(replaced(text, "\"beta\"", "\"alpha\""), "bar.json"); }),
               {"/bodies/0/shape_matching", "alpha"});
}

// "vertex_order": "spatial" renumbers a tet body's vertices (tet_mesh.hpp's spatially_ordered) before anything else:
// the same particles and tets, the clamped face found in the new order; "blocking" sets the block solver's
// partition.
TEST(TetScene, SpatialVertexOrderAndBlockingKeys) {
  const std::string long_bar = replaced(kBar, "[4, 1, 1]", "[40, 1, 1]");  // 164 vertices: more than a leaf of 32
  const std::string text = replaced(replaced(long_bar, "\"density\": 500", "\"vertex_order\": \"spatial\", \"density\": 500"),
                                    "\"dt\": 0.01,", "\"dt\": 0.01, \"blocking\": {\"constraints_per_block\": 7, \"metis\": false},");
  const Scene spatial = parse_scene(text, "bar.json");
  const Scene mesh = parse_scene(long_bar, "bar.json");
  const World<double> w = build_world<double>(spatial.world), v = build_world<double>(mesh.world);
  ASSERT_EQ(w.num_particles(), v.num_particles());
  EXPECT_NE(w.positions(), v.positions());  // renumbered
  int pinned = 0;
  for (Index i = 0; i < w.num_particles(); ++i)
    if (w.inverse_masses()[i] == 0) {
      ++pinned;
      EXPECT_EQ(w.positions()(0, i), 0.0);
    }
  EXPECT_EQ(pinned, 4);
  EXPECT_EQ(w.constraints<NeoHookeanConstraint<double>>().size(), 240u);
  EXPECT_EQ(w.blocking().constraints_per_block, 7u);
  EXPECT_FALSE(w.blocking().use_metis);
  EXPECT_EQ(v.blocking().constraints_per_block, BlockOptions{}.constraints_per_block);
  auto expect = [&](const std::string& from, const std::string& to, std::initializer_list<std::string> words) {
    const std::string bad = replaced(text, from, to);
    ASSERT_NE(bad, text) << from;
    expect_words(error_of([&] { parse_scene(bad, "bar.json"); }), words);
  };
  expect("\"spatial\"", "\"random\"", {"/bodies/0/vertex_order", "random", "spatial"});
  expect("\"constraints_per_block\": 7", "\"constraints_per_block\": 0", {"/blocking/constraints_per_block"});
  expect("\"metis\": false", "\"metis\": false, \"parts\": 2", {"/blocking", "parts"});
}

TEST(TetScene, MalformedTetBodiesNameTheirKey) {
  auto expect = [](const std::string& from, const std::string& to, std::initializer_list<std::string> words) {
    const std::string text = replaced(kBar, from, to);
    ASSERT_NE(text, kBar) << from;
    expect_words(error_of([&] { parse_scene(text, "bar.json"); }), words);
  };
  expect("\"type\": \"box\"", "\"type\": \"sphere\"", {"bar.json", "/bodies/0/generator/type", "unknown tet generator"});
  expect("[4, 1, 1]", "[4, 0, 1]", {"/bodies/0/generator/cells/1"});
  expect("[4, 1, 1]", "[4, 1]", {"/bodies/0/generator/cells", "3 integers"});
  expect("[0.4, 0.1, 0.1]", "[0.4, -0.1, 0.1]", {"/bodies/0/generator/size"});
  expect("\"x_min\"", "\"x_low\"", {"/bodies/0/clamped", "x_min"});
  expect("\"poisson\": 0.3", "\"poisson\": 0.5", {"/bodies/0/neo_hookean/poisson", "(-1, 0.5)"});
  expect("\"young\": 1e6", "\"young\": -1", {"/bodies/0/neo_hookean/young"});
  expect("\"young\": 1e6, ", "", {"/bodies/0/neo_hookean", "young"});
  expect("\"density\": 500", "\"density\": 0", {"/bodies/0/density"});
  expect("\"poisson\": 0.3}", "\"poisson\": 0.3, \"shear\": 1}", {"/bodies/0/neo_hookean", "shear"});
  expect(R"("neo_hookean": {"young": 1e6, "poisson": 0.3},
              "tet_volume": {"compliance": 1e-9})", R"("scale": 1)", {"/bodies/0", "neo_hookean"});
  expect("\"generator\": {\"type\": \"box\", \"cells\": [4, 1, 1], \"size\": [0.4, 0.1, 0.1]}",
         "\"file\": \"missing.msh\"", {"/bodies/0/file", "missing.msh"});
  expect("\"generator\": {\"type\": \"box\", \"cells\": [4, 1, 1], \"size\": [0.4, 0.1, 0.1]}",
         "\"file\": \"bar.stl\"", {"/bodies/0/file", ".msh"});
  expect("\"density\": 500", "\"file\": \"x.msh\", \"density\": 500", {"/bodies/0", "exactly one of"});
  expect("\"cells\": [4, 1, 1]", "\"cells\": [100000, 100000, 100000]", {"/bodies/0/generator/cells", "limit"});
  // 12 million cubes: their Neo-Hookean and volume tets (144 million) fit the limit of 200 million constraints; with
  // a tet fiber on every tet too (216 million) they do not, and the scene is refused before anything is built.
  const std::string big = replaced(replaced(kBar, "[4, 1, 1]", "[200, 200, 300]"), R"("tet_volume": {"compliance": 1e-9})",
                                   R"("tet_volume": {"compliance": 1e-9}, "tet_fibers": {"direction": [1, 0, 0]})");
  expect_words(error_of([&] { parse_scene(big, "bar.json"); }), {"/bodies/0/generator/cells", "limit"});
}

}  // namespace
}  // namespace pbd
