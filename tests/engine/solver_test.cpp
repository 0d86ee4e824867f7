// The colored and Jacobi solvers: proper colors, the index map, determinism for any thread count, and agreement
// with the serial reference.
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include "world_access.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cstring>
#include <numeric>
#include <random>
#include <set>

namespace pbd {
namespace {

// Forces real parallel loops even in small test scenes (every color forked, chunks of one constraint).
constexpr ParallelConfig kAlwaysFork{1, 1};

template <class Real> World<Real> cloth_world(int n) {
  World<Real> w;
  ClothOptions o;
  o.resolution = n;
  add_cloth(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  w.add_sphere(Vec3<Real>(Real(0.5), Real(0.5), Real(0.6)), Real(0.2));
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0.3));
  return w;
}

template <class Real> World<Real> rope_world() {
  World<Real> w;
  RopeOptions o;
  o.particles = 40;
  o.end_mass = 1000.0;
  add_rope(w, o, w.add_constraint_set(Stiffness::xpbd_compliance(1e-6)));
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0.2));
  return w;
}

// Random particles, random stretch pairs (some sharing pinned particles), anchors, two sets, plane + sphere so
// that particles get several collisions each.
template <class Real> World<Real> random_world(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  World<Real> w;
  const int n = 300;
  for (int i = 0; i < n; ++i)
    w.add_particle(Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng) * 0.2)), i % 17 == 0 ? World<Real>::kPinned : Real(0.5 + u(rng) * 0.4));
  const Index soft = w.add_constraint_set(Stiffness::pbd_k(0.7));
  const Index hard = w.add_constraint_set(Stiffness::xpbd_compliance(1e-7));
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < 1500; ++k) {
    const Index a = Index(pick(rng)), b = Index(pick(rng));
    if (a != b) w.add_stretch(a, b, k % 3 ? soft : hard, Real(0.8 * std::abs(u(rng)) + 0.05));
  }
  for (int k = 0; k < 40; ++k) w.add_anchor(Index(pick(rng)), soft);
  w.add_plane(Vec3<Real>(0, 0, 1), Real(-0.1));
  w.add_sphere(Vec3<Real>(0, 0, -0.1), Real(0.4));
  return w;
}

// Two inflating balls (stretch, bending, area, volume; 162 particles each, so two reduction blocks) and a cloth
// with bending and area, over a plane.
template <class Real> World<Real> mesh_world() {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::xpbd_compliance(1e-4));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.2));
  sets.area = w.add_constraint_set(Stiffness::pbd_k(0.5));
  sets.volume = w.add_constraint_set(Stiffness::xpbd_compliance(1e-7));
  sets.pressure = {1.0, 2.0, 0.2};
  MeshBodyOptions o;
  o.origin = {0.0, 0.0, 0.5};
  add_mesh(w, icosphere_mesh(2, 0.3), o, sets);
  o.origin = {0.7, 0.1, 0.6};
  o.pinned = {0, 5};
  add_mesh(w, icosphere_mesh(2, 0.25), o, sets);
  sets.volume.reset();
  o.origin = {-1.0, -0.5, 1.0};
  add_mesh(w, grid_mesh(8, 1.0), o, sets);
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0.1));
  return w;
}

template <class Real> std::vector<Real> run(World<Real> w, Solver solver, int threads, int steps) {
  StepParams<Real> p = w.params();
  p.solver = solver;
  p.iterations = 5;
  p.substeps = 2;
  w.set_params(p);
  w.set_parallel_config(kAlwaysFork);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (int s = 0; s < steps; ++s) w.step();
  });
  std::vector<Real> out(w.positions().data(), w.positions().data() + w.positions().size());
  out.insert(out.end(), w.velocities().data(), w.velocities().data() + w.velocities().size());
  return out;
}

template <class Real> bool bitwise_equal(const std::vector<Real>& a, const std::vector<Real>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Real)) == 0;
}

template <class Real> class SolverTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(SolverTest, Precisions);

TYPED_TEST(SolverTest, ColoredIsBitwiseIdenticalForAnyThreadCountAndToSerialColorOrder) {
  using Real = TypeParam;
  const std::vector<std::pair<const char*, World<Real>>> scenes = {
      {"cloth", cloth_world<Real>(16)}, {"rope", rope_world<Real>()}, {"random 1", random_world<Real>(1)},
      {"random 2", random_world<Real>(2)}, {"meshes", mesh_world<Real>()}};
  for (const auto& [name, world] : scenes) {
    const auto reference = run(world, Solver::serial_colored, 1, 30);
    for (Real v : reference) ASSERT_TRUE(std::isfinite(v)) << name;
    for (int threads : {1, 2, 3, 4})
      EXPECT_TRUE(bitwise_equal(reference, run(world, Solver::colored, threads, 30))) << name << ", " << threads << " threads";
  }
}

