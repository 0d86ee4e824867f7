// The colored and Jacobi solvers: proper colors, the index map, determinism for any thread count, and agreement
// with the serial reference.
#include "pbd/detail/block_layout.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh.hpp"
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

// A Neo-Hookean block (E = 0.1 MPa, ν = 0.45) with two corners of its base pinned, dropped onto a plane: some hundred
// tets in some thirty colors, with XPBD λ (two per tet).
template <class Real> World<Real> tet_world() {
  World<Real> w;
  const TetMesh mesh = tet_box_mesh({5, 3, 3}, {0.5, 0.3, 0.3});
  const NeoHookeanMaterial m = young_poisson(1e5, 0.45);
  TetConstraintSets sets;
  sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
  sets.ratio = m.ratio();
  TetBodyOptions o;
  o.origin = {0.0, 0.0, 0.4};
  o.pinned = {0, 5};
  add_tet_body(w, mesh, o, sets);
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0.2));
  return w;
}

template <class Real>
std::vector<Real> run(World<Real> w, Solver solver, int threads, int steps, SweepOrder order = SweepOrder::forward) {
  StepParams<Real> p = w.params();
  p.solver = solver;
  p.iterations = 5;
  p.substeps = 2;
  p.sweep_order = order;
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
      {"random 2", random_world<Real>(2)}, {"meshes", mesh_world<Real>()}, {"tets", tet_world<Real>()}};
  for (const auto& [name, world] : scenes) {
    const auto reference = run(world, Solver::serial_colored, 1, 30);
    for (Real v : reference) ASSERT_TRUE(std::isfinite(v)) << name;
    for (int threads : {1, 2, 3, 4})
      EXPECT_TRUE(bitwise_equal(reference, run(world, Solver::colored, threads, 30))) << name << ", " << threads << " threads";
  }
}

// A step that is only predict, sweeps and update (no collider, no free body, no callback) runs all its sub-steps on
// one team of threads (solver.hpp, run_substeps): predict and update are the team's loops, and x and p trade
// places each sub-step. It must give the bits of the sub-step-by-sub-step path (the serial color order, and the
// colored solver on one thread) for odd and even sub-step counts, both sweep orders, damping, external forces and
// XPBD sets (λ reset every sub-step), for float and double.
TYPED_TEST(SolverTest, AStepOnOneTeamGivesTheBitsOfTheSubStepBySubStepPath) {
  using Real = TypeParam;
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::xpbd_compliance(1e-5));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.05));
  MeshBodyOptions o;
  o.pinned = {0, 29};
  add_mesh(w, grid_mesh(30, 1.0), o, sets);
  typename World<Real>::Positions forces(3, w.num_particles());
  for (Index i = 0; i < w.num_particles(); ++i) forces.col(i) = Vec3<Real>(Real(0.01 * (i % 7)), 0, Real(-0.02 * (i % 3)));
  auto run_with = [&](Solver solver, int threads, int substeps, SweepOrder order) {
    World<Real> copy = w;
    StepParams<Real> p = copy.params();
    p.solver = solver;
    p.substeps = substeps;
    p.iterations = 2;
    p.sweep_order = order;
    p.damping = Real(0.3);
    copy.set_params(p);
    copy.set_parallel_config(kAlwaysFork);
    tbb::task_arena(threads).execute([&] {
      for (int s = 0; s < 15; ++s) {
        if (s % 2) copy.step(forces);
        else copy.step();
      }
    });
    std::vector<Real> out(copy.positions().data(), copy.positions().data() + copy.positions().size());
    out.insert(out.end(), copy.velocities().data(), copy.velocities().data() + copy.velocities().size());
    return out;
  };
  for (int substeps : {1, 2, 3})
    for (SweepOrder order : {SweepOrder::forward, SweepOrder::symmetric}) {
      const auto reference = run_with(Solver::serial_colored, 1, substeps, order);
      for (Real v : reference) ASSERT_TRUE(std::isfinite(v));
      for (Solver solver : {Solver::colored, Solver::block})
        for (int threads : {1, 2, 4}) {
          const auto got = run_with(solver, threads, substeps, order);
          if (solver == Solver::colored) {
            EXPECT_TRUE(bitwise_equal(reference, got)) << substeps << " sub-steps, " << threads << " threads, " << name(order);
          } else {  // the block solver's own order: the same bits on any thread count
            EXPECT_TRUE(bitwise_equal(run_with(Solver::block, 1, substeps, order), got)) << substeps << " sub-steps, block, " << threads << " threads";
          }
        }
    }
}

