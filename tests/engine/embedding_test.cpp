// What a host simulator relies on: external forces, a force callback, adding and removing constraints and particles
// between steps with limited recoloring, user-defined constraint types, running in the host's task_arena, and
// per-step statistics.
#include "constraint_checks.hpp"
#include "world_access.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <random>
#include <set>

namespace host {

// A user-defined constraint type, as a host would write it: keeps a particle at height `z` (C = p.z − z), and
// records the largest arena it was evaluated in (to show the solver runs in the caller's arena).
template <class Real> struct HeightConstraint {
  static constexpr const char* kName = "height";
  static constexpr int kArity = 1;
  static constexpr bool kInequality = false;
  std::array<pbd::Index, 1> particles;
  pbd::Index set;
  Real z;
};
inline std::atomic<int> widest_arena{0};
template <class Real>
bool evaluate(const HeightConstraint<Real>& c, const pbd::Vec3<Real> (&p)[1], Real& C, pbd::Vec3<Real> (&grad)[1]) {
  int seen = widest_arena.load();
  const int now = tbb::this_task_arena::max_concurrency();
  while (now > seen && !widest_arena.compare_exchange_weak(seen, now)) {}
  C = p[0].z() - c.z;
  grad[0] = pbd::Vec3<Real>::UnitZ();
  return true;
}

// A host's own distance constraint: the same maths as the built-in stretch constraint, including stretch's own
// correction (a type may supply one, found by argument-dependent lookup, instead of the generic one).
template <class Real> struct Distance {
  static constexpr const char* kName = "distance";
  static constexpr int kArity = 2;
  static constexpr bool kInequality = false;
  static constexpr bool kUnitGradients = true;
  std::array<pbd::Index, 2> particles;
  pbd::Index set;
  Real rest;
};
template <class Real>
bool evaluate(const Distance<Real>& c, const pbd::Vec3<Real> (&p)[2], Real& C, pbd::Vec3<Real> (&grad)[2]) {
  return evaluate(pbd::StretchConstraint<Real>{c.particles, c.set, c.rest}, p, C, grad);
}
template <class Real>
bool correction(const Distance<Real>& c, const pbd::Vec3<Real> (&p)[2], const Real (&w)[2],
                pbd::SolveCoefficients<Real> coeff, Real lambda, pbd::Vec3<Real> (&dp)[2], Real& dlambda) {
  return correction(pbd::StretchConstraint<Real>{c.particles, c.set, c.rest}, p, w, coeff, lambda, dp, dlambda);
}

}  // namespace host