// Stretch constraints that share no movable particle give the same result in any order, so the serial reference
// (scalar projection, insertion order) and the colored solver (float: four at a time with SIMD on padded
// positions) must agree bit for bit. The pairs cover what the SIMD kernel masks or mixes within one block of four:
// coincident particles, one or both ends pinned (pinned ends shared between constraints), PBD, iteration-independent
// and XPBD sets side by side, rest lengths shorter and longer than the distance, and counts that leave 1 to 3
// constraints for the scalar remainder. Each count runs with an XPBD set among the three (the kernel keeps λ) and
// with three sets of α̃ = 0 and different k (the kernel neither reads nor writes λ); and each of these with the
// constraints spread over the three sets and with all of them in the second set (k and α̃ read once per range).
TYPED_TEST(SolverTest, StretchKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (bool with_xpbd : {true, false})
  for (bool one_set : {false, true}) {
    for (int count : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 15, 16, 61, 250, 1003}) {
      std::mt19937 rng{unsigned(count)};
      std::uniform_real_distribution<double> u(-1, 1);
      World<Real> w;
      const Index pin_a = w.add_particle(Vec3<Real>(0, 0, 1), World<Real>::kPinned);
      const Index pin_b = w.add_particle(Vec3<Real>(Real(0.3), 0, 1), World<Real>::kPinned);
      const Index sets[3] = {w.add_constraint_set(Stiffness::pbd_k(0.7)),
                             w.add_constraint_set(with_xpbd ? Stiffness::xpbd_compliance(1e-5) : Stiffness::pbd_k(0.3)),
                             w.add_constraint_set(Stiffness::iteration_independent(0.4))};
      auto random_point = [&] { return Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng))); };
      auto movable = [&] { return w.add_particle(random_point(), Real(0.2 + 2 * std::abs(u(rng)))); };
      for (int k = 0; k < count; ++k) {
        const Index set = sets[one_set ? 1 : std::uniform_int_distribution<int>(0, 2)(rng)];
        const Real rest = Real(0.5 * std::abs(u(rng)) + 0.01);
        switch (k % 7) {
          case 0: {  // coincident: no direction, skipped
            const Vec3<Real> at = random_point();
            const Index a = w.add_particle(at, 1);
            w.add_stretch(a, w.add_particle(at, 1), set, rest);
            break;
          }
          case 1: w.add_stretch(pin_a, movable(), set, rest); break;  // first end pinned (and shared)
          case 2: w.add_stretch(movable(), pin_b, set, rest); break;  // second end pinned (and shared)
          case 3: w.add_stretch(pin_a, pin_b, set, rest); break;      // both pinned: PBD skips, XPBD moves λ only
          default: w.add_stretch(movable(), movable(), set, rest); break;
        }
      }
      // Steps without collisions or other constraints: only stretch projections move particles.
      const auto serial = run(w, Solver::serial, 1, 12);
      for (int threads : {1, 2})
        EXPECT_TRUE(bitwise_equal(serial, run(w, Solver::colored, threads, 12)))
            << count << " constraints, " << threads << " threads, " << (with_xpbd ? "with" : "without") << " XPBD, "
            << (one_set ? "one set" : "three sets");
    }
  }
}

// The colored solver reads k and α̃ once for a stretch color whose constraints all share one set. What it knows of
// each color's set must follow every change of the colored array: constraints appended into a tail color (first of
// one set, then of another, which makes it mixed) and constraints removed (an emptied color is dropped and the
// others renumbered). The constraints share no movable particle, so any order gives the same bits as the serial
// reference; taking the mixed tail color for one set would project some of its constraints with the other's k.
TYPED_TEST(SolverTest, StretchSetsOfEachColorFollowAppendsAndRemovals) {
  using Real = TypeParam;
  auto scenario = [](Solver solver) {
    World<Real> w;
    StepParams<Real> p = w.params();
    p.solver = solver;
    p.iterations = 3;
    w.set_params(p);
    const Index soft = w.add_constraint_set(Stiffness::pbd_k(0.9));
    const Index stiff = w.add_constraint_set(Stiffness::pbd_k(0.2));
    std::mt19937 rng{7};
    std::uniform_real_distribution<double> u(-1, 1);
    auto add = [&](Index set, int count) {
      for (int k = 0; k < count; ++k) {
        const Index a = w.add_particle(Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng))), 1);
        const Index b = w.add_particle(Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng))), 1);
        w.add_stretch(a, b, set, Real(0.5));
      }
    };
    std::vector<Real> out;
    auto step = [&] {
      w.step();
      out.insert(out.end(), w.positions().data(), w.positions().data() + w.positions().size());
    };
    add(soft, 400);  // one color, all soft
    step();
    add(stiff, 12);  // appended (under 10% of the constraints) into a tail color, all stiff
    step();
    add(soft, 12);   // into the same tail color: now mixed
    step();
    std::vector<Index> first(400);
    std::iota(first.begin(), first.end(), Index(0));
    w.remove_stretch(first);  // the first color is emptied and dropped: the mixed one takes its number
    step();
    add(stiff, 8);
    step();
    return out;
  };
  EXPECT_TRUE(bitwise_equal(scenario(Solver::serial), scenario(Solver::colored)));
}