// A world for a SIMD kernel's bit-for-bit test: four pinned particles (shared corners), three sets (PBD, XPBD or PBD,
// iteration-independent) and random movable particles of random masses, from a seeded generator.
template <class Real> struct KernelCase {
  World<Real> w;
  std::mt19937 rng;
  std::uniform_real_distribution<double> u{-1, 1};
  Index pin[4];
  Index sets[3];
  KernelCase(unsigned seed, bool with_xpbd) : rng(seed) {
    for (int i = 0; i < 4; ++i) pin[i] = w.add_particle(Vec3<Real>(Real(0.3 * i), Real(0.1 * i * i), 1), World<Real>::kPinned);
    sets[0] = w.add_constraint_set(Stiffness::pbd_k(0.7));
    sets[1] = w.add_constraint_set(with_xpbd ? Stiffness::xpbd_compliance(1e-3) : Stiffness::pbd_k(0.3));
    sets[2] = w.add_constraint_set(Stiffness::iteration_independent(0.4));
  }
  double uniform() { return u(rng); }
  Vec3<Real> random_point() { return Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng))); }
  Index at(const Vec3<Real>& x) { return w.add_particle(x, Real(0.2 + 2 * std::abs(u(rng)))); }
  Index movable() { return at(random_point()); }
  Index any_set() { return sets[std::uniform_int_distribution<int>(0, 2)(rng)]; }
  /// The colored solver on 1 and 2 threads gives the serial reference's bits after 12 steps (`what` names the case).
  void expect_colored_is_serial(const testing::Message& what) const {
    const auto serial = run(w, Solver::serial, 1, 12);
    for (Real v : serial) ASSERT_TRUE(std::isfinite(v)) << what;
    for (int threads : {1, 2})
      EXPECT_TRUE(bitwise_equal(serial, run(w, Solver::colored, threads, 12))) << what << ", " << threads << " threads";
  }
};

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

// Bending constraints that share no movable particle, likewise: the serial reference projects them with the scalar
// code, the colored solver (float) four at a time with SIMD on padded positions; both run bending_math.hpp, so they
// must agree bit for bit. The quadruples cover what the kernel masks within one block of four: a collinear triangle,
// coincident edge ends, a pair held exactly flat (the kink: skipped), pinned corners shared between constraints,
// all four corners pinned (PBD skips, XPBD moves λ only), PBD, iteration-independent and XPBD sets mixed in one block
// or all in one set, and counts that leave 1 to 3 constraints to the scalar remainder. Gravity moves the particles
// between steps, so every lane's guards are crossed in both directions over the run.
TYPED_TEST(SolverTest, BendingKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (bool with_xpbd : {true, false})
  for (bool one_set : {false, true}) {
    for (int count : {1, 2, 3, 4, 5, 7, 8, 9, 13, 16, 61, 250}) {
      KernelCase<Real> t(unsigned(count) + 7u, with_xpbd);
      for (int k = 0; k < count; ++k) {
        const Index set = one_set ? t.sets[1] : t.any_set();
        const Real rest = Real(0.3 + 2.8 * std::abs(t.uniform()));
        const Vec3<Real> a = t.random_point(), b = t.random_point();
        switch (k % 8) {
          case 0: t.w.add_bending(t.at(a), t.at(b), t.at(a + Real(0.4) * (b - a)), t.movable(), set, rest); break;  // collinear
          case 1: t.w.add_bending(t.at(a), t.at(a), t.movable(), t.movable(), set, rest); break;  // coincident edge ends
          case 2: {  // exactly flat: p4 = p1 + p2 − p3, in the plane of the first triangle
            const Vec3<Real> c(a.x() + Real(0.5), a.y(), a.z());
            t.w.add_bending(t.at(a), t.at(c), t.at(Vec3<Real>(a.x(), a.y() + Real(0.5), a.z())),
                          t.at(Vec3<Real>(c.x(), a.y() - Real(0.5), a.z())), set, rest);
            break;
          }
          case 3: t.w.add_bending(t.pin[0], t.pin[1], t.movable(), t.movable(), set, rest); break;  // shared pinned edge
          case 4: t.w.add_bending(t.movable(), t.movable(), t.pin[2], t.movable(), set, rest); break;  // shared pinned corner
          case 5: t.w.add_bending(t.pin[0], t.pin[1], t.pin[2], t.pin[3], set, rest); break;  // all pinned
          default: t.w.add_bending(t.movable(), t.movable(), t.movable(), t.movable(), set, rest); break;
        }
      }
      t.expect_colored_is_serial(testing::Message() << count << " constraints, " << (with_xpbd ? "with" : "without")
                                                   << " XPBD, " << (one_set ? "one set" : "three sets"));
    }
  }
}

