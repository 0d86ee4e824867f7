// Tethers (constraints/tether.hpp) and their generation (pbd/tethers.hpp): one-sided projection, closed forms for a
// pendulum under PBD and XPBD on every solver, Euclidean against geodesic lengths, nearest against all sources and
// their colors, pins moved by the host, a hanging cloth's stretch, and the same bits on 1 and 2 threads.
#include "constraint_checks.hpp"
#include "error_checks.hpp"
#include "pbd/constraints/tether.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/metrics.hpp"
#include "pbd/tethers.hpp"
#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

namespace pbd {
namespace {

using Tether = TetherConstraint<double>;

std::vector<Index> all_particles(Index n) {
  std::vector<Index> v(n);
  std::iota(v.begin(), v.end(), Index(0));
  return v;
}

TEST(Tether, ASlackTetherLeavesItsParticleBitForBit) {
  const double start[3] = {0.1, -0.2, 0.3};
  for (double length : {0.5, std::sqrt(0.14)}) {  // slack, and exactly at its length (C = 0 or rounding above)
    double p[3] = {start[0], start[1], start[2]};
    const double w[1] = {1};
    double lambda = 0;
    project(Tether{{0}, 0, {0, 0, 0}, length}, p, w, SolveCoefficients<double>{1, 0}, lambda);
    if (length == 0.5) {
      EXPECT_EQ(std::memcmp(p, start, sizeof p), 0);
    }
    EXPECT_LE(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), length * (1 + 1e-15));
    EXPECT_EQ(lambda, 0);
  }
  double p[3] = {0, 0, 2};  // stretched: pulled back to its length along the line to the target
  const double w[1] = {1};
  double lambda = 0;
  project(Tether{{0}, 0, {0, 0, 0}, 0.5}, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_NEAR(p[2], 0.5, 1e-15);
  EXPECT_EQ(p[0], 0);
}

// A pin at (0, 0, 1) and a 1 kg bob `below` m under it, with a tether to the pin from add_tethers (its length: the
// start distance); `drop` lifts the bob towards the pin after the tether is made, so it starts slack.
World<double> pendulum(Solver solver, double compliance, double below, double drop = 0.0) {
  World<double> w;
  w.add_particle({0, 0, 1}, World<double>::kPinned);
  w.add_particle({0, 0, 1 - below}, 1.0);
  TetherOptions o;
  o.compliance = compliance;
  EXPECT_EQ(w.add_tethers(all_particles(2), o), 1u);
  w.positions()(2, 1) += drop;
  StepParams<double> p;
  p.solver = solver;
  p.substeps = 4;
  p.iterations = 2;
  w.set_params(p);
  return w;
}

TEST(Tether, NeverPushesASlackBobFallsAsWithoutIt) {
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(solver, 0.0, 0.5, 0.3);  // 0.2 m below the pin, the tether 0.5 m long
    World<double> free_fall;
    free_fall.add_particle({0, 0, 1}, World<double>::kPinned);
    free_fall.add_particle({0, 0, 0.8}, 1.0);
    free_fall.set_params(w.params());
    for (int s = 0; s < 8; ++s) {  // 8/60 s: falls 0.087 m, still slack
      w.step();
      free_fall.step();
      EXPECT_EQ(std::memcmp(w.positions().data(), free_fall.positions().data(), 6 * sizeof(double)), 0) << name(solver);
      EXPECT_EQ(std::memcmp(w.velocities().data(), free_fall.velocities().data(), 6 * sizeof(double)), 0);
    }
    EXPECT_LT(w.positions()(2, 1), 0.8 - 0.05);  // it did fall
  }
}

TEST(Tether, APbdTetherHoldsAPendulumAtItsLength) {
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(solver, 0.0, 0.5);
    for (int s = 0; s < 120; ++s) w.step();
    EXPECT_NEAR(w.positions()(2, 1), 0.5, 1e-12) << name(solver);
    EXPECT_NEAR(w.velocities().col(1).norm(), 0.0, 1e-9) << name(solver);
    EXPECT_LT(violation_of<Tether>(w).max, 1e-12);
    w.validate();
  }
}

