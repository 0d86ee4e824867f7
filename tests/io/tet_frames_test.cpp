// Frames of tet bodies: which tets frame_topology draws (from Neo-Hookean and tet volume constraints, each tet once,
// body by body), the VTK_TETRA cells of a VTU frame with their volume_ratio and strain against a known affine
// stretch, tet arrays only in frames with tets, and the OBJ frame of a tet body (its surface only).
#include "error_checks.hpp"
#include "pbd/io/frame_writer.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/vtu_frame.hpp"
#include "pbd/metrics.hpp"
#include "vtu_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace pbd {
namespace {

using test::count_of;
using test::cells_of;
using test::data_array;
using test::of_body;

// A 2 × 1 × 1 box (12 particles, 12 tets) with the constraints `kinds` asks for ("neo_hookean", "volume" or "both"), added to
// `world` after whatever it holds; its scene body, named `name`.
SceneBody add_box(World<double>& world, const std::string& kinds, const std::string& name,
                  std::array<double, 3> origin = {0, 0, 0}) {
  TetConstraintSets sets;
  if (kinds != "volume") sets.neo_hookean = world.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
  if (kinds != "neo_hookean") sets.volume = world.add_constraint_set(Stiffness::xpbd_compliance(0.0));
  sets.ratio = 0.5;
  TetBodyOptions options;
  options.origin = origin;
  const Body b = add_tet_body(world, tet_box_mesh({2, 1, 1}, {0.2, 0.1, 0.1}), options, sets);
  return {name, b.first_particle, b.num_particles, b.triangles};
}

// Moves every particle by x → diag(s, 1, 1)·x about the origin.
void stretch_x(World<double>& world, double s) {
  auto x = world.positions();
  for (Eigen::Index i = 0; i < x.cols(); ++i) x(0, i) *= s;
}

TEST(TetFrames, TopologyDrawsEachTetOnceWithItsRestShape) {
  const TetMesh mesh = tet_box_mesh({2, 1, 1}, {0.2, 0.1, 0.1});
  for (const std::string kinds : {"neo_hookean", "volume", "both"}) {
    World<double> w;
    const SceneBody body = add_box(w, kinds, "tets_0");
    const FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
    ASSERT_EQ(t.bodies.size(), 1u);
    const FrameBody& b = t.bodies[0];
    EXPECT_EQ(b.tets, mesh.tets) << kinds << ": one tet per mesh tet, in its order and corner order";
    ASSERT_EQ(b.tet_rest.size(), mesh.tets.size()) << kinds;
    for (std::size_t k = 0; k < b.tets.size(); ++k) {
      EXPECT_NEAR(b.tet_rest[k].volume, 0.001 / 6, 1e-18) << kinds << " tet " << k;
      // Dm⁻¹ comes from the Neo-Hookean constraint, so with "both" too; a volume constraint has none.
      EXPECT_EQ(b.tet_rest[k].inverse_rest.has_value(), kinds != "volume") << kinds << " tet " << k;
    }
    EXPECT_TRUE(b.lines.empty()) << kinds;
  }
}

TEST(TetFrames, ATetOfSeveralConstraintsInAnyCornerOrderIsDrawnOnceAndOnlyInsideOneBody) {
  World<double> w;
  const SceneBody a = add_box(w, "neo_hookean", "tets_0");
  const SceneBody b = add_box(w, "volume", "tets_1", {1, 0, 0});
  // The first tet again, its corners in another order; and a tet from box a to box b (drawn by neither).
  const auto first = w.constraints<NeoHookeanConstraint<double>>()[0].particles;
  w.add(TetVolumeConstraint<double>{{first[2], first[0], first[3], first[1]}, 0, 1.0});
  w.add(TetVolumeConstraint<double>{{0, 1, 2, a.num_particles}, 0, 1.0});
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{a, b});
  ASSERT_EQ(t.bodies.size(), 2u);
  EXPECT_EQ(t.bodies[0].tets.size(), 12u);
  EXPECT_EQ(t.bodies[0].tets[0], first);
  EXPECT_TRUE(t.bodies[0].tet_rest[0].inverse_rest.has_value()) << "the Neo-Hookean constraint names it first";
  ASSERT_EQ(t.bodies[1].tets.size(), 12u);
  EXPECT_EQ(t.bodies[1].tets[0][0], b.first_particle) << "world particle indices";
  // Without a scene: one body with every tet.
  EXPECT_EQ(frame_topology(w, std::vector<std::array<Index, 3>>{}).bodies[0].tets.size(), 25u);
}