// Area constraints that share no movable particle give the same result in any order, so the serial reference
// (scalar projection, insertion order) and the colored solver (with AVX2: eight float or four double lanes on padded
// positions, kernels_avx2.hpp) must agree bit for bit. The triangles cover what the lanes mask: collinear and
// coincident corners, pinned corners shared between constraints, all corners pinned, mixed sets with and without
// XPBD, and counts that leave a scalar remainder.
TYPED_TEST(SolverTest, AreaKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (bool with_xpbd : {true, false})
    for (int count : {1, 3, 4, 5, 8, 9, 13, 17, 61, 250}) {
      KernelCase<Real> t(unsigned(count) + 11u, with_xpbd);
      for (int k = 0; k < count; ++k) {
        const Index set = t.any_set();
        const Real rest = Real(0.05 + 0.8 * std::abs(t.uniform()));
        const Vec3<Real> a = t.random_point(), b = t.random_point();
        switch (k % 6) {
          case 0: t.w.add_area(t.at(a), t.at(b), t.at(a + Real(0.4) * (b - a)), set, rest); break;  // collinear
          case 1: t.w.add_area(t.at(a), t.at(a), t.movable(), set, rest); break;                      // coincident corners
          case 2: t.w.add_area(t.pin[0], t.pin[1], t.movable(), set, rest); break;                    // shared pinned edge
          case 3: t.w.add_area(t.pin[0], t.pin[1], t.pin[2], set, rest); break;                       // all pinned
          default: t.w.add_area(t.movable(), t.movable(), t.movable(), set, rest); break;
        }
      }
      t.expect_colored_is_serial(testing::Message() << count << " constraints, " << (with_xpbd ? "with" : "without")
                                                   << " XPBD");
    }
}

// Tet volume constraints that share no movable particle, likewise (tet_volume_math.hpp in eight float or four double
// lanes): tets inverted and upright against rest volumes of either size, collapsed onto a line (no gradient: with
// α̃ = 0 nothing moves) and onto one point, a pinned edge shared between tets, all four corners pinned, mixed sets
// with and without XPBD, and counts that leave a scalar remainder.
TYPED_TEST(SolverTest, TetVolumeKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (bool with_xpbd : {true, false})
    for (int count : {1, 3, 4, 5, 8, 9, 13, 17, 61, 250}) {
      KernelCase<Real> t(unsigned(count) + 31u, with_xpbd);
      for (int k = 0; k < count; ++k) {
        TetVolumeConstraint<Real> c = blank_constraint<TetVolumeConstraint<Real>>();
        c.set = t.any_set();
        c.rest = Real(0.01 + 0.2 * std::abs(t.uniform()));
        const Vec3<Real> a = t.random_point(), b = t.random_point();
        switch (k % 6) {
          case 0: c.particles = {t.at(a), t.at(b), t.at(a + Real(0.3) * (b - a)), t.at(a + Real(0.6) * (b - a))}; break;
          case 1: c.particles = {t.at(a), t.at(a), t.at(a), t.at(a)}; break;        // one point
          case 2: c.particles = {t.pin[0], t.pin[1], t.movable(), t.movable()}; break;  // shared pinned edge
          case 3: c.particles = {t.pin[0], t.pin[1], t.pin[2], t.pin[3]}; break;    // all pinned
          default: c.particles = {t.movable(), t.movable(), t.movable(), t.movable()}; break;
        }
        t.w.add(c);  // its rest volume given
      }
      t.expect_colored_is_serial(testing::Message() << count << " constraints, " << (with_xpbd ? "with" : "without")
                                                   << " XPBD");
    }
}

