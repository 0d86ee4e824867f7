// The PBD step: integration, substeps, pinned particles, damping, continuous collisions.
#include "pbd/io/generators.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <random>

namespace pbd {
namespace {

template <class Real> class StepTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(StepTest, Precisions);

// A map of positions() taken before stepping stays valid: every sub-step swaps the positions with the predicted
// ones, and step() puts an odd count's result back into the same storage (the Python views rely on it).
TYPED_TEST(StepTest, PositionsStayInTheirStorageAcrossSteps) {
  using Real = TypeParam;
  for (Solver solver : {Solver::serial, Solver::colored}) {
    for (int substeps : {1, 2, 3}) {
      World<Real> w;
      const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
      add_cloth(w, ClothOptions{.resolution = 4}, set);
      StepParams<Real> p;
      p.solver = solver;
      p.substeps = substeps;
      w.set_params(p);
      auto x = w.positions();
      const Real* storage = x.data();
      for (int s = 0; s < 3; ++s) {
        w.step();
        EXPECT_EQ(w.positions().data(), storage) << "solver " << name(solver) << ", " << substeps << " substeps";
      }
      x(2, 5) += Real(0.5);  // a write through the old map is what the next step starts from
      const Real z = w.positions()(2, 5);
      EXPECT_EQ(z, x(2, 5));
    }
  }
}

TYPED_TEST(StepTest, FreeParticleFollowsTheSymplecticEulerClosedForm) {
  using Real = TypeParam;
  for (int substeps : {1, 3}) {
    World<Real> w;
    const Vec3<double> x0(0.1, -0.2, 5.0), v0(1.0, 0.5, 2.0), g(0.3, 0.0, -9.81);
    w.add_particle(x0.cast<Real>(), Real(2), v0.cast<Real>());
    StepParams<Real> p;
    p.dt = Real(0.02);
    p.substeps = substeps;
    p.gravity = g.cast<Real>();
    w.set_params(p);
    const int steps = 50;
    for (int s = 0; s < steps; ++s) w.step();
    // v_{k+1} = v_k + h g, x_{k+1} = x_k + h v_{k+1}  =>  x_n = x0 + n h v0 + h² g n(n+1)/2 with h = dt / substeps.
    const double n = double(steps * substeps), h = 0.02 / substeps;
    const Vec3<double> x = x0 + n * h * v0 + h * h * g * n * (n + 1) / 2;
    const Vec3<double> v = v0 + n * h * g;
    // float: v = (p − x)/h loses ~ε|x|/h per substep to cancellation, which accumulates over 150 substeps.
    const double tol = sizeof(Real) == 4 ? 2e-3 : 1e-10;
    EXPECT_LT((w.positions().col(0).template cast<double>() - x).norm(), tol * (1 + x.norm())) << substeps;
    EXPECT_LT((w.velocities().col(0).template cast<double>() - v).norm(), tol * 10 * (1 + v.norm())) << substeps;
  }
}

TYPED_TEST(StepTest, PinnedParticlesNeverMove) {
  using Real = TypeParam;
  World<Real> w;
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  RopeOptions r;
  r.particles = 10;
  r.end_mass = 100.0;
  add_rope(w, r, set);
  const Vec3<Real> x0 = w.positions().col(0);
  for (int s = 0; s < 100; ++s) w.step();
  EXPECT_EQ(w.positions().col(0), x0);
  EXPECT_EQ(w.velocities().col(0), Vec3<Real>::Zero());
  EXPECT_LT(w.positions().col(9).z(), Real(0.9));  // the rest fell
}

TYPED_TEST(StepTest, DampingSlowsAFreeParticle) {
  using Real = TypeParam;
  World<Real> w;
  w.add_particle(Vec3<Real>::Zero(), Real(1), Vec3<Real>(Real(1), 0, 0));
  StepParams<Real> p;
  p.gravity.setZero();
  p.damping = Real(6);  // v ← v (1 − 6 h) with h = 1/60: × 0.9 per step
  w.set_params(p);
  w.step();
  EXPECT_NEAR(double(w.velocities()(0, 0)), 0.9, 1e-6);
}

TYPED_TEST(StepTest, FastParticlesNeverEndUpBehindAPlane) {
  using Real = TypeParam;
  World<Real> w;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 200; ++i)
    w.add_particle(Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(0.5 + 0.5 * u(rng) + 0.5)), Real(1),
                   Vec3<Real>(Real(5 * u(rng)), Real(5 * u(rng)), Real(-200 - 100 * u(rng))));  // ~3-5 m per step
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
  for (int s = 0; s < 30; ++s) {
    w.step();
    const auto x = w.positions();
    for (Index i = 0; i < w.num_particles(); ++i) ASSERT_GE(double(x(2, i)), 0.0) << "particle " << i << " step " << s;
  }
  EXPECT_EQ(penetration(w).max, 0.0);
}

TYPED_TEST(StepTest, FastParticlesNeverEndUpInsideASmallSphere) {
  using Real = TypeParam;
  World<Real> w;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3<double> c(0, 0, 0);
  const double r = 0.05;
  for (int i = 0; i < 200; ++i)  // aimed at the ball from all around, several radii per step
    w.add_particle(Vec3<Real>(Real(0.01 * u(rng)), Real(0.01 * u(rng)), Real(1.0)), Real(1),
                   Vec3<Real>(Real(3 * u(rng)), Real(3 * u(rng)), Real(-120)));
  w.add_sphere(c.cast<Real>(), Real(r));
  StepParams<Real> p;
  p.gravity.setZero();
  w.set_params(p);
  const double tol = sizeof(Real) == 4 ? 1e-6 : 1e-14;  // rounding of the projection onto the tangent plane
  for (int s = 0; s < 60; ++s) {
    w.step();
    const auto x = w.positions();
    for (Index i = 0; i < w.num_particles(); ++i)
      ASSERT_GE((x.col(i).template cast<double>() - c).norm(), r - tol) << "particle " << i << " step " << s;
  }
}

TYPED_TEST(StepTest, HangingClothStaysNearItsRestLengths) {
  using Real = TypeParam;
  World<Real> w;
  ClothOptions o;
  o.resolution = 12;
  add_cloth(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  StepParams<Real> p;
  p.iterations = 20;
  w.set_params(p);
  for (int s = 0; s < 120; ++s) w.step();
  const Violation v = stretch_violation(w);
  EXPECT_EQ(v.count, std::size_t(2 * 12 * 11 + 11 * 11));
  EXPECT_LT(v.max, 0.1);  // 20 sweeps leave a few % near the pinned corners
  EXPECT_TRUE(w.positions().allFinite());
  EXPECT_LT(w.positions().row(2).minCoeff(), Real(0.5));  // it swung down
}

}  // namespace
}  // namespace pbd