TEST(TetFrames, CheckNamesTheTetOutsideItsBody) {
  World<double> w;
  const SceneBody a = add_box(w, "volume", "tets_0");
  FrameTopology t = frame_topology(w, std::vector<SceneBody>{a});
  t.bodies[0].tets[3][2] = a.num_particles;
  test::expect_words(test::error_of([&] { check_frame_topology(t, a.num_particles, "f.vtu"); }),
                     {"f.vtu", "body tets_0", "tet 3", "particle index 12", "[0, 12)"});
  t.bodies[0].tets[3][2] = 0;
  t.bodies[0].tet_rest.pop_back();
  test::expect_words(test::error_of([&] { check_frame_topology(t, a.num_particles, "f.vtu"); }),
                     {"f.vtu", "12 tets", "11 tet_rest"});
}

TEST(TetFrames, VtuHasTetraCellsWithTheVolumeRatioAndStrainOfAnAffineStretch) {
  World<double> w;
  const SceneBody body = add_box(w, "neo_hookean", "tets_0");
  const TetMesh mesh = tet_box_mesh({2, 1, 1}, {0.2, 0.1, 0.1});
  stretch_x(w, 1.1);
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
  const std::string vtu = vtu_frame(w, t, vtu_cell_constraints(w, t), "f.vtu");
  const std::size_t triangles = body.triangles.size(), tets = mesh.tets.size();
  EXPECT_NE(vtu.find("<Piece NumberOfPoints=\"12\" NumberOfCells=\"" + std::to_string(triangles + tets) + "\">"),
            std::string::npos);
  // The triangles first, then one VTK_TETRA per tet with the tet's corners.
  const auto types = data_array<std::uint8_t>(vtu, "types", 0);
  ASSERT_EQ(types.size(), triangles + tets);
  EXPECT_EQ(std::vector<std::uint8_t>(types.begin(), types.begin() + triangles), std::vector<std::uint8_t>(triangles, 5));
  EXPECT_EQ(std::vector<std::uint8_t>(types.begin() + triangles, types.end()), std::vector<std::uint8_t>(tets, 10));
  const auto cells = cells_of(vtu);
  for (std::size_t k = 0; k < tets; ++k)
    EXPECT_EQ(cells[triangles + k], std::vector<std::int64_t>(mesh.tets[k].begin(), mesh.tets[k].end())) << k;
  // F = diag(1.1, 1, 1) in every tet: V/V0 = 1.1 and |½(FᵀF − I)| = ½(1.1² − 1) = 0.105.
  const auto ratio = data_array<double>(vtu, "volume_ratio", 0);
  const auto strain = data_array<double>(vtu, "strain", 0);
  ASSERT_EQ(ratio.size(), triangles + tets);
  ASSERT_EQ(strain.size(), triangles + tets);
  const auto nh = w.constraints<NeoHookeanConstraint<double>>();
  const PositionsView<double> x(w.positions());
  for (std::size_t k = 0; k < triangles + tets; ++k) {  // a triangle shows the values of the tet it bounds
    EXPECT_NEAR(ratio[k], 1.1, 1e-12) << "cell " << k;
    EXPECT_NEAR(strain[k], 0.105, 1e-12) << "cell " << k;
  }
  for (std::size_t k = 0; k < tets; ++k) EXPECT_EQ(strain[triangles + k], violation(nh[k], x)) << "tet " << k;
  for (const char* name : {"stretch", "area"})
    EXPECT_EQ(count_of(vtu, std::string("Name=\"") + name + "\""), 0u) << name << ": no such constraints";
}