// Shape-matching clusters that share no movable particle, likewise (shape_match_math.hpp in eight float or four
// double lanes, the SVD lane by lane where Newton's iteration does not apply): clusters deformed from random rest
// shapes in the rigid and the linear mode, mirrored (det A_pq < 0), flat (coplanar), collapsed onto one point
// (A_pq = 0), with pinned particles shared between clusters, all eight pinned, mixed sets with and without XPBD,
// and counts that leave a remainder of every length.
TYPED_TEST(SolverTest, ShapeMatchKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (bool with_xpbd : {true, false})
    for (int count : {1, 2, 3, 5, 8, 9, 13, 17, 61}) {
      KernelCase<Real> t(unsigned(count) + 47u, with_xpbd);
      for (int k = 0; k < count; ++k) {
        ShapeMatchConstraint<Real> c = blank_constraint<ShapeMatchConstraint<Real>>();
        c.set = t.any_set();
        c.beta = k % 3 == 1 ? Real(0.4) : Real(0);
        constexpr auto members = ShapeMatchConstraint<Real>::offsets();
        for (int i = 0; i < 8; ++i) c.*members[i] = t.random_point();
        const Vec3<Real> centre = t.random_point();
        for (int i = 0; i < 8; ++i) {
          Vec3<Real> x = centre + Real(0.8) * (c.*members[i]) + Real(0.2) * t.random_point();
          if (k % 7 == 2) x.x() = -x.x();         // mirrored
          if (k % 7 == 3) x.z() = centre.z();     // flat
          if (k % 7 == 4) x = centre;             // collapsed
          c.particles[i] = k % 11 == 6 ? t.w.add_particle(x, World<Real>::kPinned) : t.at(x);  // all pinned
        }
        if (k % 5 == 3) c.particles[0] = t.pin[0], c.particles[1] = t.pin[1];  // shared pins
        t.w.add(c);
      }
      t.expect_colored_is_serial(testing::Message() << count << " clusters, " << (with_xpbd ? "with" : "without")
                                                   << " XPBD");
    }
}

