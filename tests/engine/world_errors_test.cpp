// Bad input to the World API: a pbd::Error naming the offending item, and the world left unchanged.
#include "pbd/io/mesh_generators.hpp"
#include "world_access.hpp"
#include "pbd/step_limits.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

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
    EXPECT_EQ(w.constraint_sets().size(), before.constraint_sets().size());
    EXPECT_EQ(test::stretch_of(w).size(), test::stretch_of(before).size());
    EXPECT_EQ(test::anchor_of(w).size(), test::anchor_of(before).size());
    EXPECT_EQ(test::bending_of(w).size(), test::bending_of(before).size());
    EXPECT_EQ(test::area_of(w).size(), test::area_of(before).size());
    EXPECT_EQ(w.volumes().size(), before.volumes().size());
    EXPECT_EQ(w.colliders().planes.size(), before.colliders().planes.size());
    EXPECT_EQ(w.colliders().spheres.size(), before.colliders().spheres.size());
    EXPECT_EQ(w.params().dt, before.params().dt);
  }
};

// Runs `bad` on a fresh fixture F, expects pbd::Error whose message contains every one of `words`, and no change.
template <class F>
void expect_rejected_on(const std::function<void(World<double>&, const F&)>& bad,
                        std::initializer_list<const char*> words) {
  F f;
  const World<double> before = f.w;
  try {
    bad(f.w, f);
    ADD_FAILURE() << "no pbd::Error thrown";
  } catch (const Error& e) {
    for (const char* word : words) EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
  f.expect_unchanged(before);
}

// As expect_rejected_on, on the plain fixture.
void expect_rejected(const std::function<void(World<double>&)>& bad, std::initializer_list<const char*> words) {
  expect_rejected_on<Fixture>([&](World<double>& w, const Fixture&) { bad(w); }, words);
}

const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();

TEST(WorldErrors, NonFinitePositionOrVelocity) {
  expect_rejected([](auto& w) { w.add_particle({0, nan, 0}, 1.0); }, {"particle 3", "position"});
  expect_rejected([](auto& w) { w.add_particle({inf, 0, 0}, 1.0); }, {"particle 3", "position"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, 1.0, {0, 0, nan}); }, {"particle 3", "velocity"});
}

TEST(WorldErrors, NonFiniteValuesWrittenThroughTheMapsStopTheNextStep) {
  for (const bool velocity : {false, true}) {
    Fixture f;
    f.w.step();
    const World<double> before = f.w;
    if (velocity) f.w.velocities()(2, 1) = inf;
    else f.w.positions()(0, 1) = nan;
    const std::string what = velocity ? "velocity" : "position";
    try {
      f.w.step();
      ADD_FAILURE() << "no pbd::Error for a non-finite " << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("step: particle 1 has a non-finite " + what), std::string::npos) << e.what();
    }
    EXPECT_EQ(f.w.time(), before.time());  // nothing stepped
    if (velocity) f.w.velocities()(2, 1) = 0;
    else f.w.positions()(0, 1) = before.positions()(0, 1);
    EXPECT_EQ(f.w.positions(), before.positions());
    f.w.step();  // repaired: steps again
    EXPECT_TRUE(f.w.positions().allFinite());
  }
  // A map handed out and left alone: the check passes and the step is the same as without it.
  Fixture a, b;
  a.w.positions();
  a.w.step();
  b.w.step();
  EXPECT_EQ(a.w.positions(), b.w.positions());
}

TEST(WorldErrors, NegativeZeroOrNaNMass) {
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, -1.0); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, 0.0); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, nan); }, {"particle 3", "mass"});
  expect_rejected([](auto& w) { w.set_mass(1, nan); }, {"particle 1", "mass"});
}