TEST(TetFrames, TetsWithOnlyVolumeConstraintsHaveAVolumeRatioAndNoStrainArray) {
  World<double> w;
  const SceneBody body = add_box(w, "volume", "tets_0");
  stretch_x(w, 1.1);
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
  const std::string vtu = vtu_frame(w, t, vtu_cell_constraints(w, t), "f.vtu");
  const auto types = data_array<std::uint8_t>(vtu, "types", 0);
  EXPECT_EQ(std::count(types.begin(), types.end(), 10), 12);
  const auto ratio = data_array<double>(vtu, "volume_ratio", 0);
  ASSERT_EQ(ratio.size(), types.size());
  for (std::size_t k = 0; k < types.size(); ++k) EXPECT_NEAR(ratio[k], 1.1, 1e-12) << "cell " << k;
  EXPECT_EQ(count_of(vtu, "Name=\"strain\""), 0u) << "no Neo-Hookean constraint: no rest shape to strain from";
}

TEST(TetFrames, AnInvertedTetHasANegativeVolumeRatio) {
  World<double> w;
  const SceneBody body = add_box(w, "neo_hookean", "tets_0");
  stretch_x(w, -1.0);  // a mirror: every tet turned inside out, its shape kept
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
  const std::string vtu = vtu_frame(w, t, vtu_cell_constraints(w, t), "f.vtu");
  const auto types = data_array<std::uint8_t>(vtu, "types", 0);
  const auto ratio = data_array<double>(vtu, "volume_ratio", 0);
  const auto strain = data_array<double>(vtu, "strain", 0);
  for (std::size_t k = 0; k < types.size(); ++k)
    if (types[k] == 10) {
      EXPECT_NEAR(ratio[k], -1.0, 1e-12) << "cell " << k;
      EXPECT_NEAR(strain[k], 0.0, 1e-12) << "cell " << k << ": FᵀF = I, a mirror strains nothing";
    }
}