TYPED_TEST(SolverTest, JacobiIsBitwiseIdenticalForAnyThreadCount) {
  using Real = TypeParam;
  for (const World<Real>& world : {cloth_world<Real>(16), random_world<Real>(3), mesh_world<Real>()}) {
    const auto reference = run(world, Solver::jacobi, 1, 30);
    for (int threads : {2, 3, 4}) EXPECT_TRUE(bitwise_equal(reference, run(world, Solver::jacobi, threads, 30))) << threads;
  }
}

TEST(ColoredConstraints, EveryColorIsIndependentAndTheIndexMapIsExact) {
  for (unsigned seed : {1u, 2u, 3u}) {
    World<double> w = random_world<double>(seed);
    const World<double> uncolored = w;  // never colored: its stores keep insertion order
    const auto inv_mass = w.inverse_masses();
    auto check = [&](const auto& colored, const auto& original) {
      ASSERT_EQ(colored.items.size(), original.size());
      ASSERT_EQ(colored.offsets.back(), original.size());
      for (std::size_t i = 0; i < original.size(); ++i) {
        EXPECT_EQ(colored.items[colored.stored[i]].particles, original[i].particles) << i;
        EXPECT_EQ(colored.items[colored.stored[i]].set, original[i].set) << i;
      }
      for (Index c = 0; c < colored.num_colors; ++c) {
        std::set<Index> moved;
        for (Index i = colored.offsets[c]; i < colored.offsets[c + 1]; ++i)
          for (Index p : colored.items[i].particles)
            if (inv_mass[p] != 0) {
              EXPECT_TRUE(moved.insert(p).second) << "particle " << p << " twice in color " << c;
            }
      }
    };
    check(w.colors<StretchConstraint<double>>(), test::stretch_of(uncolored));
    check(w.colors<AnchorConstraint<double>>(), test::anchor_of(uncolored));
    EXPECT_GE(w.colors<StretchConstraint<double>>().num_colors, 2u);
    // The user's view follows the map: the same constraints in the same order as the uncolored world's.
    for (std::size_t i = 0; i < test::stretch_of(w).size(); ++i)
      EXPECT_EQ(test::stretch_of(w)[i].particles, test::stretch_of(uncolored)[i].particles) << i;
    EXPECT_NO_THROW(w.validate());
  }
}

TEST(ColoredConstraints, AddingAConstraintOrUnpinningRecolors) {
  World<double> w = cloth_world<double>(8);
  const Index before = Index(w.colors<StretchConstraint<double>>().size());
  w.add_stretch(0, 63, 0);
  EXPECT_EQ(w.colors<StretchConstraint<double>>().size(), before + 1u);
  // Unpinning a corner makes constraints that shared it conflict: the coloring must still be proper.
  w.set_mass(56, 1.0);
  const auto c = w.colors<StretchConstraint<double>>();
  for (Index col = 0; col < c.num_colors; ++col) {
    std::set<Index> seen;
    for (Index i = c.offsets[col]; i < c.offsets[col + 1]; ++i)
      for (Index p : c.items[i].particles) EXPECT_TRUE(seen.insert(p).second);
  }
  EXPECT_NO_THROW(w.validate());
}

// Max relative stretch of a hanging rope after 60 damped steps with the given solver and sweeps.
template <class Real> double rope_stretch_after(Solver s, int iterations) {
  World<Real> w;
  RopeOptions o;
  o.particles = 10;
  o.direction = {0.0, 0.0, -1.0};
  add_rope(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  StepParams<Real> p;
  p.solver = s;
  p.iterations = iterations;
  p.damping = Real(5);
  w.set_params(p);
  for (int k = 0; k < 60; ++k) w.step();
  return stretch_violation(w).max;
}

TYPED_TEST(SolverTest, EverySolverConvergesWithMoreSweeps) {
  using Real = TypeParam;
  for (Solver s : {Solver::serial, Solver::serial_colored, Solver::colored, Solver::jacobi}) {
    const double few = rope_stretch_after<Real>(s, 5), many = rope_stretch_after<Real>(s, 100);
    EXPECT_LT(many, few / 4) << name(s);
    EXPECT_LT(many, 0.01) << name(s);
  }
}

TYPED_TEST(SolverTest, ContactsHoldUnderGaussSeidelAndStayBoundedUnderJacobi) {
  using Real = TypeParam;
  for (Solver s : {Solver::serial, Solver::serial_colored, Solver::colored, Solver::jacobi}) {
    World<Real> w = cloth_world<Real>(12);
    StepParams<Real> p;
    p.solver = s;
    p.iterations = 10;
    p.substeps = 4;
    w.set_params(p);
    for (int k = 0; k < 120; ++k) w.step();
    ASSERT_TRUE(w.positions().allFinite()) << name(s);
    // Every solver ends each sweep with the contacts, projected in place (Jacobi too), so they hold up to rounding.
    EXPECT_LT(penetration(w).max, 1e-5) << name(s);
  }
}

TEST(Solver, NamesRoundTrip) {
  for (Solver s : {Solver::serial, Solver::serial_colored, Solver::colored, Solver::jacobi}) EXPECT_EQ(parse_solver(name(s)), s);
  EXPECT_FALSE(parse_solver("gauss").has_value());
}

}  // namespace
}  // namespace pbd
