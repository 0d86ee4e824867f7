// A body that starts a step inside a collider (placed there through the API, or a collider added into it) leaves it
// with no gain in speed (contact/prestabilize.hpp): at rest it stays at rest on the surface, under every solver, in
// both precisions. Before pre-stabilization the first sub-step's push out, 0.1 m, stayed as a velocity of 0.1 m / h
// (24 m/s at 4 sub-steps of a 1/60 s step), and the grid's energy went from 4.9 J to hundreds.
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <string>

namespace pbd {
namespace {

template <class Real> class Prestabilize : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Prestabilize, Precisions);

constexpr int kSide = 5;          // a kSide × kSide grid of particles, 0.1 m apart, joined by stretch constraints
constexpr double kDepth = 0.1;    // how deep the grid starts inside the collider, m

// The grid at rest at height z, its neighbours joined by stretch constraints when `joined`.
template <class Real> World<Real> grid_world(Solver solver, double z, bool joined = true) {
  World<Real> w;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) w.add_particle(Vec3<Real>(Real(0.1 * i), Real(0.1 * j), Real(z)), Real(1));
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  for (int i = 0; i < kSide && joined; ++i)
    for (int j = 0; j < kSide; ++j) {
      if (i + 1 < kSide) w.add_stretch(i * kSide + j, (i + 1) * kSide + j, set);
      if (j + 1 < kSide) w.add_stretch(i * kSide + j, i * kSide + j + 1, set);
    }
  StepParams<Real> p = w.params();
  p.solver = solver;
  p.substeps = 4;
  p.iterations = 4;
  w.set_params(p);
  return w;
}

TYPED_TEST(Prestabilize, AGridStartingInsideTheGroundRisesOntoItWithoutSpeed) {
  using Real = TypeParam;
  const double g = 9.81, n = kSide * kSide;
  for (const Solver solver : kSolvers) {
    SCOPED_TRACE(std::string(name(solver)));
    World<Real> w = grid_world<Real>(solver, -kDepth);
    w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
    const Energy start = energy(w);
    double max_kinetic = 0;
    for (int step = 0; step < 60; ++step) {
      w.step();
      max_kinetic = std::max(max_kinetic, energy(w).kinetic);
      for (Index i = 0; i < w.num_particles(); ++i) ASSERT_GE(double(w.positions()(2, i)), -1e-5) << "particle " << i;
    }
    // At rest on the ground: no speed at all (the old push gave each particle ½ (0.1 m × 240/s)² = 288 J/kg), and
    // the energy is the start's plus the lift m g d, no more.
    EXPECT_LT(max_kinetic, 1e-6 * n * g * kDepth);
    EXPECT_NEAR(energy(w).total(), start.total() + n * g * kDepth, 1e-4 * n * g * kDepth);
  }
}

TYPED_TEST(Prestabilize, AGridInsideASphereColliderIsMovedToItsSurfaceWithoutSpeed) {
  using Real = TypeParam;
  const double radius = 1.0;
  for (const Solver solver : kSolvers) {
    SCOPED_TRACE(std::string(name(solver)));
    // The grid's particles 0.5-0.75 m from the centre, deep inside; not joined, so that moving each out along its
    // own normal stretches nothing (a joined grid would spring back from the sphere: its elastic energy, rightly).
    World<Real> w = grid_world<Real>(solver, 0.5, false);
    StepParams<Real> p = w.params();
    p.gravity.setZero();  // no force: a body at rest moved out of the sphere must stay at rest
    w.set_params(p);
    w.add_sphere(Vec3<Real>::Zero(), Real(radius));
    for (int step = 0; step < 30; ++step) {
      w.step();
      EXPECT_LT(energy(w).kinetic, 1e-9) << "step " << step;
    }
    for (Index i = 0; i < w.num_particles(); ++i)
      EXPECT_GE(double(w.positions().col(i).norm()), radius - 1e-5) << "particle " << i;
  }
}

// A grid resting on the ground, pressed by its own weight, is the case pre-stabilization most often meets (a last
// sub-step's remainder within rounding): it stays at rest with its energy unchanged.
TYPED_TEST(Prestabilize, AGridRestingOnTheGroundStaysAtRest) {
  using Real = TypeParam;
  for (const Solver solver : kSolvers) {
    SCOPED_TRACE(std::string(name(solver)));
    World<Real> w = grid_world<Real>(solver, 0.0);
    w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
    const Energy start = energy(w);
    for (int step = 0; step < 120; ++step) w.step();
    EXPECT_LT(energy(w).kinetic, 1e-9);
    EXPECT_NEAR(energy(w).total(), start.total(), 1e-6);
  }
}

}  // namespace
}  // namespace pbd