TEST(TetFrames, AFrameWithTetsHasTheTetArraysNaNOffTheTetsAndAFrameWithoutHasNone) {
  World<double> w;
  ClothOptions cloth;
  cloth.resolution = 3;
  const Body c = add_cloth(w, cloth, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  const SceneBody cloth_body{"cloth_0", c.first_particle, c.num_particles, c.triangles};
  const FrameTopology without = frame_topology(w, std::vector<SceneBody>{cloth_body});
  const std::string plain = vtu_frame(w, without, vtu_cell_constraints(w, without), "f.vtu");
  EXPECT_EQ(count_of(plain, "volume_ratio"), 0u);
  EXPECT_EQ(count_of(plain, "strain"), 0u);
  const SceneBody box = add_box(w, "both", "tets_1", {1, 0, 0});
  const FrameTopology with = frame_topology(w, std::vector<SceneBody>{cloth_body, box});
  const std::string vtu = vtu_frame(w, with, vtu_cell_constraints(w, with), "f.vtu");
  EXPECT_EQ(count_of(vtu, "Name=\"volume_ratio\""), 1u);
  EXPECT_EQ(count_of(vtu, "Name=\"strain\""), 1u);
  const auto body = data_array<std::int32_t>(vtu, "body", 1);
  for (const char* name : {"volume_ratio", "strain"}) {
    const auto on_cloth = of_body(data_array<double>(vtu, name, 0), body, 0);
    EXPECT_EQ(on_cloth.size(), 8u) << name;
    for (double v : on_cloth) EXPECT_TRUE(std::isnan(v)) << name << " on the cloth";
    const auto on_box = of_body(data_array<double>(vtu, name, 0), body, 1);
    EXPECT_EQ(on_box.size(), box.triangles.size() + 12) << name;
    for (double v : on_box) EXPECT_NEAR(v, std::string(name) == "volume_ratio" ? 1.0 : 0.0, 1e-12) << name;
  }
  // The box's tets are on its own particles, numbered as in the world: after the cloth's 9.
  const auto cells = cells_of(vtu);
  EXPECT_EQ(cells.back().size(), 4u);
  for (std::int64_t p : cells.back()) {
    EXPECT_GE(p, 9);
    EXPECT_LT(p, 21);
  }
}

// A body with tet fibers: each tet cell carries its tet fiber's total strain and stress (World::material_readings),
// the triangles NaN; a body held by its tet fibers alone is drawn too; a frame without tet fibers has no such array.
TEST(TetFrames, TetCellsCarryTheirTetFibersStrainAndStress) {
  World<double> w;
  const SceneBody plain = add_box(w, "both", "tets_0");
  const std::string before = [&] {
    const FrameTopology t = frame_topology(w, std::vector<SceneBody>{plain});
    return vtu_frame(w, t, vtu_cell_constraints(w, t), "f.vtu");
  }();
  EXPECT_EQ(count_of(before, "tet_fiber"), 0u);
  Material m;
  m.stiffness = 1e5;
  TetConstraintSets sets;
  sets.fibers = w.add_constraint_set(Stiffness::fiber(m));
  TetBodyOptions options;
  options.origin = {1, 0, 0};
  const Body fibers_only = add_tet_body(w, tet_box_mesh({2, 1, 1}, {0.2, 0.1, 0.1}), options, sets);
  const SceneBody body{"tets_1", fibers_only.first_particle, fibers_only.num_particles, fibers_only.triangles};
  auto x = w.positions();
  for (Index i = body.first_particle; i < w.num_particles(); ++i) x(0, i) = 1.0 + 1.1 * (x(0, i) - 1.0);  // F·a0: 1.1
  StepParams<double> p;
  p.gravity.setZero();
  w.set_params(p);
  w.step();  // a λ to read
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{plain, body});
  ASSERT_EQ(t.bodies[1].tets.size(), 12u);
  const std::string vtu = vtu_frame(w, t, vtu_cell_constraints(w, t), "f.vtu");
  EXPECT_EQ(count_of(vtu, "Name=\"tet_fiber_strain\""), 1u);
  EXPECT_EQ(count_of(vtu, "Name=\"tet_fiber_stress\""), 1u);
  const auto cell_body = data_array<std::int32_t>(vtu, "body", 1);
  for (double v : of_body(data_array<double>(vtu, "tet_fiber_stress", 0), cell_body, 0))
    EXPECT_TRUE(std::isnan(v)) << "no tet fiber there";
  const auto readings = w.material_readings<TetFiberConstraint<double>>();
  const auto strain = of_body(data_array<double>(vtu, "tet_fiber_strain", 0), cell_body, 1);
  const auto stress = of_body(data_array<double>(vtu, "tet_fiber_stress", 0), cell_body, 1);
  const std::size_t triangles = t.bodies[1].triangles.size();
  ASSERT_EQ(stress.size(), triangles + 12);
  for (std::size_t k = 0; k < triangles; ++k) EXPECT_TRUE(std::isnan(stress[k])) << "triangle " << k;
  for (std::size_t k = 0; k < 12; ++k) {  // the tets in the fibers' order
    EXPECT_EQ(strain[triangles + k], readings[k].strain) << "tet " << k;
    EXPECT_EQ(stress[triangles + k], readings[k].force) << "tet " << k;
    EXPECT_GT(stress[triangles + k], 0.0) << "tet " << k;
  }
}

