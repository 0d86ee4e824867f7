// Bad input to the World API: a pbd::Error naming the offending item, and the world left unchanged.
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace pbd {
namespace {

// A small world with 3 particles, one set and one stretch constraint; compare() checks nothing changed.
struct Fixture {
  World<double> w;
  Fixture() {
    w.add_particle({0, 0, 0}, 1.0);
    w.add_particle({1, 0, 0}, 2.0);
    w.add_particle({0, 1, 0}, World<double>::kPinned);
    w.add_stretch(0, 1, w.add_constraint_set(Stiffness::pbd_k(0.5)));
    w.add_plane({0, 0, 1}, -1);
  }
  void expect_unchanged(const World<double>& before) const {
    EXPECT_EQ(w.num_particles(), before.num_particles());
    EXPECT_EQ(w.positions(), before.positions());
    EXPECT_EQ(w.velocities(), before.velocities());
    EXPECT_EQ(w.inverse_masses(), before.inverse_masses());
    EXPECT_EQ(w.constraints().sets.size(), before.constraints().sets.size());
    EXPECT_EQ(w.constraints().stretch.size(), before.constraints().stretch.size());
    EXPECT_EQ(w.constraints().anchor.size(), before.constraints().anchor.size());
    EXPECT_EQ(w.colliders().planes.size(), before.colliders().planes.size());
    EXPECT_EQ(w.colliders().spheres.size(), before.colliders().spheres.size());
    EXPECT_EQ(w.params().dt, before.params().dt);
  }
};

// Runs `bad` on a fresh fixture, expects pbd::Error whose message contains every one of `words`, and no change.
void expect_rejected(const std::function<void(World<double>&)>& bad, std::initializer_list<const char*> words) {
  Fixture f;
  const World<double> before = f.w;
  try {
    bad(f.w);
    ADD_FAILURE() << "no pbd::Error thrown";
  } catch (const Error& e) {
    for (const char* word : words) EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
  f.expect_unchanged(before);
}

const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();

TEST(WorldErrors, NonFinitePositionOrVelocity) {
  expect_rejected([](auto& w) { w.add_particle({0, nan, 0}, 1.0); }, {"particle 3", "position"});
  expect_rejected([](auto& w) { w.add_particle({inf, 0, 0}, 1.0); }, {"particle 3", "position"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, 1.0, {0, 0, nan}); }, {"particle 3", "velocity"});
}

TEST(WorldErrors, NegativeZeroOrNaNMass) {
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, -1.0); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, 0.0); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, nan); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.set_mass(1, nan); }, {"particle 1", "mass"});
}

TEST(WorldErrors, BatchOfParticlesIsAllOrNothing) {
  Matrix3X<double> x = Matrix3X<double>::Zero(3, 4);
  Eigen::VectorXd m = Eigen::VectorXd::Ones(4);
  m[2] = -5;
  expect_rejected([&](auto& w) { w.add_particles(x, m); }, {"particle 5", "mass"});  // 3 existing + index 2
  m[2] = 1;
  x(1, 3) = nan;
  expect_rejected([&](auto& w) { w.add_particles(x, m); }, {"particle 6", "position"});
  expect_rejected([&](auto& w) { w.add_particles(x, Eigen::VectorXd::Ones(3)); }, {"4 positions", "3 masses"});
}

TEST(WorldErrors, ConstraintIndexOutOfRange) {
  expect_rejected([](auto& w) { w.add_stretch(0, 7, 0); }, {"stretch constraint 1", "particle index 7", "3 particles"});
  expect_rejected([](auto& w) { w.add_anchor(3, 0); }, {"anchor 0", "particle index 3"});
  expect_rejected([](auto& w) { w.set_mass(9, 1.0); }, {"particle index 9"});
  expect_rejected([](auto& w) { w.add_stretch(0, 1, 4); }, {"stretch constraint 1", "constraint set 4"});
}

TEST(WorldErrors, ConstraintNamingTheSameParticleTwice) {
  expect_rejected([](auto& w) { w.add_stretch(1, 1, 0); }, {"stretch constraint 1", "particle 1 twice"});
}

TEST(WorldErrors, StiffnessOutsideUnitIntervalAndNegativeCompliance) {
  expect_rejected([](auto& w) { w.add_constraint_set(Stiffness::pbd_k(1.5)); }, {"set 1", "stiffness"});
  expect_rejected([](auto& w) { w.add_constraint_set(Stiffness::pbd_k(-0.1)); }, {"set 1", "stiffness"});
  expect_rejected([](auto& w) { w.add_constraint_set(Stiffness::iteration_independent(nan)); }, {"set 1", "stiffness"});
  expect_rejected([](auto& w) { w.add_constraint_set(Stiffness::xpbd_compliance(-1e-9)); }, {"set 1", "compliance"});
  expect_rejected([](auto& w) { w.add_constraint_set(Stiffness::xpbd_compliance(inf)); }, {"set 1", "compliance"});
}

TEST(WorldErrors, BadRestLengthAnchorTargetAndColliders) {
  expect_rejected([](auto& w) { w.add_stretch(0, 1, 0, -1.0); }, {"stretch constraint 1", "rest"});
  expect_rejected([](auto& w) { w.add_anchor(0, 0, Vec3<double>(nan, 0, 0)); }, {"anchor 0", "target"});
  expect_rejected([](auto& w) { w.add_plane({0, 0, 0}, 1); }, {"plane 1", "normal"});
  expect_rejected([](auto& w) { w.add_sphere({0, 0, 0}, 0); }, {"sphere 0", "radius"});
  expect_rejected([](auto& w) { w.add_sphere({0, 0, nan}, 1); }, {"sphere 0", "center"});
}

TEST(WorldErrors, BadStepParameters) {
  auto with = [](auto change) {
    return [change](World<double>& w) {
      StepParams<double> p = w.params();
      change(p);
      w.set_params(p);
    };
  };
  expect_rejected(with([](auto& p) { p.dt = 0; }), {"dt"});
  expect_rejected(with([](auto& p) { p.dt = -0.01; }), {"dt"});
  expect_rejected(with([](auto& p) { p.dt = nan; }), {"dt"});
  expect_rejected(with([](auto& p) { p.substeps = 0; }), {"substeps"});
  expect_rejected(with([](auto& p) { p.iterations = -1; }), {"iterations"});
  expect_rejected(with([](auto& p) { p.gravity.x() = inf; }), {"gravity"});
  expect_rejected(with([](auto& p) { p.damping = -1; }), {"damping"});
}

TEST(WorldErrors, ValidCallsStillWorkAfterARejectedOne) {
  Fixture f;
  EXPECT_THROW(f.w.add_stretch(0, 0, 0), Error);
  EXPECT_EQ(f.w.add_stretch(0, 2, 0), 1u);
  EXPECT_EQ(f.w.add_particle({1, 1, 1}, 1.0), 3u);
}

TEST(World, ConvertsBetweenPrecisions) {
  Fixture f;
  const World<float> w(f.w);
  EXPECT_EQ(w.num_particles(), 3u);
  EXPECT_EQ(w.constraints().stretch.size(), 1u);
  EXPECT_FLOAT_EQ(w.constraints().stretch[0].rest, 1.0f);
  EXPECT_EQ(w.inverse_masses()[2], 0.0f);
  EXPECT_FLOAT_EQ(w.inverse_masses()[1], 0.5f);
  EXPECT_EQ(w.colliders().planes.size(), 1u);
}

}  // namespace
}  // namespace pbd
