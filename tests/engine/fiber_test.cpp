// Fibers (constraints/fiber.hpp) with a stress–strain curve (material.hpp) against closed forms, under every solver:
// a quasi-static tension test follows the curve through toe, linear part and yield and breaks at the rupture strain;
// unloaded after yield it goes back along the linear slope to the plastic strain; the grips' work is the elastic
// energy plus the plastic dissipation; a tear gives the same bits on 1–4 threads, several fibers breaking in one
// step; and a free body keeps its momentum across a tear.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "tension_points.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cmath>
#include <vector>

namespace pbd {
namespace {

using W = World<double>;

// A ligament-like curve: k = 1000 N per unit strain, toe to 3%, yield at 8% with hardening 200 N, rupture at 14%.
Material ligament() {
  Material m;
  m.stiffness = 1000.0;
  m.toe_strain = 0.03;
  m.yield_strain = 0.08;
  m.hardening = 200.0;
  m.rupture_strain = 0.14;
  return m;
}

// A tension test: n fibers of rest length L0 in a row along x between a fixed grip (particle 0) and a moving one
// (particle n), the particles between them free, no gravity.
struct Tension {
  static constexpr Index kFibers = 4;
  static constexpr double kRest = 0.01;  // m per fiber
  W w;
  explicit Tension(Solver solver, const Material& m = ligament()) {
    for (Index i = 0; i <= kFibers; ++i)
      w.add_particle(W::Vec(kRest * double(i), 0, 0), i == 0 || i == kFibers ? W::kPinned : 1e-3);
    const Index set = w.add_constraint_set(Stiffness::fiber(m));
    for (Index i = 0; i < kFibers; ++i) w.add_fiber(i, i + 1, set);
    w.set_params(test::weightless<double>(solver, 10, solver == Solver::jacobi ? 40 : 10));
  }
  double grip() const { return w.positions()(0, kFibers); }
  // The chain's total strain: the grips' distance over the rest length.
  double strain() const { return grip() / (kRest * kFibers) - 1.0; }
  // Moves the moving grip to total strain s, then steps.
  void step_to(double s) {
    w.positions()(0, kFibers) = kRest * kFibers * (1.0 + s);
    w.step();
  }
  double force() const { return w.fibers().back().force; }  // the fiber at the moving grip
};

// Strain per step: 1e-4 (a pull at 0.1 strain per second, slow against the chain's period of about 1 ms).
constexpr double kRate = 1e-4;

TEST(Fiber, TensionTestFollowsTheCurveAndBreaksAtTheRuptureStrainUnderEverySolver) {
  const Material m = ligament();
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Tension t(solver);
    const std::vector<double> points = test::tension_points(m);
    std::size_t next = 0;
    double broke_at = -1.0;
    for (int step = 1; step < 2000 && broke_at < 0; ++step) {
      t.step_to(kRate * step);
      const double s = t.w.fibers().empty() ? 0.0 : t.strain();
      if (!t.w.last_breaks().empty()) {
        broke_at = t.w.last_breaks().front().strain;
        EXPECT_NEAR(t.w.last_breaks().front().force, m.loading_force(broke_at), 0.02 * m.loading_force(broke_at));
        break;
      }
      if (next < points.size() && s >= points[next]) {
        const double expected = m.loading_force(s);
        EXPECT_NEAR(t.force(), expected, 0.02 * expected) << "at strain " << s;
        ++next;
      }
    }
    EXPECT_EQ(next, points.size());
    EXPECT_NEAR(broke_at, m.rupture_strain, 0.01 * m.rupture_strain);
    t.w.validate();
  }
}

// A stiff cloth of fibers (h²·F′·Σw about 2000 per fiber) stretched uniformly: its bottom and top rows are grips
// pulled apart at a constant speed, and every particle starts at the speed of that stretch, so the vertical fibers'
// strain stays near the grips' strain. A projection that took one Newton step from a fiber gone slack released all
// its tension at once, overshooting by about that factor: with 64 sweeps such a cloth blew up (mean strains near
// 30 for a grips' strain of 0.04) under every solver but Jacobi.
TEST(Fiber, AStiffClothStretchedUniformlyStaysNearTheGripsStrainWithManySweepsUnderEverySolver) {
  constexpr int kN = 24;                      // particles per side
  constexpr double kSide = 0.1, kSpeed = 0.2;  // m, m/s (the grips' relative speed)
  const double spacing = kSide / (kN - 1);
  Material m;
  m.stiffness = 100.0;
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    W w;
    for (int i = 0; i < kN; ++i)
      for (int j = 0; j < kN; ++j) {
        const bool grip = i == 0 || i == kN - 1;
        const double y = spacing * i;
        w.add_particle(W::Vec(spacing * j, y, 0), grip ? W::kPinned : 2e-5, W::Vec(0, kSpeed * (y / kSide - 0.5), 0));
      }
    const Index set = w.add_constraint_set(Stiffness::fiber(m));
    auto at = [](int i, int j) { return Index(i * kN + j); };
    for (int i = 0; i < kN; ++i)
      for (int j = 0; j < kN; ++j) {
        if (j + 1 < kN) w.add_fiber(at(i, j), at(i, j + 1), set);
        if (i + 1 < kN) w.add_fiber(at(i, j), at(i + 1, j), set);
        if (i + 1 < kN && j + 1 < kN) w.add_fiber(at(i, j + 1), at(i + 1, j), set);
      }
    w.set_params(test::weightless<double>(solver, 1, 64));
    for (int step = 0; step < 20; ++step) w.step();
    const double grips = (w.positions()(1, at(kN - 1, 0)) - w.positions()(1, 0)) / kSide - 1.0;
    double mean = 0.0, largest = 0.0;
    int vertical = 0;
    const auto readings = w.fibers();
    const auto& fibers = w.constraints<FiberConstraint<double>>();
    for (std::size_t k = 0; k < fibers.size(); ++k) {
      if (fibers[k].particles[1] - fibers[k].particles[0] != kN) continue;
      mean += readings[k].strain;
      largest = std::max(largest, readings[k].strain);
      ++vertical;
    }
    mean /= vertical;
    // The vertical fibers' mean strain is the grips' (their columns are nearly straight). At 64 sweeps the colored
    // solvers still leave every other fiber of a column up to 3.5 times as stretched as the grips; a blown-up
    // solve is orders of magnitude past that.
    EXPECT_NEAR(mean, grips, 0.05 * grips);
    EXPECT_LT(largest, 5.0 * grips);
  }
}