TEST(Tether, AnXpbdTetherHangsAtItsLengthPlusComplianceTimesWeight) {
  const double alpha = 1e-3, g = 9.81;  // m/N; m = 1 kg: stretched by α·m·g = 9.81 mm
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(solver, alpha, 0.5);
    for (int s = 0; s < 600; ++s) w.step();  // implicit Euler damps the spring's oscillation
    EXPECT_NEAR(w.positions()(2, 1), 1.0 - (0.5 + alpha * g), 1e-9) << name(solver);
    EXPECT_NEAR(violation_of<Tether>(w).max, alpha * g, 1e-9);
  }
}

TEST(Tether, FollowsAPinTheHostMoves) {
  for (Solver solver : kSolvers) {
    World<double> w = pendulum(solver, 0.0, 0.5);
    w.step();
    w.positions().col(0) = Eigen::Vector3d(0.0, 0.0, 2.0);  // the pin raised by 1 m between steps
    w.step();
    EXPECT_EQ(w.constraints<Tether>()[0].target, Eigen::Vector3d(0.0, 0.0, 2.0));
    EXPECT_NEAR((w.positions().col(1) - w.positions().col(0)).norm(), 0.5, 1e-12) << name(solver);
  }
}

// An L-shaped chain of unit-spaced particles: a pin at (0, 0, 0), three along x to (3, 0, 0), three more along y to
// (3, 3, 0), joined by stretch constraints of their rest lengths.
World<double> l_chain() {
  World<double> w;
  w.add_particle({0, 0, 0}, World<double>::kPinned);
  for (int i = 1; i <= 3; ++i) w.add_particle({double(i), 0, 0}, 1.0);
  for (int i = 1; i <= 3; ++i) w.add_particle({3, double(i), 0}, 1.0);
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  for (Index i = 0; i + 1 < 7; ++i) w.add_stretch(i, i + 1, set);
  return w;
}

TEST(Tether, EuclideanAndGeodesicLengthsOnAnLShapedChain) {
  for (TetherLength length : {TetherLength::euclidean, TetherLength::geodesic}) {
    World<double> w = l_chain();
    TetherOptions o;
    o.length = length;
    ASSERT_EQ(w.add_tethers(all_particles(7), o), 6u);
    const auto t = w.constraints<Tether>();
    for (Index k = 0; k < 6; ++k) {
      const Index i = k + 1;
      EXPECT_EQ(t[k].particles[0], i);
      EXPECT_EQ(t[k].pin, 0u);
      EXPECT_EQ(t[k].target, Eigen::Vector3d::Zero());
      const double straight = w.positions().col(i).norm();
      EXPECT_EQ(t[k].length, length == TetherLength::euclidean ? straight : double(i)) << i;  // path: i unit edges
    }
    EXPECT_EQ(w.constraint_sets().back().mode, StiffnessMode::xpbd);
  }
}

TEST(Tether, NearestAndAllSourcesAndAnAnchorAsASource) {
  World<double> w = l_chain();
  w.set_mass(6, World<double>::kPinned);  // a second pin at the far end (3, 3, 0)
  const Index soft = w.add_constraint_set(Stiffness::pbd_k(0.5));
  w.add_anchor(3, soft, Eigen::Vector3d(3, 0, 0.5));  // particle 3 anchored 0.5 m above where it is
  TetherOptions nearest;
  nearest.length = TetherLength::geodesic;
  ASSERT_EQ(w.add_tethers(all_particles(7), nearest), 4u);  // 1, 2, 4, 5: the pins and the anchored one have none
  const auto t = w.constraints<Tether>();
  // 1 → pin 0 (1); 2 → anchor 3 (1 + 0.5) or pin 0 (2): the anchor; 4 → anchor (1.5) against pin 6 (2); 5 → pin 6.
  const Index particle[] = {1, 2, 4, 5}, pin[] = {0, 3, 3, 6};
  const double len[] = {1.0, 1.5, 1.5, 1.0};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(t[k].particles[0], particle[k]);
    EXPECT_EQ(t[k].pin, pin[k]) << k;
    EXPECT_EQ(t[k].length, len[k]) << k;
  }
  EXPECT_EQ(t[1].target, Eigen::Vector3d(3, 0, 0.5));  // an anchor's target, not the anchored particle
  TetherOptions all;
  all.to = TetherTo::all;
  EXPECT_EQ(w.add_tethers(all_particles(7), all), 12u);  // 4 particles × 3 sources
}

