// Surfaces that tear along broken fibers (World::add_surface, engine/src/tear.hpp): a cloth of fibers pulled apart
// separates into two pieces whose particles along the cut were copied; mass and momentum are kept; the same bits on
// 1-4 threads under every parallel solver; validate() holds after each tear.
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "pieces.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <numeric>
#include <set>
#include <vector>

namespace pbd {
namespace {

using W = World<double>;

// An n x n cloth of spacing d in the x-y plane, fibers on every triangle edge (k = 50 N, rupture at 10%), bending
// on every interior edge, a tearing surface of its triangles. Columns 0 and n - 1 pinned when `pinned`.
struct TearCloth {
  static constexpr Index n = 10;
  static constexpr double d = 0.01;
  W w;
  std::vector<std::array<Index, 3>> triangles;
  TearCloth(Solver solver, bool pinned) {
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i)
        w.add_particle(W::Vec(d * double(i), d * double(j), 0), pinned && (i == 0 || i == n - 1) ? W::kPinned : 1e-3,
                       W::Vec(pinned ? 0.0 : (i < n / 2 ? -6.0 : 6.0), 0.05, 0.0));
    Material m;
    m.stiffness = 50.0;
    m.rupture_strain = 0.1;
    const Index fibers = w.add_constraint_set(Stiffness::fiber(m));
    const Index bending = w.add_constraint_set(Stiffness::xpbd_compliance(10.0));
    auto id = [](Index i, Index j) { return j * n + i; };
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) {
        triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        if (i + 1 < n) w.add_fiber(id(i, j), id(i + 1, j), fibers);
        if (j + 1 < n) w.add_fiber(id(i, j), id(i, j + 1), fibers);
        if (i + 1 < n && j + 1 < n) w.add_fiber(id(i, j), id(i + 1, j + 1), fibers);
      }
    for (Index j = 0; j + 1 < n; ++j)  // bending across each diagonal
      for (Index i = 0; i + 1 < n; ++i) w.add_bending(id(i, j), id(i + 1, j + 1), id(i + 1, j), id(i, j + 1), bending);
    w.add_surface(triangles);
    w.set_params(test::weightless<double>(solver, 4, 4));
  }
  void step(bool pull) {
    if (pull)
      for (Index j = 0; j < n; ++j) w.positions()(0, j * n + n - 1) += 2e-4;  // the right edge away, 0.2 mm a step
    w.step();
  }
};

using test::pieces;

TEST(Tear, APulledClothSeparatesAlongItsBrokenFibersUnderEverySolver) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    TearCloth c(solver, true);
    std::size_t copies = 0;
    for (int step = 0; step < 400 && pieces(c.w.surface(0), c.w.num_particles()) < 2; ++step) {
      c.step(true);
      for (const TornParticle& t : c.w.last_copies()) {
        EXPECT_EQ(c.w.positions().col(t.particle), c.w.positions().col(t.from));
        ++copies;
      }
      c.w.validate();
    }
    EXPECT_GE(pieces(c.w.surface(0), c.w.num_particles()), 2u);
    EXPECT_GE(copies, std::size_t(TearCloth::n - 2));  // the cut crosses the cloth: a copy of each inner particle on it
    EXPECT_EQ(c.w.num_particles(), Index(TearCloth::n * TearCloth::n + copies));
    for (int step = 0; step < 50; ++step) c.step(true);  // the pieces part: their gap grows
    c.w.validate();
  }
}

// A free cloth whose halves fly apart tears: its mass and momentum stay what they were, to rounding.
TEST(Tear, AFreeClothKeepsItsMassAndMomentumAcrossATear) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    TearCloth c(solver, false);
    auto mass = [&] {
      double m = 0;
      for (Index i = 0; i < c.w.num_particles(); ++i) m += 1.0 / c.w.inverse_masses()[i];
      return m;
    };
    const double m0 = mass();
    const auto [p0, l0] = test::momenta(c.w);
    std::size_t copies = 0;
    for (int step = 0; step < 100; ++step) {
      c.step(false);
      copies += c.w.last_copies().size();
      const auto [p1, l1] = test::momenta(c.w);
      ASSERT_NEAR(mass(), m0, 1e-15 * m0 * 10) << "step " << step;
      ASSERT_LT((p1 - p0).norm(), 1e-14) << "step " << step;
    }
    EXPECT_GT(copies, 0u);
    EXPECT_GE(pieces(c.w.surface(0), c.w.num_particles()), 2u);
  }
}