// The pull of the tension test to ε_max past yield, then back at the same rate: the fiber leaves the linear part
// with the elastic slope k and goes slack at its plastic strain k·(ε_max − ε_y)/(k + H) (Material::plastic_after).
TEST(Fiber, UnloadedAfterYieldItGoesBackAlongTheLinearSlopeToItsPlasticStrain) {
  const Material m = ligament();
  const double top = 0.11;
  const double plastic = m.stiffness * (top - m.yield_strain) / (m.stiffness + m.hardening);
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Tension t(solver);
    const int up = int(std::lround(top / kRate));
    for (int step = 1; step <= up; ++step) t.step_to(kRate * step);
    // The chain's plastic strain, and each fiber's. Jacobi's sub-steps after each move of the grip stretch the
    // grip's fiber first (its corrections reach the others a sweep later), so that fiber yields a little more
    // (+2.1%, the others less): plastic flow keeps such a path. Its chain is checked whole.
    double mean = 0.0;
    for (const FiberReading& r : t.w.fibers()) {
      mean += r.plastic / double(Tension::kFibers);
      if (solver != Solver::jacobi) {
        EXPECT_NEAR(r.plastic, plastic, 0.02 * plastic);
      }
    }
    EXPECT_NEAR(mean, plastic, 0.02 * plastic);
    // Unloading: two readings on the linear part give its slope; the first step with no tension is the slack one.
    double slack = -1.0, f1 = 0.0, s1 = 0.0, f2 = 0.0, s2 = 0.0;
    for (int step = up - 1; step >= 0 && slack < 0; --step) {
      t.step_to(kRate * step);
      const double s = t.strain();
      if (step == up - 50) f1 = t.force(), s1 = s;
      if (step == up - 250) f2 = t.force(), s2 = s;
      if (t.force() <= 0.0) slack = s;
    }
    EXPECT_NEAR((f1 - f2) / (s1 - s2), m.stiffness, 0.02 * m.stiffness);
    EXPECT_NEAR(slack, plastic, 0.02 * plastic);
    EXPECT_TRUE(t.w.last_breaks().empty());
  }
}