TEST(TetFrames, CellConstraintsOfAnotherTopologyAreRefused) {
  World<double> w;
  const SceneBody body = add_box(w, "neo_hookean", "tets_0");
  FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
  const VtuCellConstraints cells = vtu_cell_constraints(w, t);
  t.bodies[0].tets.resize(2);  // fewer tets than the triangles were found on
  t.bodies[0].tet_rest.resize(2);
  test::expect_words(test::error_of([&] { vtu_frame(w, t, cells, "f.vtu"); }),
                     {"f.vtu", "another topology", "body tets_0", "of 2"});
}

TEST(TetFrames, ObjFrameOfATetBodyHasEveryParticleAndTheSurfaceTriangles) {
  World<double> w;
  const SceneBody body = add_box(w, "neo_hookean", "tets_0");
  const FrameTopology t = frame_topology(w, std::vector<SceneBody>{body});
  std::istringstream in(obj_frame(w, t, "f.obj"));
  std::size_t v = 0, f = 0, other = 0;  // besides the header ("#") and the object line ("o")
  for (std::string line; std::getline(in, line);) {
    const std::string tag = line.substr(0, line.find(' '));
    if (tag == "v") ++v;
    else if (tag == "f") ++f;
    else if (tag != "#" && tag != "o") ++other;
  }
  EXPECT_EQ(v, 12u);
  EXPECT_EQ(f, body.triangles.size()) << "the boundary surface: OBJ has no volume cells";
  EXPECT_EQ(other, 0u);
}

// A tet body draws the boundary of the tets it has now: its own boundary, in its order, while every tet is there;
// once the tets on an edge are gone (as a fiber that breaks takes them, engine/src/tear_cells.hpp), the boundary of
// those left, the crack's faces with it. Its fibers along the tets' edges are drawn as the tets; a fiber left with
// an end on no tet is a line.
TEST(TetFrames, ATetBodyDrawsTheBoundaryOfTheTetsItHasNow) {
  World<double> w;
  TetConstraintSets sets;
  sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
  sets.ratio = 0.5;
  Material m;
  m.stiffness = 5.0;
  sets.stretch = w.add_constraint_set(Stiffness::fiber(m));
  const TetMesh mesh = tet_box_mesh({2, 1, 1}, {0.2, 0.1, 0.1});
  const Body b = add_tet_body(w, mesh, TetBodyOptions{}, sets);
  const std::vector<SceneBody> bodies{{"tets_0", b.first_particle, b.num_particles, b.triangles}};
  const FrameTopology whole = frame_topology(w, bodies);
  EXPECT_EQ(whole.bodies[0].triangles, b.triangles);
  EXPECT_TRUE(whole.bodies[0].fiber_lines.empty());
  // The tets holding particles 0 and 1 (an edge of the first cube) leave, as a break of the fiber there would take them.
  std::vector<Index> gone;
  std::vector<std::array<Index, 4>> left;
  const auto tets = w.constraints<NeoHookeanConstraint<double>>();
  for (Index k = 0; k < Index(tets.size()); ++k) {
    const auto& q = tets[k].particles;
    const bool on = std::count(q.begin(), q.end(), Index(0)) && std::count(q.begin(), q.end(), Index(1));
    if (on) gone.push_back(k);
    else left.push_back(q);
  }
  ASSERT_FALSE(gone.empty());
  w.remove_constraints<NeoHookeanConstraint<double>>(gone);
  const FrameTopology torn = frame_topology(w, bodies);
  EXPECT_EQ(torn.bodies[0].tets, left);
  EXPECT_EQ(torn.bodies[0].triangles, tet_mesh_surface(TetMesh{{}, left}));
  EXPECT_NE(torn.bodies[0].triangles, b.triangles);
  for (const auto& line : torn.bodies[0].fiber_lines) {  // drawn only with an end on no tet left
    bool both = true;
    for (Index p : line)
      both = both && std::any_of(left.begin(), left.end(), [&](const auto& q) {
               return std::count(q.begin(), q.end(), p) > 0;
             });
    EXPECT_FALSE(both) << line[0] << "-" << line[1];
  }
}

}  // namespace
}  // namespace pbd
