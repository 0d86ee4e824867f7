// The leash (tests/new_type/leash.hpp) once it is in the list, built only inside check_new_type.sh's copy of the
// tree: its physics against closed forms, the determinism of every solver with it, and free bodies (a leashed body
// is held, not free). The list-walking tests (tests/io/constraint_types_test.cpp) run beside these.
#include "error_checks.hpp"
#include "pbd/constraints/leash.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cmath>

namespace pbd {
namespace {

using Leash = LeashConstraint<double>;

static_assert(is_builtin_v<Leash, double>, "check_new_type.sh adds the leash to BuiltinConstraintTypes");

// A pendulum bob of 1 kg released at its leash's fixed point (0, 0, 1): it falls freely while the leash is slack,
// is caught at |p − p0| = L and hangs there.
World<double> pendulum(double length, Solver solver) {
  World<double> w;
  w.add_particle({0, 0, 1}, 1.0);
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  Leash t = blank_constraint<Leash>();
  t.particles = {0};
  t.set = set;
  t.length = length;
  w.add(t, 2u);  // the length given, the fixed point where the bob starts
  StepParams<double> p;
  p.solver = solver;
  w.set_params(p);
  return w;
}

TEST(Leash, APendulumSettlesAtItsLengthBelowTheFixedPoint) {
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(0.5, solver);
    for (int s = 0; s < 240; ++s) w.step();
    const auto x = w.positions();
    EXPECT_NEAR(x(2, 0), 1.0 - 0.5, 1e-9) << name(solver);
    EXPECT_EQ(x(0, 0), 0.0);
    EXPECT_EQ(x(1, 0), 0.0);
    EXPECT_NEAR(w.velocities().col(0).norm(), 0.0, 1e-6) << name(solver);
    EXPECT_LT(violation_of<Leash>(w).max, 1e-9);
    w.validate();
  }
}

TEST(Leash, ASlackLeashExertsNothingTheBobFallsFreely) {
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(100.0, solver);
    World<double> free_fall;
    free_fall.add_particle({0, 0, 1}, 1.0);
    free_fall.set_params(w.params());
    const int n = 30;
    for (int s = 0; s < n; ++s) {
      w.step();
      free_fall.step();
    }
    // Bit for bit the unleashed bob, and the closed form of the integrator: z_n = z_0 − g·h²·n(n + 1)/2.
    EXPECT_EQ(position_hash(w), position_hash(free_fall)) << name(solver);
    const double h = w.params().dt, g = 9.81;
    EXPECT_NEAR(w.positions()(2, 0), 1.0 - g * h * h * n * (n + 1) / 2, 1e-9) << name(solver);
    EXPECT_EQ(violation_of<Leash>(w).max, 0.0);
  }
}

// XPBD (λ accumulated per sub-step): a compliant leash of compliance α holds the 1 kg bob at L + α·m·g, the
// stretch at which its force α⁻¹·δ carries the weight; every solver.
TEST(Leash, ACompliantLeashStretchesByItsComplianceTimesTheWeight) {
  const double alpha = 1e-4, g = 9.81;
  for (Solver solver : kSolvers) {
    World<double> w;
    w.add_particle({0, 0, 1}, 1.0);
    const Index set = w.add_constraint_set(Stiffness::xpbd_compliance(alpha));
    Leash t = blank_constraint<Leash>();
    t.particles = {0};
    t.set = set;
    t.length = 0.5;
    w.add(t, 2u);
    auto p = w.params();
    p.solver = solver;
    w.set_params(p);
    for (int s = 0; s < 600; ++s) w.step();
    EXPECT_NEAR(1.0 - w.positions()(2, 0), 0.5 + alpha * g, 1e-9) << name(solver);
    EXPECT_NEAR(violation_of<Leash>(w).max, alpha * g, 1e-9) << name(solver);
    w.validate();
  }
}

// A swinging pendulum: the bob never gets farther than L from the fixed point, on every solver.
TEST(Leash, ASwingingBobStaysWithinItsLength) {
  for (Solver solver : kSolvers) {
    World<double> w;
    w.add_particle({0.5, 0, 1}, 1.0);
    const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
    Leash t = blank_constraint<Leash>();
    t.particles = {0};
    t.set = set;
    t.target = {0, 0, 1};
    w.add(t, 1u);  // the fixed point given, the length measured: 0.5
    EXPECT_DOUBLE_EQ(w.constraints<Leash>()[0].length, 0.5);
    auto p = w.params();
    p.solver = solver;
    w.set_params(p);
    for (int s = 0; s < 120; ++s) {
      w.step();
      ASSERT_LE((w.positions().col(0) - Vec3<double>(0, 0, 1)).norm(), 0.5 + 1e-9) << name(solver) << " step " << s;
    }
  }
}

// The determinism contract with leashes among other constraints: a rope of 40 particles, its end leashed, steps to
// the same bits on 1 and 2 threads under every parallel solver.
TEST(Leash, EveryParallelSolverGivesTheSameBitsOnOneAndTwoThreads) {
  for (Solver solver : {Solver::colored, Solver::jacobi, Solver::block}) {
    std::uint64_t hash[2];
    for (int threads : {1, 2}) {
      World<float> w;
      const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
      for (int i = 0; i < 40; ++i) w.add_particle({0.025f * float(i), 0, 1}, i == 0 ? World<float>::kPinned : 0.1f);
      for (Index i = 0; i + 1 < 40; ++i) w.add_stretch(i, i + 1, set);
      LeashConstraint<float> t = blank_constraint<LeashConstraint<float>>();
      t.particles = {39};
      t.set = set;
      t.target = {1.2f, 0, 1};
      t.length = 0.3f;
      w.add(t, kAllFields);
      auto p = w.params();
      p.solver = solver;
      w.set_params(p);
      ParallelConfig config;
      config.inline_below = 1;  // small colors go to the threads too
      config.min_grain = 1;
      w.set_parallel_config(config);
      tbb::task_arena arena(threads);
      arena.execute([&] {
        for (int s = 0; s < 30; ++s) w.step();
      });
      w.validate();
      hash[threads - 1] = position_hash(w);
    }
    EXPECT_EQ(hash[0], hash[1]) << name(solver);
  }
}

}  // namespace
}  // namespace pbd