// The grip's work (∫F dx, from λ) up to just before rupture is the fibers' elastic energy (L0·∫F de each), their
// plastic dissipation (L0·F·Δε_p summed over the steps) and the particles' kinetic energy.
TEST(Fiber, TheGripsWorkIsTheElasticEnergyPlusThePlasticDissipation) {
  const Material m = ligament();
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Tension t(solver);
    double work = 0.0, dissipated = 0.0, force = 0.0, grip = t.grip();
    std::vector<FiberReading> before = t.w.fibers();
    const int steps = int(std::lround(0.135 / kRate));
    for (int step = 1; step <= steps; ++step) {
      t.step_to(kRate * step);
      const std::vector<FiberReading> after = t.w.fibers();
      work += 0.5 * (force + t.force()) * (t.grip() - grip);
      force = t.force();
      grip = t.grip();
      for (std::size_t i = 0; i < after.size(); ++i)
        dissipated += Tension::kRest * after[i].force * (after[i].plastic - before[i].plastic);
      before = after;
    }
    double elastic = 0.0, kinetic = 0.0;
    for (const FiberReading& r : before) elastic += Tension::kRest * m.energy(r.strain - r.plastic);
    for (Index i = 1; i < Tension::kFibers; ++i) kinetic += 0.5 * 1e-3 * t.w.velocities().col(i).squaredNorm();
    EXPECT_GT(dissipated, 0.2 * work);  // well past yield: a good part of the work is dissipated
    EXPECT_NEAR(elastic + dissipated + kinetic, work, 0.02 * work);
  }
}

// A strip of fibers (a grid with diagonals) held along its top row and pulled down by its bottom row until it tears:
// the same bits and the same breaks on 1–4 threads, with steps in which several fibers break at once.
struct Strip {
  static constexpr Index kCols = 12, kRows = 8;
  W w;
  Index bottom = 0;
  Strip(Solver solver) {
    const double d = 0.01;
    for (Index r = 0; r < kRows; ++r)
      for (Index c = 0; c < kCols; ++c)
        w.add_particle(W::Vec(d * double(c), -d * double(r), 0), r == 0 || r == kRows - 1 ? W::kPinned : 1e-3);
    bottom = (kRows - 1) * kCols;
    Material m = ligament();
    const Index set = w.add_constraint_set(Stiffness::fiber(m));
    auto at = [](Index r, Index c) { return r * kCols + c; };
    for (Index r = 0; r < kRows; ++r)
      for (Index c = 0; c < kCols; ++c) {
        if (c + 1 < kCols && r > 0 && r + 1 < kRows) w.add_fiber(at(r, c), at(r, c + 1), set);
        if (r + 1 < kRows) w.add_fiber(at(r, c), at(r + 1, c), set);
        if (r + 1 < kRows && c + 1 < kCols) w.add_fiber(at(r, c), at(r + 1, c + 1), set);
      }
    w.set_params(test::weightless<double>(solver, 4, 4));
  }
  void step() {  // the bottom row down by 0.2 mm a step
    for (Index c = 0; c < kCols; ++c) w.positions()(1, bottom + c) -= 2e-4;
    w.step();
  }
};

TEST(Fiber, ATearGivesTheSameBitsAndBreaksOnOneToFourThreads) {
  for (Solver solver : {Solver::serial_colored, Solver::colored, Solver::jacobi, Solver::block}) {
    SCOPED_TRACE(name(solver));
    std::vector<std::uint64_t> hashes;
    std::vector<std::vector<std::int64_t>> logs;
    std::size_t most = 0;
    for (int threads = 1; threads <= 4; ++threads) {
      tbb::task_arena arena(threads);
      Strip s(solver);
      std::vector<std::int64_t> log;
      arena.execute([&] {
        for (int i = 0; i < 500; ++i) {
          s.step();
          for (const FiberBreak& b : s.w.last_breaks()) log.insert(log.end(), {b.step, std::int64_t(b.fiber)});
          most = std::max(most, s.w.last_breaks().size());
        }
      });
      s.w.validate();
      hashes.push_back(position_hash(s.w));
      logs.push_back(log);
    }
    EXPECT_GT(logs[0].size(), 2u * Strip::kCols);  // torn across: more fibers broke than a row has
    EXPECT_GE(most, 2u);                           // several in one step
    for (int i = 1; i < 4; ++i) {
      EXPECT_EQ(hashes[i], hashes[0]) << i + 1 << " threads";
      EXPECT_EQ(logs[i], logs[0]) << i + 1 << " threads";
    }
  }
}