namespace pbd {
namespace {

World<double> cloth(int n, Solver solver = Solver::colored) {
  World<double> w;
  ClothOptions o;
  o.resolution = n;
  add_cloth(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  StepParams<double> p;
  p.solver = solver;
  w.set_params(p);
  w.set_parallel_config({1, 1});  // fork even for tiny colors, so the tests exercise real parallel loops
  return w;
}

std::vector<double> state(const World<double>& w) {
  std::vector<double> s(w.positions().data(), w.positions().data() + w.positions().size());
  s.insert(s.end(), w.velocities().data(), w.velocities().data() + w.velocities().size());
  return s;
}

// Every color of every type of `w` holds constraints on distinct movable particles.
void expect_proper(World<double>& w) {
  const auto inv = w.inverse_masses();
  auto check = [&](const auto& a) {
    for (Index col = 0; col < a.num_colors; ++col) {
      std::set<Index> seen;
      for (Index i = a.offsets[col]; i < a.offsets[col + 1]; ++i)
        for (Index p : a.items[i].particles)
          if (inv[p] != 0) {
            EXPECT_TRUE(seen.insert(p).second) << "particle " << p << " twice in color " << col;
          }
    }
  };
  check(w.colors<StretchConstraint<double>>());
  check(w.colors<AnchorConstraint<double>>());
  check(w.colors<BendingConstraint<double>>());
  check(w.colors<AreaConstraint<double>>());
  EXPECT_NO_THROW(w.validate());
}

TEST(ExternalForces, ConstantForceOnAFreeParticleFollowsTheClosedForm) {
  World<double> w;
  w.add_particle({0, 0, 0}, 2.0);
  w.add_particle({5, 0, 0}, World<double>::kPinned);
  StepParams<double> p;
  p.gravity.setZero();
  p.substeps = 4;
  p.dt = 0.01;
  w.set_params(p);
  Matrix3X<double> f = Matrix3X<double>::Zero(3, 2);
  f.col(0) = Vec3<double>(1.0, 0, -4.0);
  f.col(1) = Vec3<double>(100.0, 0, 0);  // on a pinned particle: ignored
  for (int s = 0; s < 10; ++s) w.step(f);
  const Vec3<double> a = f.col(0) / 2.0;  // a = w·f
  const double n = 40, h = 0.0025;
  EXPECT_LT((w.positions().col(0) - a * h * h * n * (n + 1) / 2).norm(), 1e-12);
  EXPECT_LT((w.velocities().col(0) - a * h * n).norm(), 1e-12);
  EXPECT_EQ(w.positions().col(1), Vec3<double>(5, 0, 0));
}

TEST(ExternalForces, BadForcesAreRejectedAndTheWorldIsUnchanged) {
  World<double> w = cloth(4);
  const auto before = state(w);
  Matrix3X<double> f = Matrix3X<double>::Zero(3, 16);
  f(1, 7) = std::nan("");
  try {
    w.step(f);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(w.step(Matrix3X<double>::Zero(3, 15)), Error);
  EXPECT_EQ(state(w), before);
  EXPECT_EQ(w.time(), 0.0);
}

TEST(ExternalForces, CallbackIsCalledEverySubstepWithTheTime) {
  World<double> w;
  w.add_particle({1, 0, 0}, 1.0);
  StepParams<double> p;
  p.gravity.setZero();
  p.substeps = 3;
  p.dt = 0.03;
  w.set_params(p);
  std::vector<double> times;
  w.set_force_callback([&](double t, Eigen::Ref<const Matrix3X<double>> x, Eigen::Ref<Matrix3X<double>> f) {
    times.push_back(t);
    f = -10.0 * x;  // a spring to the origin
  });
  w.step();
  w.step();
  ASSERT_EQ(times.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(times[i], 0.01 * (i + 1), 1e-12);
  EXPECT_LT(w.positions()(0, 0), 1.0);  // pulled towards the origin
  w.set_force_callback({});
  const double v = w.velocities()(0, 0);
  w.step();
  EXPECT_DOUBLE_EQ(w.velocities()(0, 0), v);  // no force any more, no gravity: constant velocity
}

TEST(Incremental, AddingConstraintsColorsOnlyTheNewOnesAndStaysDeterministic) {
  World<double> w = cloth(20);
  w.step();
  const Index colors = w.colors<StretchConstraint<double>>().num_colors;
  const std::vector<Index> colors_before(w.colors<StretchConstraint<double>>().color.begin(), w.colors<StretchConstraint<double>>().color.end());
  std::mt19937 rng(5);
  std::uniform_int_distribution<Index> pick(0, 399);
  for (int k = 0; k < 40; ++k) {  // ~4% more constraints, random pairs
    const Index a = pick(rng), b = pick(rng);
    if (a != b) w.add_stretch(a, b, 0);
  }
  expect_proper(w);
  const auto after = w.colors<StretchConstraint<double>>();
  for (std::size_t i = 0; i < colors_before.size(); ++i) ASSERT_EQ(after.color[i], colors_before[i]) << "recolored " << i;
  EXPECT_GE(after.num_colors, colors);
  // The incrementally colored world still gives the same bits on 1 and 2 threads and in serial color order.
  World<double> serial = w;
  StepParams<double> p = serial.params();
  p.solver = Solver::serial_colored;
  serial.set_params(p);
  World<double> two = w;
  for (int s = 0; s < 20; ++s) serial.step();
  tbb::task_arena(2).execute([&] {
    for (int s = 0; s < 20; ++s) two.step();
  });
  EXPECT_EQ(state(serial), state(two));
}

TEST(Incremental, RepeatedAndLargeAdditionsStayProper) {
  World<double> w = cloth(16);
  std::mt19937 rng(11);
  std::uniform_int_distribution<Index> pick(0, 255);
  for (int round = 0; round < 6; ++round) {  // small rounds fill the tail colors, a big one forces a full recolor
    const int count = round == 4 ? 400 : 10;
    for (int k = 0; k < count; ++k) {
      const Index a = pick(rng), b = pick(rng);
      if (a != b) w.add_stretch(a, b, 0);
    }
    expect_proper(w);
    const auto c = w.colors<StretchConstraint<double>>();
    ASSERT_EQ(c.items.size(), test::stretch_of(w).size());
    for (std::size_t i = 0; i < c.stored.size(); ++i)
      ASSERT_EQ(c.items[c.stored[i]].particles, test::stretch_of(w)[i].particles) << i;
    w.step();
  }
}

TEST(Incremental, RemovingConstraintsKeepsTheOthersColors) {
  World<double> w = cloth(10);
  w.step();
  const std::vector<Index> colors(w.colors<StretchConstraint<double>>().color.begin(), w.colors<StretchConstraint<double>>().color.end());
  const std::vector<Index> gone = {3, 0, 17};
  w.remove_stretch(gone);
  EXPECT_EQ(test::stretch_of(w).size(), colors.size() - 3);
  const auto after_span = w.colors<StretchConstraint<double>>().color;
  const std::vector<Index> after(after_span.begin(), after_span.end());
  std::vector<Index> expected;
  for (std::size_t i = 0; i < colors.size(); ++i)
    if (i != 0 && i != 3 && i != 17) expected.push_back(colors[i]);
  // The same colors up to renumbering of emptied colors (none empties here): equal.
  EXPECT_EQ(after, expected);
  expect_proper(w);
  w.step();
  EXPECT_TRUE(w.positions().allFinite());
}

TEST(Incremental, BadRemovalsAreRejectedAndChangeNothing) {
  World<double> w = cloth(5);
  const std::size_t n = test::stretch_of(w).size();
  const std::vector<Index> out_of_range = {1, Index(n)}, twice = {2, 2};
  EXPECT_THROW(w.remove_stretch(out_of_range), Error);
  EXPECT_THROW(w.remove_stretch(twice), Error);
  EXPECT_EQ(test::stretch_of(w).size(), n);
}

TEST(Incremental, RemovedParticleLosesItsConstraintsAndNeverMovesAgain) {
  World<double> w = cloth(6);
  const Index p = 14;
  const Vec3<double> x = w.positions().col(p);
  w.remove_particle(p);
  for (const auto& c : test::stretch_of(w)) EXPECT_TRUE(c.particles[0] != p && c.particles[1] != p);
  for (int s = 0; s < 10; ++s) w.step();
  EXPECT_EQ(w.positions().col(p), x);
  EXPECT_EQ(w.num_particles(), 36u);  // indices do not shift
  expect_proper(w);
}

TEST(Incremental, AddingParticlesDoesNotRecolor) {
  World<double> w = cloth(6);
  w.step();
  const std::vector<Index> colors(w.colors<StretchConstraint<double>>().color.begin(), w.colors<StretchConstraint<double>>().color.end());
  const Index q = w.add_particle({3, 3, 3}, 1.0);
  w.add_stretch(q, 0, 0);
  const auto after_span = w.colors<StretchConstraint<double>>().color;
  const std::vector<Index> after(after_span.begin(), after_span.end());
  for (std::size_t i = 0; i < colors.size(); ++i) EXPECT_EQ(after[i], colors[i]);
  w.step();
  EXPECT_TRUE(w.positions().allFinite());
}

TEST(CustomConstraints, HostTypeMatchesTheBuiltInStretchBitForBit) {
  for (Solver s : kSolvers) {
    World<double> builtin = cloth(8, s);
    World<double> hosted;
    hosted.add_particles(builtin.positions(), Eigen::VectorXd::Ones(64));
    for (Index i : {Index(56), Index(63)}) hosted.set_mass(i, World<double>::kPinned);
    const Index set = hosted.add_constraint_set(Stiffness::pbd_k(1.0));
    for (const auto& c : test::stretch_of(builtin)) hosted.add_custom(host::Distance<double>{c.particles, set, c.rest});
    hosted.set_params(builtin.params());
    for (int k = 0; k < 30; ++k) {
      builtin.step();
      hosted.step();
    }
    EXPECT_EQ(state(builtin), state(hosted)) << name(s);
    EXPECT_EQ(hosted.custom<host::Distance<double>>().size(), test::stretch_of(builtin).size());
  }
}

// A user-defined type lives in the same kind of store as a built-in one, is colored by the same code (full, then
// tail colors for constraints added later, kept across removals elsewhere) and is swept by the same driver: with
// the same constraints as the built-in stretch type it gets the same colors, the same layout and the same bits.
TEST(CustomConstraints, HostTypeGoesThroughTheSameStoreColoringAndSweepsAsBuiltIns) {
  World<double> builtin = cloth(12);
  World<double> hosted;
  hosted.add_particles_by_inverse_mass(builtin.positions(), builtin.inverse_masses());
  const Index set = hosted.add_constraint_set(Stiffness::pbd_k(1.0));
  for (const auto& c : test::stretch_of(builtin)) hosted.add_custom(host::Distance<double>{c.particles, set, c.rest});
  hosted.set_params(builtin.params());
  hosted.set_parallel_config({1, 1});
  auto same_layout = [&] {
    const auto a = builtin.colors<StretchConstraint<double>>();
    const auto b = hosted.colors<host::Distance<double>>();
    ASSERT_EQ(a.num_colors, b.num_colors);
    ASSERT_GE(b.num_colors, 2u);
    EXPECT_TRUE(std::equal(a.offsets.begin(), a.offsets.end(), b.offsets.begin(), b.offsets.end()));
    EXPECT_TRUE(std::equal(a.color.begin(), a.color.end(), b.color.begin(), b.color.end()));
    EXPECT_TRUE(std::equal(a.stored.begin(), a.stored.end(), b.stored.begin(), b.stored.end()));
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.items[i].particles, b.items[i].particles) << i;
    EXPECT_NO_THROW(hosted.validate());
  };
  same_layout();
  for (int k = 0; k < 5; ++k) {
    builtin.step();
    tbb::task_arena(2).execute([&] { hosted.step(); });
  }
  // A few more constraints: both get tail colors the same way, without recoloring the others.
  const Index before = hosted.colors<host::Distance<double>>().num_colors;
  for (auto [a, b] : {std::pair<Index, Index>{0, 13}, {5, 30}, {40, 41}}) {
    builtin.add_stretch(a, b, 0);
    hosted.add_custom(host::Distance<double>{{a, b}, set, (builtin.positions().col(a) - builtin.positions().col(b)).norm()});
  }
  same_layout();
  EXPECT_GT(hosted.colors<host::Distance<double>>().num_colors, before);  // the new ones went into tail colors
  for (int k = 0; k < 5; ++k) {
    builtin.step();
    tbb::task_arena(2).execute([&] { hosted.step(); });
  }
  EXPECT_EQ(state(builtin), state(hosted));
  // Removing a particle removes the user type's constraints on it, as it does the built-in ones.
  builtin.remove_particle(20);
  hosted.remove_particle(20);
  EXPECT_EQ(hosted.custom<host::Distance<double>>().size(), test::stretch_of(builtin).size());
  for (const auto& c : hosted.custom<host::Distance<double>>()) EXPECT_TRUE(c.particles[0] != 20 && c.particles[1] != 20);
  same_layout();
  builtin.step();
  hosted.step();
  EXPECT_EQ(state(builtin), state(hosted));
}

TEST(CustomConstraints, GradientOfTheHostTypeChecksOut) {
  std::mt19937 rng(9);
  for (int k = 0; k < 50; ++k) {
    const Vec3<double> p[1] = {test::random_point<double>(rng)};
    EXPECT_TRUE(test::check_gradient(host::HeightConstraint<double>{{0}, 0, 0.3}, p));
  }
}

TEST(CustomConstraints, BadHostConstraintsAreRejected) {
  World<double> w = cloth(3);
  EXPECT_THROW(w.add_custom(host::Distance<double>{{0, 9}, 0, 1.0}), Error);
  EXPECT_THROW(w.add_custom(host::Distance<double>{{2, 2}, 0, 1.0}), Error);
  EXPECT_THROW(w.add_custom(host::Distance<double>{{0, 1}, 5, 1.0}), Error);
  EXPECT_TRUE(w.custom<host::Distance<double>>().empty());
  w.add_custom(host::Distance<double>{{0, 1}, 0, 1.0});
}

TEST(HostArena, RunsInsideTheCallersArenaAndGivesTheSameBitsOnOneAndTwoThreads) {
  auto make = [] {
    World<double> w = cloth(12);
    const Index set = w.add_constraint_set(Stiffness::pbd_k(0.5));
    for (Index i = 0; i < 144; i += 5) w.add_custom(host::HeightConstraint<double>{{i}, set, 0.8});
    return w;
  };
  World<double> one = make(), two = make();
  host::widest_arena = 0;
  tbb::task_arena(1).execute([&] {
    for (int s = 0; s < 20; ++s) one.step();
  });
  EXPECT_EQ(host::widest_arena.load(), 1) << "the solver left the host's one-thread arena";
  host::widest_arena = 0;
  tbb::task_arena(2).execute([&] {
    for (int s = 0; s < 20; ++s) two.step();
  });
  EXPECT_EQ(host::widest_arena.load(), 2);
  EXPECT_EQ(state(one), state(two));
}

// A host that steps several worlds at once from its own parallel loop, in one arena: each world's solve holds a team
// of the arena's threads (team.hpp) while other worlds' solves want the same threads. Every world must finish and
// give the bits it gives stepped alone on one thread.
TEST(HostArena, WorldsSteppedAtOnceFromTheHostsParallelLoopGiveTheirOneThreadBits) {
  std::vector<World<double>> worlds;
  for (int k = 0; k < 6; ++k) {
    World<double> w = cloth(20 + k, k % 2 ? Solver::block : Solver::colored);
    w.set_blocking({64, true});
    worlds.push_back(w);
  }
  std::vector<std::vector<double>> alone;
  tbb::task_arena(1).execute([&] {
    for (World<double> w : worlds) {
      for (int s = 0; s < 15; ++s) w.step();
      alone.push_back(state(w));
    }
  });
  for (int threads : {2, 4}) {
    std::vector<World<double>> at_once = worlds;
    tbb::task_arena(threads).execute([&] {
      tbb::parallel_for(std::size_t(0), at_once.size(), [&](std::size_t k) {
        for (int s = 0; s < 15; ++s) at_once[k].step();
      });
    });
    for (std::size_t k = 0; k < worlds.size(); ++k)
      EXPECT_EQ(state(at_once[k]), alone[k]) << "world " << k << ", " << threads << " threads";
  }
}

TEST(StepStatistics, PhasesSweepsColorsAndViolation) {
  World<double> w = cloth(10);
  StepParams<double> p = w.params();
  p.substeps = 2;
  p.iterations = 7;
  w.set_params(p);
  w.add_plane({0, 0, 1}, 0.5);
  w.set_measure_violation(true);
  for (int s = 0; s < 30; ++s) w.step();
  const StepStats& st = w.last_step_stats();
  EXPECT_EQ(st.substeps, 2);
  EXPECT_EQ(st.sweeps, 14);
  EXPECT_EQ(st.colors, w.num_colors());
  EXPECT_GT(st.colors, 0u);
  EXPECT_GT(st.collisions, 0u);
  EXPECT_GT(st.seconds_integrate, 0.0);  // every phase that did work was timed
  EXPECT_GT(st.seconds_collisions, 0.0);
  EXPECT_GT(st.seconds_solve, 0.0);
  // The phases are parts of the step, so their times add up to at most its time: a check of the statistics'
  // bookkeeping, not of speed (no bound on any duration).
  EXPECT_LE(st.seconds_integrate + st.seconds_collisions + st.seconds_coloring + st.seconds_solve, st.seconds);
  ASSERT_EQ(st.violation.size(), 2u);
  EXPECT_EQ(st.violation[0].type, "stretch");
  EXPECT_EQ(st.violation[0].value.count, test::stretch_of(w).size());
  EXPECT_GT(st.violation[0].value.max, 0.0);
  EXPECT_DOUBLE_EQ(st.violation[0].value.rms, stretch_violation(w).rms);  // the measures of the state the step left
  EXPECT_DOUBLE_EQ(st.violation[0].value.max, stretch_violation(w).max);
  EXPECT_EQ(st.violation[1].type, "collision");
  EXPECT_LT(st.violation[1].value.max, 1e-9);
  w.set_measure_violation(false);
  w.step();
  EXPECT_TRUE(w.last_step_stats().violation.empty());
}

// The sweeps' waiting (StepStats::seconds_waiting, solve_threads): none on one thread; on two, part of the solve,
// and not zero once a step's sweeps ran on two threads (every shared color ends at a barrier, whose wait is timed).
TEST(StepStatistics, WaitingIsPartOfTheSolveAndNoneOnOneThread) {
  World<double> w = cloth(80);  // colors above the team's threshold (1,024 constraints)
  tbb::task_arena(1).execute([&] {
    for (int s = 0; s < 3; ++s) {
      w.step();
      EXPECT_EQ(w.last_step_stats().solve_threads, 1);
      EXPECT_EQ(w.last_step_stats().seconds_waiting, 0.0);
    }
  });
  bool shared = false;
  tbb::task_arena(2).execute([&] {
    for (int s = 0; s < 200 && !shared; ++s) {  // a team forms when the arena's worker joins in time
      // Wake the arena's worker first (both slots busy for 0.2 ms), so that it is at hand when the step's team forms
      // even when other processes load the machine.
      tbb::parallel_for(tbb::blocked_range<int>(0, 2, 1), [](const tbb::blocked_range<int>&) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
        while (std::chrono::steady_clock::now() < until) {
        }
      });
      w.step();
      const StepStats& st = w.last_step_stats();
      EXPECT_GE(st.solve_threads, 1);
      EXPECT_LE(st.solve_threads, 2);
      EXPECT_GE(st.seconds_waiting, 0.0);
      EXPECT_LE(st.seconds_waiting, st.seconds_solve);
      if (st.solve_threads == 2) {
        shared = true;
        EXPECT_GT(st.seconds_waiting, 0.0);
      } else {
        EXPECT_EQ(st.seconds_waiting, 0.0);
      }
    }
  });
  if (!shared) GTEST_SKIP() << "no step's sweeps ran on two threads in 200 steps (the arena's worker never joined)";
}

}  // namespace
}  // namespace pbd