TEST(WorldErrors, MassesWhoseInverseTheRealTypeCannotHoldAreRefusedNotPinned) {
  // In float the inverse of a mass over about 8.5e37 kg is subnormal, and past about 1e45 kg it rounds to 0, the
  // inverse mass of a pinned particle.
  World<float> f;
  f.add_particle({0, 0, 0}, 1.0f);
  auto refused = [](const std::function<void()>& call) {
    try {
      call();
    } catch (const Error& e) {
      return std::string(e.what()).find("out of range for float") != std::string::npos;
    }
    return false;
  };
  for (const float bad : {1e38f, 3e38f, 1e-39f}) {
    EXPECT_TRUE(refused([&] { f.add_particle({0, 0, 0}, bad); })) << bad;
    EXPECT_TRUE(refused([&] { f.set_mass(0, bad); })) << bad;
  }
  ASSERT_EQ(f.inverse_masses().size(), 1);
  EXPECT_EQ(f.inverse_masses()[0], 1.0f);  // the refused set_mass calls changed nothing
  f.add_particle({0, 0, 0}, 1.0f);
  EXPECT_EQ(f.add_particle({0, 0, 0}, 1e37f), 2u);  // its inverse is a normal float: not pinned
  EXPECT_GT(f.inverse_masses()[2], 0.0f);
  f.add_particle({0, 0, 0}, World<float>::kPinned);  // infinity still pins
  EXPECT_EQ(f.inverse_masses()[3], 0.0f);
  expect_rejected([](auto& w) { w.add_particle({0, 0, 0}, 1e-320); }, {"particle 3", "out of range for double"});
  Matrix3X<double> x = Matrix3X<double>::Zero(3, 1);
  expect_rejected([&](auto& w) { w.add_particles_by_inverse_mass(x, Eigen::VectorXd::Constant(1, 1e-320)); },
                  {"particle 3", "inverse mass", "normal"});
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

TEST(WorldErrors, StepParametersAskingForMoreSweepsThanTheLimitAreRefused) {
  auto with = [](int substeps, int iterations) {
    return [=](World<double>& w) {
      StepParams<double> p = w.params();
      p.substeps = substeps;
      p.iterations = iterations;
      w.set_params(p);
    };
  };
  expect_rejected(with(kMaxSubsteps + 1, 1), {"substeps must be in [1, 100000]"});
  expect_rejected(with(1, kMaxIterations + 1), {"iterations must be in [0, 100000]"});
  expect_rejected(with(100'000, 100'000), {"substeps × iterations is 10000000000 sweeps", "limit of 1000000"});
  expect_rejected(with(kMaxSubsteps, 11), {"sweeps a step"});
  World<double> w;
  StepParams<double> p;
  p.substeps = 1000;
  p.iterations = 1000;  // at the limit
  EXPECT_NO_THROW(w.set_params(p));
  p.substeps = kMaxSubsteps;
  p.iterations = 0;  // a sub-step without sweeps counts as one
  EXPECT_NO_THROW(w.set_params(p));
}

TEST(WorldErrors, ValidCallsStillWorkAfterARejectedOne) {
  Fixture f;
  EXPECT_THROW(f.w.add_stretch(0, 0, 0), Error);
  EXPECT_EQ(f.w.add_stretch(0, 2, 0), 1u);
  EXPECT_EQ(f.w.add_particle({1, 1, 1}, 1.0), 3u);
}

// A closed dodecahedron mesh after the 3 fixture particles, with one stretch and one
// volume constraint on it: the world for bending, area, volume and removal errors.
struct MeshFixture : Fixture {
  std::vector<std::array<Index, 3>> tris;
  MeshFixture() {
    const TriangleMesh m = dodecahedron_mesh(1.0);
    w.add_particles(m.positions, Eigen::VectorXd::Ones(m.num_vertices()));
    for (const auto& t : m.triangles) tris.push_back({t[0] + 3, t[1] + 3, t[2] + 3});
    w.add_volume(tris, 0);
  }
};

// As expect_rejected, on the mesh fixture.
void expect_rejected_mesh(const std::function<void(World<double>&, const MeshFixture&)>& bad,
                          std::initializer_list<const char*> words) {
  expect_rejected_on<MeshFixture>(bad, words);
}

TEST(WorldErrors, BadBendingConstraints) {
  using F = const MeshFixture&;
  expect_rejected_mesh([](auto& w, F) { w.add_bending(0, 1, 3, 99, 0); }, {"bending", "99"});
  expect_rejected_mesh([](auto& w, F) { w.add_bending(3, 4, 4, 5, 0); }, {"bending", "twice"});
  expect_rejected_mesh([](auto& w, F) { w.add_bending(3, 4, 5, 6, 0, nan); }, {"bending", "rest"});
  expect_rejected_mesh([](auto& w, F) { w.add_bending(0, 1, 3, 4, 9); }, {"bending", "set 9"});
}

TEST(WorldErrors, BadAreaConstraints) {
  using F = const MeshFixture&;
  expect_rejected_mesh([](auto& w, F) { w.add_area(3, 4, 99, 0); }, {"area", "99"});
  expect_rejected_mesh([](auto& w, F) { w.add_area(3, 3, 4, 0); }, {"area", "twice"});
  expect_rejected_mesh([](auto& w, F) { w.add_area(3, 4, 5, 0, -1.0); }, {"area", "rest"});
  expect_rejected_mesh([](auto& w, F) { w.add_area(3, 4, 5, 0, inf); }, {"area", "rest"});
}

TEST(WorldErrors, BadVolumeConstraints) {
  using F = const MeshFixture&;
  expect_rejected_mesh([](auto& w, F f) {  // one triangle missing: open
    w.add_volume(std::span(f.tris).subspan(1), 0);
  }, {"volume", "edge"});
  expect_rejected_mesh([](auto& w, F f) {  // one triangle flipped: inconsistent orientation
    auto t = f.tris;
    std::swap(t[0][1], t[0][2]);
    w.add_volume(t, 0);
  }, {"volume", "edge"});
  expect_rejected_mesh([](auto& w, F f) {
    auto t = f.tris;
    t[5][0] = 77;
    w.add_volume(t, 0);
  }, {"volume", "77"});
  expect_rejected_mesh([](auto& w, F f) { w.add_volume(f.tris, 0, {}, nan); }, {"volume", "rest"});
  expect_rejected_mesh([](auto& w, F f) { w.add_volume(f.tris, 0, {1.0, 2.0, -1.0}); }, {"volume", "duration"});
  expect_rejected_mesh([](auto& w, F f) { w.add_volume(f.tris, 0, {1.0, nan, 1.0}); }, {"volume", "pressure"});
  expect_rejected_mesh([](auto& w, F f) { w.add_volume(f.tris, 0, {1.0, -2.0, 1.0}); }, {"volume", "pressure"});
  expect_rejected_mesh([](auto& w, F f) {  // inside out: every triangle flipped
    auto t = f.tris;
    for (auto& tri : t) std::swap(tri[1], tri[2]);
    w.add_volume(t, 0);
  }, {"volume"});
}

TEST(WorldErrors, BadRemovalsChangeNothing) {
  using F = const MeshFixture&;
  expect_rejected_mesh([](auto& w, F) { w.remove_stretch(std::vector<Index>{1}); }, {"stretch", "1"});
  expect_rejected_mesh([](auto& w, F) { w.remove_stretch(std::vector<Index>{0, 0}); }, {"stretch", "0", "twice"});
  expect_rejected_mesh([](auto& w, F) { w.remove_anchor(std::vector<Index>{0}); }, {"anchor", "0"});
  expect_rejected_mesh([](auto& w, F) { w.remove_bending(std::vector<Index>{3}); }, {"bending", "3"});
  expect_rejected_mesh([](auto& w, F) { w.remove_area(std::vector<Index>{2}); }, {"area", "2"});
  expect_rejected_mesh([](auto& w, F) { w.remove_particle(99); }, {"particle", "99"});
  expect_rejected_mesh([](auto& w, F) { w.remove_particle(5); }, {"particle 5", "volume"});
}

TEST(WorldErrors, BadExternalForces) {
  expect_rejected([](auto& w) { w.step(Matrix3X<double>::Zero(3, 2)); }, {"forces", "2", "3"});
  expect_rejected([](auto& w) {
    Matrix3X<double> f = Matrix3X<double>::Zero(3, 3);
    f(2, 1) = nan;
    w.step(f);
  }, {"force", "particle 1"});
  expect_rejected([](auto& w) {
    w.set_force_callback([](double, Eigen::Ref<const Matrix3X<double>>, Eigen::Ref<Matrix3X<double>> f) { f(0, 0) = inf; });
    w.step();
  }, {"force", "particle 0"});
}

// The callback fails at the third of four sub-steps (a non-finite force, or an exception of the host's own): the
// sub-steps already taken are undone, so the world is as it was before step().
TEST(WorldErrors, ForceCallbackFailingAtALaterSubStepUndoesTheStep) {
  for (const bool host_exception : {false, true}) {
    Fixture f;
    StepParams<double> p = f.w.params();
    p.substeps = 4;
    f.w.set_params(p);
    f.w.step();  // moving, so an undone sub-step would show
    int calls = 0;
    f.w.set_force_callback([&](double, Eigen::Ref<const Matrix3X<double>>, Eigen::Ref<Matrix3X<double>> force) {
      if (++calls == 3) {
        if (host_exception) throw std::runtime_error("host failure");
        force(1, 1) = nan;
      }
    });
    const World<double> before = f.w;
    const double t = f.w.time();
    if (host_exception) EXPECT_THROW(f.w.step(), std::runtime_error);
    else EXPECT_THROW(f.w.step(), Error);
    EXPECT_EQ(calls, 3);
    f.expect_unchanged(before);
    EXPECT_EQ(f.w.time(), t);
  }
}

TEST(World, AddParticlesByInverseMassValidatesEveryParticleFirst) {
  Fixture f;
  const World<double> before = f.w;
  Matrix3X<double> x(3, 2);
  x << 0, 1, 0, 0, 0, 0;
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    try {
      f.w.add_particles_by_inverse_mass(x, Eigen::Vector2d(0.5, bad));
      ADD_FAILURE() << "accepted inverse mass " << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("particle 4: inverse mass"), std::string::npos) << e.what();
    }
    f.expect_unchanged(before);
  }
  EXPECT_THROW(f.w.add_particles_by_inverse_mass(x, Eigen::VectorXd::Ones(3)), Error);
  f.expect_unchanged(before);
  EXPECT_EQ(f.w.add_particles_by_inverse_mass(x, Eigen::Vector2d(0.0, 0.25)), 3u);
  EXPECT_EQ(f.w.inverse_masses()[3], 0.0);  // pinned
  EXPECT_EQ(f.w.inverse_masses()[4], 0.25);
  EXPECT_TRUE(f.w.velocities().rightCols(2).isZero());
}

TEST(World, SetTimeTakesFiniteTimesOnly) {
  Fixture f;
  f.w.set_time(2.5);
  EXPECT_EQ(f.w.time(), 2.5);
  EXPECT_THROW(f.w.set_time(std::nan("")), Error);
  EXPECT_EQ(f.w.time(), 2.5);
}

}  // namespace
}  // namespace pbd