// A torn world described and built again (describe_world: the surfaces as they are, with their cut edges) steps on
// as the original does, tears included, bit for bit: under the serial solver, whose order is the insertion order
// the description keeps (a colored solver's bits follow its colors, which a rebuilt world makes afresh).
TEST(Tear, ATornWorldRebuiltFromItsDescriptionTearsOnAlike) {
  TearCloth c(Solver::serial, true);
  int step = 0;
  for (; step < 400 && c.w.num_particles() == TearCloth::n * TearCloth::n; ++step) c.step(true);
  ASSERT_GT(c.w.num_particles(), TearCloth::n * TearCloth::n);
  W copy = build_world<double>(describe_world(c.w));
  EXPECT_EQ(copy.num_particles(), c.w.num_particles());
  ASSERT_EQ(copy.num_surfaces(), 1u);
  EXPECT_TRUE(std::ranges::equal(copy.surface(0), c.w.surface(0)));
  EXPECT_TRUE(std::ranges::equal(copy.surface_cut(0), c.w.surface_cut(0)));
  for (int k = 0; k < 100; ++k) {
    for (W* w : {&c.w, &copy}) {
      for (Index j = 0; j < TearCloth::n; ++j) w->positions()(0, j * TearCloth::n + TearCloth::n - 1) += 2e-4;
      w->step();
    }
  }
  EXPECT_EQ(copy.num_particles(), c.w.num_particles());
  EXPECT_EQ(position_hash(copy), position_hash(c.w));
}

// A pinned particle moves at its own velocity whatever acts on it (the scenes' grips): gravity, a fiber pulling it.
TEST(Tear, APinnedParticleMovesAtItsVelocityWhateverActsOnIt) {
  for (Solver solver : kSolvers) {
    W w;
    w.add_particle(W::Vec(0, 0, 0), W::kPinned, W::Vec(0.5, -0.25, 0.125));
    w.add_particle(W::Vec(0.01, 0, 0), 1e-3);
    w.add_fiber(0, 1, w.add_constraint_set(Stiffness::fiber([] { Material m; m.stiffness = 100; return m; }())));
    StepParams<double> p;
    p.dt = 1e-3;
    p.solver = solver;
    w.set_params(p);
    for (int step = 0; step < 100; ++step) w.step();
    EXPECT_NEAR(w.positions()(0, 0), 0.05, 1e-14) << name(solver);
    EXPECT_NEAR(w.positions()(1, 0), -0.025, 1e-14) << name(solver);
    EXPECT_NEAR(w.positions()(2, 0), 0.0125, 1e-14) << name(solver);
    EXPECT_EQ(w.velocities().col(0), W::Vec(0.5, -0.25, 0.125)) << name(solver);
    EXPECT_GT(w.fibers()[0].force, 0.0) << name(solver);  // the fiber pulls it, in vain
  }
}

TEST(Tear, ATearGivesTheSameBitsOnOneToFourThreads) {
  for (Solver solver : {Solver::serial_colored, Solver::colored, Solver::jacobi, Solver::block}) {
    SCOPED_TRACE(name(solver));
    std::vector<std::uint64_t> hashes;
    std::vector<Index> counts;
    for (int threads = 1; threads <= 4; ++threads) {
      tbb::task_arena arena(threads);
      TearCloth c(solver, true);
      arena.execute([&] {
        for (int step = 0; step < 250; ++step) c.step(true);
      });
      c.w.validate();
      hashes.push_back(position_hash(c.w));
      counts.push_back(c.w.num_particles());
    }
    EXPECT_GT(counts[0], TearCloth::n * TearCloth::n);
    for (int i = 1; i < 4; ++i) {
      EXPECT_EQ(hashes[i], hashes[0]) << i + 1 << " threads";
      EXPECT_EQ(counts[i], counts[0]) << i + 1 << " threads";
    }
  }
}

}  // namespace
}  // namespace pbd