// A free chain of fibers flying apart (no pin, no gravity) tears; its momentum and angular momentum stay what they
// were, step by step, to rounding.
TEST(Fiber, AFreeBodyKeepsItsMomentaAcrossATear) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    W w;
    const Index n = 6;
    for (Index i = 0; i < n; ++i)
      w.add_particle(W::Vec(0.01 * double(i), 0.002 * double(i % 2), 0), 1e-3 * double(1 + i % 3),
                     W::Vec(5.0 * (double(i) - 2.5) + 0.3, 0.1, -0.2 * double(i % 2)));
    const Index set = w.add_constraint_set(Stiffness::fiber(ligament()));
    for (Index i = 0; i + 1 < n; ++i) w.add_fiber(i, i + 1, set);
    w.set_params(test::weightless<double>(solver, 4, 4));
    const auto [p0, l0] = test::momenta(w);
    const double scale = 1e-3 * 3 * 15.0 * double(n);  // Σ m|v| bounds the sums' rounding
    std::size_t broken = 0;
    for (int step = 0; step < 300; ++step) {
      w.step();
      broken += w.last_breaks().size();
      const auto [p1, l1] = test::momenta(w);
      ASSERT_LT((p1 - p0).norm(), 1e-13 * scale) << "step " << step;
      // Jacobi's angular momentum is not checked: on the pieces this chain tears into it drifts by 1e-7 of a
      // momentum scale of 5e-5 even when they are built that way, with no break and plain compliance (its
      // simultaneous projections are not central about the final positions, and the free bodies' despin does not
      // reach them); the Gauss-Seidel solvers keep it to rounding.
      if (solver != Solver::jacobi) {
        ASSERT_LT((l1 - l0).norm(), 1e-13 * scale) << "step " << step;
      }
    }
    EXPECT_GE(broken, 1u);
  }
}

// The plastic strain is kept with the fibers: a world described after yielding (describe_world) is rebuilt with the
// rest lengths they have grown to, and steps on from there as the original does, bit for bit.
TEST(Fiber, AWorldRebuiltFromItsDescriptionKeepsThePlasticStrains) {
  Tension t(Solver::serial);
  for (int step = 1; step <= 1000; ++step) t.step_to(kRate * step);  // past yield: 10% against 8%
  W copy = build_world<double>(describe_world(t.w));
  ASSERT_EQ(copy.fibers().size(), t.w.fibers().size());
  for (std::size_t i = 0; i < copy.fibers().size(); ++i) {
    EXPECT_GT(t.w.fibers()[i].plastic, 0.01);
    EXPECT_EQ(copy.fibers()[i].plastic, t.w.fibers()[i].plastic);
  }
  for (W* w : {&t.w, &copy}) {
    w->positions()(0, Tension::kFibers) = Tension::kRest * Tension::kFibers * 1.1001;
    w->step();
  }
  EXPECT_EQ(position_hash(copy), position_hash(t.w));
}

TEST(Fiber, ACurveThatCannotBeIsRefusedAndOnlyFibersTakeOne) {
  W w;
  w.add_particle(W::Vec(0, 0, 0), 1);
  w.add_particle(W::Vec(1, 0, 0), 1);
  Material bad = ligament();
  bad.yield_strain = 0.01;  // below the toe's end
  test::expect_words(test::error_of([&] { w.add_constraint_set(Stiffness::fiber(bad)); }), {"add_constraint_set: set 0: yield_strain must be at least toe_strain"});
  bad = ligament();
  bad.stiffness = -1;
  test::expect_words(test::error_of([&] { w.add_constraint_set(Stiffness::fiber(bad)); }), {"stiffness must be finite and > 0"});
  const Index set = w.add_constraint_set(Stiffness::fiber(ligament()));
  test::expect_words(test::error_of([&] { w.add_stretch(0, 1, set); }), {"add_stretch: stretch constraint 0: set 0 has a stress-strain curve, which only fibers and tet fibers take"});
  w.add_particle(W::Vec(1, 0, 0), 1);
  test::expect_words(test::error_of([&] { w.add_fiber(1, 2, set); }), {"add_fiber: fiber 0: the particles coincide"});
  EXPECT_EQ(w.add_fiber(0, 1, set), 0u);
  EXPECT_EQ(w.num_constraints(), 1u);
}

}  // namespace
}  // namespace pbd