TEST(Tether, ABodyWithoutPinsOrAnchorsGetsNoTethersAndNoSet) {
  World<double> w;
  w.add_particle({0, 0, 0}, 1.0);
  w.add_particle({1, 0, 0}, 1.0);
  EXPECT_EQ(w.add_tethers(all_particles(2)), 0u);
  EXPECT_EQ(w.constraint_sets().size(), 0u);
  EXPECT_EQ(w.num_constraints(), 0u);
}

TEST(Tether, BadRequestsThrowAndChangeNothing) {
  World<double> w = l_chain();
  const std::vector<Index> out_of_range = {0, 9}, twice = {0, 1, 1};
  TetherOptions bad;
  bad.compliance = -1;
  EXPECT_EQ(test::error_of([&] { w.add_tethers(out_of_range); }), "add_tethers: particle index 9 out of range (the world has 7 particles)");
  EXPECT_EQ(test::error_of([&] { w.add_tethers(twice); }), "add_tethers: particle 1 is listed twice");
  EXPECT_EQ(test::error_of([&] { w.add_tethers(all_particles(7), bad); }), "add_tethers: compliance must be finite and >= 0, got -1");
  EXPECT_EQ(w.constraints<Tether>().size(), 0u);
  EXPECT_EQ(w.constraint_sets().size(), 1u);
}

// An n×n hanging cloth (1 m, two corners pinned, PBD stretch k = 1) with tethers to the nearest pin or without.
World<float> cloth(int n, bool tethers, Solver solver, TetherTo to = TetherTo::nearest, int substeps = 8) {
  World<float> w;
  ClothOptions c;
  c.resolution = n;
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  add_cloth(w, c, set);
  if (tethers) {
    TetherOptions o;
    o.to = to;
    w.add_tethers(all_particles(w.num_particles()), o);
  }
  StepParams<float> p;
  p.solver = solver;
  p.substeps = substeps;
  p.iterations = 1;
  w.set_params(p);
  return w;
}

TEST(Tether, AHangingClothStretchesLessWithTethersAtEqualSweeps) {
  for (Solver solver : kSolvers) {
    World<float> with = cloth(20, true, solver), without = cloth(20, false, solver);
    double with_sum = 0, without_sum = 0;
    for (int s = 0; s < 30; ++s) {
      with.step();
      without.step();
      with_sum += stretch_violation(with).rms;
      without_sum += stretch_violation(without).rms;
    }
    // The run's mean RMS stretch at least halved; Jacobi averages each tether's correction with the particle's
    // other ones (split masses), so it gains less at this budget.
    EXPECT_LT(with_sum, (solver == Solver::jacobi ? 0.9 : 0.5) * without_sum) << name(solver);
    // A Gauss-Seidel sweep ends with the tethers: none is left stretched.
    if (solver != Solver::jacobi) {
      EXPECT_LT(violation_of<TetherConstraint<float>>(with).max, 1e-6) << name(solver);
    }
  }
}

TEST(Tether, NearestIsOneColorAllIsOnePerPin) {
  for (TetherTo to : {TetherTo::nearest, TetherTo::all}) {
    World<float> w = cloth(12, true, Solver::colored, to);
    EXPECT_EQ(w.colors<TetherConstraint<float>>().num_colors, to == TetherTo::nearest ? 1u : 2u);
    w.validate();
  }
}

// Final positions after 10 steps of the tethered cloth on `threads` threads.
std::vector<float> run(Solver solver, int threads, bool chebyshev) {
  World<float> w = cloth(16, true, solver, TetherTo::all, 2);
  StepParams<float> p = w.params();
  p.iterations = 4;  // Chebyshev measures ρ over its first sweeps
  p.chebyshev.enabled = chebyshev;
  w.set_params(p);
  std::vector<float> x;
  tbb::task_arena(threads).execute([&] {
    for (int s = 0; s < 10; ++s) w.step();
  });
  x.assign(w.positions().data(), w.positions().data() + w.positions().size());
  return x;
}

TEST(Tether, SameBitsOnOneAndTwoThreads) {
  for (Solver solver : {Solver::colored, Solver::jacobi, Solver::block})
    for (bool chebyshev : {false, true}) {
      if (chebyshev && solver == Solver::jacobi) continue;
      const std::vector<float> one = run(solver, 1, chebyshev), two = run(solver, 2, chebyshev);
      EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(float)), 0)
          << name(solver) << (chebyshev ? " + chebyshev" : "");
    }
}

}  // namespace
}  // namespace pbd