// Neo-Hookean tets that share no movable particle, likewise: the colored solver (with AVX2: eight float or four
// double lanes on padded positions, neo_hookean_math.hpp) must give the serial reference's bits. The tets cover what
// the lanes mask or mix in one block: PBD sets (α̃ = 0: the tet does not move) beside XPBD sets of two compliances,
// corners made coincident (F = 0), flat or inverted after their rest values were measured, pinned corners shared
// between tets, all four corners pinned (nothing moves; λ moves where μ/λ > 0, and the system is singular where it is
// 0), ratios μ/λ from 0 to 1, and counts that leave a remainder (one tet: scalar; more: in masked lanes), which must
// find the tet's two λ (2i, 2i + 1).
TYPED_TEST(SolverTest, NeoHookeanKernelMatchesTheScalarProjectionBitForBit) {
  using Real = TypeParam;
  for (int count : {1, 3, 4, 5, 8, 9, 13, 17, 61, 250}) {
    KernelCase<Real> t(unsigned(count) + 23u, true);
    const Index xpbd[2] = {t.w.add_constraint_set(Stiffness::xpbd_compliance(1e-6)),
                           t.w.add_constraint_set(Stiffness::xpbd_compliance(1e-4))};
    std::array<Index, 4> pinned;  // a pinned tet whose corners all-pinned tets share
    for (int i = 0; i < 4; ++i)
      pinned[i] = t.w.add_particle(Vec3<Real>(Real(i == 1), Real(i == 2), Real(1 + (i == 3))), World<Real>::kPinned);
    std::vector<std::pair<int, std::array<Index, 4>>> reshape;  // tets deformed once their rest values are measured
    for (int k = 0; k < count; ++k) {
      NeoHookeanConstraint<Real> c = blank_constraint<NeoHookeanConstraint<Real>>();
      c.set = k % 5 == 4 ? t.any_set() : xpbd[k % 2];
      c.ratio = Real(std::array{0.0, 0.02, 0.3, 1.0}[k % 4]);
      auto& q = c.particles;
      q = {t.movable(), t.movable(), t.movable(), t.movable()};
      if (k % 7 == 3) q[0] = t.pin[0], q[1] = t.pin[1];  // a pinned edge, shared
      if (k % 7 == 4) q = pinned;                        // all pinned
      const auto x = t.w.positions();  // a view, taken once the particles are added
      const Vec3<Real> e1 = x.col(q[1]) - x.col(q[0]), e2 = x.col(q[2]) - x.col(q[0]), e3 = x.col(q[3]) - x.col(q[0]);
      if (e1.cross(e2).dot(e3) < 0) std::swap(q[2], q[3]);  // positively oriented where it starts
      t.w.add(c, required_fields<NeoHookeanConstraint<Real>>());
      if (k % 7 <= 2) reshape.emplace_back(k % 7, q);
    }
    auto x = t.w.positions();
    for (const auto& [how, q] : reshape) {
      if (how == 0) {  // coincident corners: F = 0
        for (int i = 1; i < 4; ++i) x.col(q[i]) = x.col(q[0]);
      } else if (how == 1) {  // flat
        x.col(q[3]) = x.col(q[0]) + Real(0.3) * (x.col(q[1]) - x.col(q[0])) + Real(0.5) * (x.col(q[2]) - x.col(q[0]));
      } else {  // inverted
        x.col(q[2]).swap(x.col(q[3]));
      }
    }
    t.expect_colored_is_serial(testing::Message() << count << " constraints");
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

// Small blocks (64 constraints each) so that even the test scenes have many blocks and a boundary.
template <class Real> World<Real> with_small_blocks(World<Real> w) {
  w.set_blocking({64, true});
  return w;
}

TYPED_TEST(SolverTest, BlockIsBitwiseIdenticalForAnyThreadCountAndToItsOneThreadRun) {
  using Real = TypeParam;
  const std::vector<std::pair<const char*, World<Real>>> scenes = {
      {"cloth", cloth_world<Real>(16)}, {"rope", rope_world<Real>()}, {"random 1", random_world<Real>(1)},
      {"random 2", random_world<Real>(2)}, {"meshes", mesh_world<Real>()}};
  for (const auto& [name, world] : scenes)
    for (SweepOrder order : {SweepOrder::forward, SweepOrder::symmetric}) {
      const World<Real> blocked = with_small_blocks(world);
      const auto reference = run(blocked, Solver::block, 1, 30, order);  // one thread: the blocks one after the other
      for (Real v : reference) ASSERT_TRUE(std::isfinite(v)) << name;
      for (int threads : {2, 3, 4})
        EXPECT_TRUE(bitwise_equal(reference, run(blocked, Solver::block, threads, 30, order)))
            << name << ", " << threads << " threads, " << pbd::name(order);
      // The blocks change the order, so the result: not the colored one's (a check that the blocks are used).
      EXPECT_FALSE(bitwise_equal(reference, run(world, Solver::serial_colored, 1, 30, order))) << name;
    }
}

// With one block holding everything, the block schedule is the insertion order: the serial reference's bits (the
// boundary is empty; volumes and contacts run after the constraints under both).
TYPED_TEST(SolverTest, OneBlockIsTheSerialReference) {
  using Real = TypeParam;
  for (World<Real> w : {cloth_world<Real>(12), rope_world<Real>(), mesh_world<Real>()}) {
    w.set_blocking({1u << 30, true});
    EXPECT_TRUE(bitwise_equal(run(w, Solver::serial, 1, 20), run(w, Solver::block, 2, 20)));
  }
}

TEST(BlockLayout, InteriorsAreDisjointTheBoundaryColoredAndTheMapExact) {
  for (bool metis : {true, false}) {
    World<double> w = cloth_world<double>(24);
    const World<double> uncolored = w;
    w.set_blocking({100, metis});
    StepParams<double> p = w.params();
    p.solver = Solver::block;
    w.set_params(p);
    w.step();
    const Index blocks = w.num_blocks();
    EXPECT_GE(blocks, 10u);  // 1633 constraints, 100 a block
    const auto c = w.colors<StretchConstraint<double>>();
    ASSERT_GT(c.num_colors, blocks);  // the blocks' interiors, then the boundary colors
    const auto inv_mass = w.inverse_masses();
    std::vector<Index> owner(w.num_particles(), ~Index(0));
    std::size_t interior = 0;
    for (Index g = 0; g < c.num_colors; ++g) {
      std::set<Index> in_color;
      for (Index i = c.offsets[g]; i < c.offsets[g + 1]; ++i)
        for (Index q : c.items[i].particles) {
          if (inv_mass[q] == 0) continue;
          if (g < blocks) {
            EXPECT_TRUE(owner[q] == ~Index(0) || owner[q] == g) << "particle " << q << " in blocks " << owner[q] << ", " << g;
            owner[q] = g;
          } else {
            EXPECT_TRUE(in_color.insert(q).second) << "particle " << q << " twice in boundary color " << g;
          }
        }
      if (g < blocks) interior += c.offsets[g + 1] - c.offsets[g];
    }
    EXPECT_GT(interior, c.items.size() / 2) << "most constraints should be inside a block";
    // Within a block, insertion order.
    for (Index g = 0; g < blocks; ++g)
      for (Index i = c.offsets[g] + 1; i < c.offsets[g + 1]; ++i) {
        Index prev = 0, cur = 0;
        for (Index u = 0; u < c.stored.size(); ++u) {
          if (c.stored[u] == i - 1) prev = u;
          if (c.stored[u] == i) cur = u;
        }
        EXPECT_LT(prev, cur) << "block " << g;
      }
    for (std::size_t i = 0; i < test::stretch_of(w).size(); ++i)
      EXPECT_EQ(test::stretch_of(w)[i].particles, test::stretch_of(uncolored)[i].particles) << i;
    EXPECT_NO_THROW(w.validate());
  }
}

// Adding constraints lays out only the stores that changed, on the same blocks (only their boundary is colored);
// removing keeps every group. Each result stays proper, and 1 and 4 threads agree bit for bit throughout.
TEST(BlockLayout, AddingAndRemovingConstraintsKeepsThePartitionAndStaysDeterministic) {
  auto scenario = [](int threads) {
    World<double> w = with_small_blocks(cloth_world<double>(16));
    StepParams<double> p = w.params();
    p.solver = Solver::block;
    p.iterations = 4;
    w.set_params(p);
    w.set_parallel_config(kAlwaysFork);
    tbb::task_arena arena(threads);
    std::vector<double> out;
    Index blocks = 0;
    arena.execute([&] {
      w.step();
      blocks = w.num_blocks();
      const Index set = 0;
      w.add_stretch(17, 18 + 16, set);  // a diagonal: inside a block or across two
      w.add_stretch(0, 255, set);       // across the cloth: a boundary constraint
      w.add_anchor(100, set);           // a new type, one particle: inside its block
      w.step();
      EXPECT_EQ(w.num_blocks(), blocks) << "adding a few constraints must not partition anew";
      EXPECT_NO_THROW(w.validate());
      w.remove_stretch(std::vector<Index>{3, 40, 41});
      w.step();
      EXPECT_EQ(w.num_blocks(), blocks);
      EXPECT_NO_THROW(w.validate());
      out.assign(w.positions().data(), w.positions().data() + w.positions().size());
    });
    EXPECT_GT(blocks, 4u);
    return out;
  };
  EXPECT_TRUE(bitwise_equal(scenario(1), scenario(4)));
}

// A type with colored interiors (Neo-Hookean): lay_out_blocks colors each block's interior into runs that tile it,
// and Store::validate rejects runs that share a movable particle or stop covering a block.
TEST(BlockLayout, ColoredInteriorRunsTileEachBlockAndAreChecked) {
  using C = NeoHookeanConstraint<double>;
  detail::Store<C> s;
  // Two strips of tets, particles 0..9 in block 0 and 10..19 in block 1; consecutive tets share three corners.
  for (Index b : {0u, 10u})
    for (Index k = 0; k + 3 < 10; ++k) {
      C c = blank_constraint<C>();
      c.particles = {b + k, b + k + 1, b + k + 2, b + k + 3};
      s.append(c);
    }
  C across = blank_constraint<C>();
  across.particles = {8, 9, 10, 11};  // the boundary
  s.append(across);
  const std::vector<std::uint8_t> fixed(20, 0);
  std::vector<std::uint32_t> block(20, 0);
  for (Index p = 10; p < 20; ++p) block[p] = 1;
  detail::lay_out_blocks(s, fixed, block, 2, coloring::Options{});
  ASSERT_EQ(s.block_runs.size(), 3u);
  EXPECT_EQ(s.block_runs[1] - s.block_runs[0], 4u);  // 7 tets in a strip, each sharing a corner with the next 3
  EXPECT_EQ(s.block_runs[2] - s.block_runs[1], 4u);
  EXPECT_EQ(s.runs.back(), s.offsets[2]);
  EXPECT_NO_THROW(s.validate(fixed, C::kName));
  detail::Store<C> merged = s;  // two runs of block 0 as one: neighbours in one run
  merged.runs.erase(merged.runs.begin() + 1);
  for (Index& r : merged.block_runs) r -= r > 0 ? 1 : 0;
  EXPECT_THROW(merged.validate(fixed, C::kName), Error);
  detail::Store<C> short_runs = s;  // block 1's runs end before its interior does
  short_runs.runs.back() -= 1;
  EXPECT_THROW(short_runs.validate(fixed, C::kName), Error);
}

TEST(BlockLayout, SwitchingBetweenColoredAndBlockLaysOutAgain) {
  World<double> w = with_small_blocks(cloth_world<double>(12));
  StepParams<double> p = w.params();
  for (Solver s : {Solver::block, Solver::colored, Solver::block, Solver::jacobi, Solver::serial, Solver::block}) {
    p.solver = s;
    w.set_params(p);
    w.step();
    EXPECT_EQ(w.num_blocks() > 0, s == Solver::block) << name(s);
    EXPECT_NO_THROW(w.validate()) << name(s);
  }
  EXPECT_THROW(w.set_blocking({0, true}), Error);
}

// Chebyshev acceleration (Wang 2015) on a perturbed cloth without gravity, one sub-step of many sweeps: the RMS
// stretch it reaches, with ρ as given (0: this step estimates it, sweeping plain, and reports it in StepStats).
template <class Real> World<Real> perturbed_cloth(Solver s, int iterations, bool accelerate, Real rho) {
  World<Real> w = with_small_blocks(cloth_world<Real>(24));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  auto x = w.positions();
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    if (w.inverse_masses()[i] != 0) x.col(i) += Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng)));
  StepParams<Real> p = w.params();
  p.solver = s;
  p.iterations = iterations;
  p.gravity.setZero();
  p.chebyshev.enabled = accelerate;
  p.chebyshev.rho = rho;
  w.set_params(p);
  return w;
}

