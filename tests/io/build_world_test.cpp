// Worlds built from a precision-free description: exactly Real(value) for every value (as a World<double> cast to
// Real gave), values beyond Real's range refused naming them, and describe_world giving the description back.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace pbd {
namespace {

// Expects the material `m` to be the cast of `d`, coefficient by coefficient.
template <class Real>
void expect_material_cast(const ContactMaterial<double>& d, const ContactMaterial<Real>& m, const std::string& what) {
  EXPECT_EQ(m.static_friction, Real(d.static_friction)) << what;
  EXPECT_EQ(m.kinetic_friction, Real(d.kinetic_friction)) << what;
  EXPECT_EQ(m.restitution, Real(d.restitution)) << what;
}

// Expects every value of `w` to be Real(value of d), bit for bit, and the constraints in the description's order.
template <class Real> void expect_cast_of(const WorldDescription& d, const World<Real>& w, const std::string& what) {
  ASSERT_EQ(w.num_particles(), d.num_particles()) << what;
  EXPECT_EQ(Matrix3X<Real>(w.positions()), d.positions.cast<Real>()) << what;
  EXPECT_EQ(Matrix3X<Real>(w.velocities()), d.velocities.cast<Real>()) << what;
  for (Index i = 0; i < d.num_particles(); ++i)  // Real(1/m) computed in double, not 1/Real(m)
    ASSERT_EQ(w.inverse_masses()[i], Real(d.inverse_masses[i])) << what << " particle " << i;
  ASSERT_EQ(w.constraint_sets().size(), d.sets.size()) << what;
  const auto& stretch = w.template constraints<StretchConstraint<Real>>();
  ASSERT_EQ(stretch.size(), d.constraints<StretchConstraint<double>>().size()) << what;
  for (std::size_t i = 0; i < stretch.size(); ++i) {
    ASSERT_EQ(stretch[i].particles, d.constraints<StretchConstraint<double>>()[i].particles)
        << what << " stretch " << i;
    ASSERT_EQ(stretch[i].set, d.constraints<StretchConstraint<double>>()[i].set) << what << " stretch " << i;
    ASSERT_EQ(stretch[i].rest, Real(d.constraints<StretchConstraint<double>>()[i].rest)) << what << " stretch " << i;
  }
  const auto& bending = w.template constraints<BendingConstraint<Real>>();
  ASSERT_EQ(bending.size(), d.constraints<BendingConstraint<double>>().size()) << what;
  for (std::size_t i = 0; i < bending.size(); ++i) {
    ASSERT_EQ(bending[i].particles, d.constraints<BendingConstraint<double>>()[i].particles)
        << what << " bending " << i;
    ASSERT_EQ(bending[i].rest, Real(d.constraints<BendingConstraint<double>>()[i].rest)) << what << " bending " << i;
  }
  const auto& area = w.template constraints<AreaConstraint<Real>>();
  ASSERT_EQ(area.size(), d.constraints<AreaConstraint<double>>().size()) << what;
  for (std::size_t i = 0; i < area.size(); ++i)
    ASSERT_EQ(area[i].rest, Real(d.constraints<AreaConstraint<double>>()[i].rest)) << what << " area " << i;
  const auto& anchors = w.template constraints<AnchorConstraint<Real>>();
  ASSERT_EQ(anchors.size(), d.constraints<AnchorConstraint<double>>().size()) << what;
  for (std::size_t i = 0; i < anchors.size(); ++i)
    ASSERT_EQ(anchors[i].target, d.constraints<AnchorConstraint<double>>()[i].target.cast<Real>())
        << what << " anchor " << i;
  ASSERT_EQ(w.volumes().size(), d.volumes.size()) << what;
  for (std::size_t i = 0; i < d.volumes.size(); ++i) {
    EXPECT_EQ(w.volumes().items[i].rest, Real(d.volumes[i].rest)) << what << " volume " << i;
    EXPECT_EQ(w.volumes().items[i].pressure.to, d.volumes[i].pressure.to) << what << " volume " << i;
  }
  ASSERT_EQ(w.colliders().planes.size(), d.planes.size()) << what;
  for (std::size_t i = 0; i < d.planes.size(); ++i) {
    EXPECT_EQ(w.colliders().planes[i].normal, d.planes[i].normal.cast<Real>()) << what << " plane " << i;
    EXPECT_EQ(w.colliders().planes[i].offset, Real(d.planes[i].offset)) << what << " plane " << i;
    expect_material_cast(d.planes[i].material, w.colliders().planes[i].material, what + " plane " + std::to_string(i));
  }
  ASSERT_EQ(w.colliders().spheres.size(), d.spheres.size()) << what;
  for (std::size_t i = 0; i < d.spheres.size(); ++i) {
    EXPECT_EQ(w.colliders().spheres[i].center, d.spheres[i].center.cast<Real>()) << what << " sphere " << i;
    EXPECT_EQ(w.colliders().spheres[i].radius, Real(d.spheres[i].radius)) << what << " sphere " << i;
    expect_material_cast(d.spheres[i].material, w.colliders().spheres[i].material,
                         what + " sphere " + std::to_string(i));
  }
  ASSERT_EQ(w.contact_bodies().size(), d.contact_bodies.size()) << what;
  for (std::size_t i = 0; i < d.contact_bodies.size(); ++i) {
    const ContactBody<Real>& b = w.contact_bodies()[i];
    const std::string body = what + " contact body " + std::to_string(i);
    EXPECT_EQ(b.first, d.contact_bodies[i].first) << body;
    EXPECT_EQ(b.count, d.contact_bodies[i].count) << body;
    EXPECT_EQ(b.radius, Real(d.contact_bodies[i].radius)) << body;
    EXPECT_EQ(b.self_collision, d.contact_bodies[i].self_collision) << body;
    expect_material_cast(d.contact_bodies[i].material, b.material, body);
  }
  EXPECT_EQ(w.params().dt, Real(d.params.dt)) << what;
  EXPECT_EQ(w.params().gravity, d.params.gravity.cast<Real>()) << what;
  EXPECT_EQ(w.params().damping, Real(d.params.damping)) << what;
  EXPECT_EQ(w.params().collision_margin, Real(d.params.collision_margin)) << what;
  EXPECT_EQ(w.params().substeps, d.params.substeps) << what;
  EXPECT_EQ(w.params().iterations, d.params.iterations) << what;
  EXPECT_EQ(w.params().sweep_order, d.params.sweep_order) << what;
  EXPECT_EQ(w.time(), 0.0) << what;
}

TEST(BuildWorld, EveryBuiltInSceneInEitherPrecisionHoldsTheCastOfEachValue) {
  for (const std::string& name : scene_names(PBD_TEST_SCENE_DIR)) {
    const WorldDescription d = load_scene_by_name(name, PBD_TEST_SCENE_DIR).world;
    expect_cast_of(d, build_world<float>(d), name + " (float)");
    expect_cast_of(d, build_world<double>(d), name + " (double)");
  }
}

TEST(BuildWorld, TheRopesInverseMassesAreRoundedFromDouble) {
  // The rope's end is 1000× heavier: float(1/m) and 1/float(m) differ for such masses; the world must hold the first.
  const WorldDescription d = load_scene_by_name("rope", PBD_TEST_SCENE_DIR).world;
  const World<float> w = build_world<float>(d);
  for (Index i = 0; i < d.num_particles(); ++i) EXPECT_EQ(w.inverse_masses()[i], float(d.inverse_masses[i])) << i;
}

TEST(BuildWorld, DescribeWorldGivesTheDescriptionBack) {
  for (const std::string& name : scene_names(PBD_TEST_SCENE_DIR)) {
    const WorldDescription d = load_scene_by_name(name, PBD_TEST_SCENE_DIR).world;
    const WorldDescription again = describe_world(build_world<double>(d));
    expect_cast_of(again, build_world<double>(d), name);
    ASSERT_EQ(again.volumes.size(), d.volumes.size());
    for (std::size_t i = 0; i < d.volumes.size(); ++i) EXPECT_EQ(again.volumes[i].triangles, d.volumes[i].triangles);
  }
}

TEST(BuildWorld, AFloatWorldRebuiltInDoubleKeepsItsValues) {
  // A flat cloth's bending rest angle is π; in float that is just above double's π, which World<double> accepts
  // (its bound is π rounded to float): every value is the float value exactly.
  const WorldDescription d = load_scene_by_name("cloth", PBD_TEST_SCENE_DIR).world;
  const World<float> f = build_world<float>(d);
  const World<double> w = build_world<double>(describe_world(f));
  const auto& bending = w.constraints<BendingConstraint<double>>();
  ASSERT_FALSE(bending.empty());
  for (std::size_t i = 0; i < bending.size(); ++i) {
    const double from_float = double(f.constraints<BendingConstraint<float>>()[i].rest);
    EXPECT_EQ(bending[i].rest, from_float) << i;
  }
  for (Index i = 0; i < w.num_particles(); ++i) EXPECT_EQ(w.inverse_masses()[i], double(f.inverse_masses()[i])) << i;
  EXPECT_EQ(w.params().dt, double(f.params().dt));
}

// A world rebuilt from its description mid-run (with its time set, as the study's reference does) steps on exactly
// as the original: the symmetric sweep order numbers sub-steps from the world's time, not from a counter the
// description would lose.
TEST(BuildWorld, ARebuiltWorldStepsOnAsTheOriginalUnderSymmetricSweeps) {
  for (const char* scene : {"inflate", "inflate-mesh"}) {
    World<double> a = build_world<double>(load_scene_by_name(scene, PBD_TEST_SCENE_DIR).world);
    ASSERT_EQ(a.params().sweep_order, SweepOrder::symmetric) << scene;
    StepParams<double> p = a.params();
    p.solver = Solver::serial;
    p.substeps = 1;  // one sub-step a step, as the study runs it: after 7 steps the next sub-step is odd
    a.set_params(p);
    for (int s = 0; s < 7; ++s) a.step();
    World<double> b = build_world<double>(describe_world(a));
    b.set_time(a.time());
    for (int s = 0; s < 3; ++s) {
      a.step();
      b.step();
    }
    EXPECT_TRUE(a.positions() == b.positions()) << scene;
    EXPECT_TRUE(a.velocities() == b.velocities()) << scene;
  }
}

// The world of the engine tests' fixture: 3 particles (one pinned), one stretch constraint, one plane.
World<double> small_world() {
  World<double> w;
  w.add_particle({0, 0, 0}, 1.0);
  w.add_particle({1, 0, 0}, 2.0);
  w.add_particle({0, 1, 0}, World<double>::kPinned);
  w.add_stretch(0, 1, w.add_constraint_set(Stiffness::pbd_k(0.5)));
  w.add_plane({0, 0, 1}, -1);
  return w;
}

TEST(BuildWorld, ConvertsASmallWorldToFloat) {
  const World<float> w = build_world<float>(describe_world(small_world()));
  EXPECT_EQ(w.num_particles(), 3u);
  ASSERT_EQ(w.constraints<StretchConstraint<float>>().size(), 1u);
  EXPECT_FLOAT_EQ(w.constraints<StretchConstraint<float>>()[0].rest, 1.0f);
  EXPECT_EQ(w.inverse_masses()[2], 0.0f);
  EXPECT_FLOAT_EQ(w.inverse_masses()[1], 0.5f);
  EXPECT_EQ(w.colliders().planes.size(), 1u);
}

TEST(BuildWorld, RefusesValuesOutOfFloatRangeNamingThem) {
  auto expect_throws = [](const World<double>& w, std::initializer_list<std::string> words) {
    const WorldDescription d = describe_world(w);
    test::expect_words(test::error_of([&] { build_world<float>(d); }), words);
    EXPECT_NO_THROW(build_world<double>(d));
  };
  {
    World<double> w = small_world();
    w.add_particle({1e300, 0, 0}, 1.0);
    expect_throws(w, {"build_world<float>", "position of particle 3", "1e+300", "out of range"});
  }
  {
    World<double> w = small_world();
    w.add_particle({0, 0, 0}, 1e-300);  // inverse mass 1e300
    expect_throws(w, {"inverse mass of particle 3", "1e+300"});
  }
  for (const double heavy : {1e50, 1e40}) {  // inverse masses that round to 0 (pinned) or are subnormal in float
    World<double> w = small_world();
    w.add_particle({0, 0, 0}, heavy);
    expect_throws(w, {"inverse mass of particle 3", heavy == 1e50 ? "1e-50" : "1e-40"});
  }
  {
    World<double> w = small_world();
    w.add_stretch(0, 2, 0, 1e200);
    expect_throws(w, {"rest length of stretch constraint 1", "1e+200"});
  }
  {
    World<double> w = small_world();
    w.add_sphere({0, 0, 0}, 1e100);
    expect_throws(w, {"sphere 0", "1e+100"});
  }
  {
    World<double> w = small_world();
    w.add_plane({0, 0, 1}, 0, {0.5, 1e200, 0});
    expect_throws(w, {"the friction of plane 1", "kinetic 1e+200"});
  }
  {
    World<double> w = small_world();
    w.add_sphere({0, 0, 0}, 1, {1e200, 0, 0});
    expect_throws(w, {"the friction of sphere 0", "static 1e+200"});
  }
  {
    World<double> w = small_world();  // refused by World<double> itself now: at most 1e6 m (issue 48)
    test::expect_words(test::error_of([&] { w.add_contact_body({0, 2, 1e100, {}, false}); }),
                       {"add_contact_body: body 0: radius", "1e+100"});
  }
  {
    World<double> w = small_world();
    w.add_contact_body({0, 3, 0.1, {1e300, 1e300, 0.5}, true});
    expect_throws(w, {"the friction of contact body 0", "1e+300"});
  }
}

TEST(BuildWorld, RefusesADescriptionWhoseParticleArraysDisagree) {
  WorldDescription d = describe_world(small_world());
  d.velocities.resize(3, 2);
  test::expect_words(test::error_of([&] { build_world<double>(d); }), {"3 positions", "2 velocities"});
}

}  // namespace
}  // namespace pbd