TEST(Chebyshev, TheEstimatedRhoCutsJacobisErrorAndAGuessTooLargeFallsBack) {
  World<double> plain = perturbed_cloth<double>(Solver::jacobi, 60, false, 0.0);
  plain.step();
  // The estimate: a first step sweeps plain (the same bits as without acceleration) and measures ρ.
  World<double> estimating = perturbed_cloth<double>(Solver::jacobi, 60, true, 0.0);
  estimating.step();
  EXPECT_EQ(stretch_violation(estimating).rms, stretch_violation(plain).rms);
  const double rho = estimating.last_step_stats().chebyshev_rho;
  EXPECT_EQ(estimating.params().chebyshev.rho, 0.0);  // the measure is an output: the parameters stay as set
  EXPECT_GT(rho, 0.9);
  EXPECT_LT(rho, 0.999);
  World<double> fast = perturbed_cloth<double>(Solver::jacobi, 60, true, rho);
  fast.step();
  std::printf("CHEBYSHEV jacobi 60 sweeps: rms stretch plain %.3e accelerated %.3e (rho %.4f)\n",
              stretch_violation(plain).rms, stretch_violation(fast).rms, rho);
  EXPECT_EQ(fast.last_step_stats().chebyshev_fallbacks, 0);
  EXPECT_LT(stretch_violation(fast).rms, stretch_violation(plain).rms / 2.5);  // measured: 3.4x lower
  for (Solver s : {Solver::colored, Solver::block}) {
    World<double> gs = perturbed_cloth<double>(s, 60, true, 0.9999);
    gs.step();
    std::printf("CHEBYSHEV %s rho 0.9999: rms stretch %.3e fallbacks %d\n", std::string(name(s)).c_str(),
                stretch_violation(gs).rms, gs.last_step_stats().chebyshev_fallbacks);
    EXPECT_EQ(gs.last_step_stats().chebyshev_fallbacks, 1) << name(s);
    EXPECT_TRUE(gs.positions().allFinite()) << name(s);
  }
}

TYPED_TEST(SolverTest, ChebyshevIsBitwiseIdenticalForAnyThreadCount) {
  using Real = TypeParam;
  for (Solver s : {Solver::jacobi, Solver::colored, Solver::block}) {
    World<Real> world = with_small_blocks(mesh_world<Real>());  // compliant sets: λ is extrapolated too
    StepParams<Real> p = world.params();
    p.chebyshev.enabled = true;
    p.chebyshev.delay = 3;
    world.set_params(p);
    const auto reference = run(world, s, 1, 20);
    for (Real v : reference) ASSERT_TRUE(std::isfinite(v)) << name(s);
    for (int threads : {2, 4}) EXPECT_TRUE(bitwise_equal(reference, run(world, s, threads, 20))) << name(s) << threads;
  }
}

TEST(Chebyshev, BadParametersAreRejected) {
  World<double> w;
  StepParams<double> p;
  p.chebyshev.enabled = true;
  p.solver = Solver::serial;
  EXPECT_THROW(w.set_params(p), Error);
  p.solver = Solver::jacobi;
  EXPECT_NO_THROW(w.set_params(p));
  for (double rho : {-0.1, 1.0, std::nan("")}) {
    p.chebyshev.rho = rho;
    EXPECT_THROW(w.set_params(p), Error) << rho;
  }
  p.chebyshev.rho = 0;
  p.iterations = 3;  // an estimate needs the rate over the second half of at least 4 sweeps
  EXPECT_THROW(w.set_params(p), Error);
  p.iterations = 10;
  p.chebyshev.delay = 0;
  EXPECT_THROW(w.set_params(p), Error);
  p.chebyshev.rho = 0.9;
  p.chebyshev.delay = 1;
  EXPECT_NO_THROW(w.set_params(p));
  p.chebyshev.diverge = 1;
  EXPECT_THROW(w.set_params(p), Error);
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
  for (Solver s : kSolvers) {
    const double few = rope_stretch_after<Real>(s, 5), many = rope_stretch_after<Real>(s, 100);
    EXPECT_LT(many, few / 4) << name(s);
    EXPECT_LT(many, 0.01) << name(s);
  }
}

TYPED_TEST(SolverTest, ContactsHoldUnderGaussSeidelAndStayBoundedUnderJacobi) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
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
  for (Solver s : kSolvers) EXPECT_EQ(parse_solver(name(s)), s);
  EXPECT_FALSE(parse_solver("gauss").has_value());
}

}  // namespace
}  // namespace pbd
