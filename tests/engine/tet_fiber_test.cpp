// Tet fibers (constraints/tet_fiber.hpp): the stress–strain curve on a body of tets, against closed forms, under
// every solver. A bar of tets whose fibers run along it, pulled quasi-statically, carries A·σ(ε) at its grips
// through toe, linear part and yield and breaks at the rupture strain; unloaded after yield it goes back along the
// slope E·A to its plastic strain; the grips' work is the elastic energy plus the plastic dissipation. A tet fiber
// that breaks takes its tet's other constraints and no others; a free block keeps its momentum across such tears,
// and a tear gives the same bits on 1–4 threads. The plastic strain is kept in a world's description.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh.hpp"
#include "pbd/world.hpp"
#include "pieces.hpp"
#include "tension_points.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <set>
#include <vector>

namespace pbd {
namespace {

using W = World<double>;
using Tet = std::array<Index, 4>;

// A tendon-like curve in Pa: E = 1 MPa, toe to 3%, yield at 8% with hardening 0.2 MPa, rupture at 14%.
Material tendon() {
  Material m;
  m.stiffness = 1e6;
  m.toe_strain = 0.03;
  m.yield_strain = 0.08;
  m.hardening = 2e5;
  m.rupture_strain = 0.14;
  return m;
}

// A tension test on a bar of 4 × 1 × 1 cubes of 1 cm (24 Kuhn tets, 1000 kg/m³) with a tet fiber along x on every
// tet and nothing else: its x = 0 face is a fixed grip, its x = L face a grip moved along x; no gravity. Moved
// along x only, every tet's F·a0 stays along x, so each tet is a piece of a bundle of fibers of cross-section
// A = 1 cm² and the bar carries A·σ(ε).
struct Bar {
  static constexpr int kCells = 4;
  static constexpr double kCell = 0.01, kLength = kCells * kCell, kArea = kCell * kCell;
  W w;
  std::vector<Index> grip;  // the moving grip's particles
  explicit Bar(Solver solver, const Material& m = tendon()) {
    const TetMesh mesh = tet_box_mesh({kCells, 1, 1}, {kLength, kCell, kCell});
    TetBodyOptions o;
    o.pinned = tet_mesh_face_vertices(mesh, 0, false);
    grip = tet_mesh_face_vertices(mesh, 0, true);
    o.pinned.insert(o.pinned.end(), grip.begin(), grip.end());
    TetConstraintSets sets;
    sets.fibers = w.add_constraint_set(Stiffness::fiber(m));
    add_tet_body(w, mesh, o, sets);
    w.set_params(test::weightless<double>(solver, 10, solver == Solver::jacobi ? 40 : 10));
  }
  double end() const { return w.positions()(0, grip[0]); }
  double strain() const { return end() / kLength - 1.0; }
  void step_to(double s) {  // moves the grip to total strain s, then steps
    for (Index v : grip) w.positions()(0, v) = kLength * (1.0 + s);
    w.step();
  }
  // The force the bar carries, from its tets' stresses: Σ V0·σ / L (the work of a uniform stretch).
  double force() const {
    const auto r = w.material_readings<TetFiberConstraint<double>>();
    const auto& c = w.constraints<TetFiberConstraint<double>>();
    double sum = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) sum += c[i].volume * r[i].force;
    return sum / kLength;
  }
};

constexpr double kRate = 1e-4;  // strain per 1 ms step: slow against the bar's period (about 8 ms)

TEST(TetFiber, TensionTestFollowsTheCurveAndBreaksAtTheRuptureStrainUnderEverySolver) {
  const Material m = tendon();
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Bar bar(solver);
    const std::vector<double> points = test::tension_points(m);
    std::size_t next = 0;
    double broke_at = -1.0;
    for (int step = 1; step < 2000 && broke_at < 0; ++step) {
      bar.step_to(kRate * step);
      if (!bar.w.last_breaks().empty()) {
        const FiberBreak& b = bar.w.last_breaks().front();
        EXPECT_STREQ(b.type, "tet_fiber");
        EXPECT_EQ(b.arity, 4);
        broke_at = b.strain;
        EXPECT_NEAR(b.force, m.loading_force(broke_at), 0.02 * m.loading_force(broke_at));  // a stress, Pa
        break;
      }
      const double s = bar.strain();
      if (next < points.size() && s >= points[next]) {
        const double expected = Bar::kArea * m.loading_force(s);
        EXPECT_NEAR(bar.force(), expected, 0.02 * expected) << "at strain " << s;
        ++next;
      }
    }
    EXPECT_EQ(next, points.size());
    EXPECT_NEAR(broke_at, m.rupture_strain, 0.01 * m.rupture_strain);
    // The first cube to reach it (all carry the same strain, to rounding) broke whole, its 6 tets on its 8
    // corners: the bar is cut through.
    std::set<Index> corners;
    for (const FiberBreak& b : bar.w.last_breaks()) corners.insert(b.particles.begin(), b.particles.end());
    EXPECT_EQ(bar.w.last_breaks().size(), 6u);
    EXPECT_EQ(corners.size(), 8u);
    bar.w.validate();
  }
}

// Pulled to ε_max past yield and back at the same rate: each tet's plastic strain is E·(ε_max − ε_y)/(E + H), the
// bar leaves the linear part with slope E·A and goes slack at that strain.
TEST(TetFiber, UnloadedAfterYieldItGoesBackAlongTheLinearSlopeToItsPlasticStrain) {
  const Material m = tendon();
  const double top = 0.11;
  const double plastic = m.stiffness * (top - m.yield_strain) / (m.stiffness + m.hardening);
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Bar bar(solver);
    const int up = int(std::lround(top / kRate));
    for (int step = 1; step <= up; ++step) bar.step_to(kRate * step);
    double mean = 0.0;
    const auto readings = bar.w.material_readings<TetFiberConstraint<double>>();
    for (const FiberReading& r : readings) mean += r.plastic / double(readings.size());
    EXPECT_NEAR(mean, plastic, 0.02 * plastic);
    double slack = -1.0, f1 = 0.0, s1 = 0.0, f2 = 0.0, s2 = 0.0;
    for (int step = up - 1; step >= 0 && slack < 0; --step) {
      bar.step_to(kRate * step);
      const double s = bar.strain();
      if (step == up - 50) f1 = bar.force(), s1 = s;
      if (step == up - 250) f2 = bar.force(), s2 = s;
      if (bar.force() <= 0.0) slack = s;
    }
    EXPECT_NEAR((f1 - f2) / (s1 - s2), m.stiffness * Bar::kArea, 0.02 * m.stiffness * Bar::kArea);
    EXPECT_NEAR(slack, plastic, 0.02 * plastic);
    EXPECT_TRUE(bar.w.last_breaks().empty());
  }
}

// The grip's work (∫F dx) up to just before rupture is the tets' elastic energy (V0·Ψ(e) each), their plastic
// dissipation (V0·σ·Δε_p summed over the steps) and the particles' kinetic energy.
TEST(TetFiber, TheGripsWorkIsTheElasticEnergyPlusThePlasticDissipation) {
  const Material m = tendon();
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    Bar bar(solver);
    const auto& tets = bar.w.constraints<TetFiberConstraint<double>>();
    double work = 0.0, dissipated = 0.0, force = 0.0, end = bar.end();
    auto before = bar.w.material_readings<TetFiberConstraint<double>>();
    const int steps = int(std::lround(0.135 / kRate));
    for (int step = 1; step <= steps; ++step) {
      bar.step_to(kRate * step);
      const auto after = bar.w.material_readings<TetFiberConstraint<double>>();
      work += 0.5 * (force + bar.force()) * (bar.end() - end);
      force = bar.force();
      end = bar.end();
      for (std::size_t i = 0; i < after.size(); ++i)
        dissipated += tets[i].volume * after[i].force * (after[i].plastic - before[i].plastic);
      before = after;
    }
    double elastic = 0.0, kinetic = 0.0;
    for (std::size_t i = 0; i < before.size(); ++i) elastic += tets[i].volume * m.energy(before[i].strain - before[i].plastic);
    for (Index i = 0; i < bar.w.num_particles(); ++i)
      if (bar.w.inverse_masses()(i) > 0.0)
        kinetic += 0.5 / bar.w.inverse_masses()(i) * bar.w.velocities().col(i).squaredNorm();
    EXPECT_GT(dissipated, 0.2 * work);  // well past yield: a good part of the work is dissipated
    EXPECT_NEAR(elastic + dissipated + kinetic, work, 0.02 * work);
  }
}

// A block of nx × 1 × 1 cells of 1 cm with Neo-Hookean and volume constraints and a tet fiber along x on every tet
// (E = 20 kPa, rupture at 10%). Free, its halves moving apart at `speed` along x; or, `speed` 0, held at x = 0 with
// its far end pinned and pulled at 0.5 m/s.
struct FiberBlock {
  static constexpr int nx = 4;
  W w;
  FiberBlock(Solver solver, double speed) {
    const TetMesh mesh = tet_box_mesh({nx, 1, 1}, {0.01 * nx, 0.01, 0.01});
    TetBodyOptions o;
    if (speed == 0.0) {
      o.pinned = tet_mesh_face_vertices(mesh, 0, false);
      for (Index v : tet_mesh_face_vertices(mesh, 0, true)) o.pinned.push_back(v);
    }
    TetConstraintSets sets;
    sets.volume = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
    sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(1e-3));
    sets.ratio = 0.5;
    Material m;
    m.stiffness = 2e4;
    m.rupture_strain = 0.1;
    sets.fibers = w.add_constraint_set(Stiffness::fiber(m));
    add_tet_body(w, mesh, o, sets);
    for (Index i = 0; i < w.num_particles(); ++i) {
      const double x = w.positions()(0, i);
      if (speed != 0.0) w.velocities()(0, i) = x < 0.005 * nx ? -speed : speed;
      else if (x > 0.01 * nx - 1e-9) w.velocities()(0, i) = 0.5;
    }
    w.set_params(test::weightless<double>(solver, 4, 4));
  }
  template <class C> std::multiset<Tet> corners() const {  // each constraint of C's corners, sorted
    std::multiset<Tet> out;
    for (const auto& c : w.constraints<C>()) {
      Tet t = c.particles;
      std::sort(t.begin(), t.end());
      out.insert(t);
    }
    return out;
  }
};

// Each step, the Neo-Hookean and volume tets that left are exactly those whose tet fibers the step broke, and no
// other constraint left; until no tet holds the pulled end: the block is cut through.
TEST(TetFiber, ABrokenTetFiberTakesItsTetAndNoOtherUnderEverySolver) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    FiberBlock b(solver, 0.0);
    std::vector<Index> pulled;  // the pulled end's particles
    for (Index i = 0; i < b.w.num_particles(); ++i)
      if (b.w.positions()(0, i) > 0.01 * FiberBlock::nx - 1e-9) pulled.push_back(i);
    auto holds_pulled = [&](const std::multiset<Tet>& tets) {
      for (const Tet& t : tets)
        for (Index p : t)
          if (std::find(pulled.begin(), pulled.end(), p) != pulled.end()) return true;
      return false;
    };
    std::multiset<Tet> before = b.corners<NeoHookeanConstraint<double>>();
    std::size_t broken = 0;
    for (int step = 0; step < 200 && holds_pulled(before); ++step) {
      b.w.step();
      std::multiset<Tet> expected = before;
      for (const FiberBreak& f : b.w.last_breaks()) {
        ASSERT_STREQ(f.type, "tet_fiber");
        Tet t = f.particles;
        std::sort(t.begin(), t.end());
        ASSERT_EQ(expected.count(t), 1u) << "step " << step;
        expected.erase(t);
      }
      broken += b.w.last_breaks().size();
      ASSERT_EQ(b.corners<NeoHookeanConstraint<double>>(), expected) << "step " << step;
      ASSERT_EQ(b.corners<TetVolumeConstraint<double>>(), expected) << "step " << step;
      ASSERT_EQ(b.corners<TetFiberConstraint<double>>(), expected) << "step " << step;
      before = expected;
      b.w.validate();
    }
    EXPECT_GE(broken, 6u);  // at least a cube's worth: the whole cross-section
    EXPECT_FALSE(holds_pulled(before));
  }
}

TEST(TetFiber, AFreeBlockTornByItsOwnMotionKeepsItsMassAndMomentum) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    FiberBlock b(solver, 10.0);
    const VectorX<double> w0 = b.w.inverse_masses();
    const auto [p0, l0] = test::momenta(b.w);
    std::size_t broken = 0;
    for (int step = 0; step < 100; ++step) {
      b.w.step();
      broken += b.w.last_breaks().size();
      const auto [p1, l1] = test::momenta(b.w);
      ASSERT_LT((p1 - p0).norm(), 1e-14) << "step " << step;
    }
    EXPECT_EQ(b.w.inverse_masses(), w0);
    EXPECT_GT(broken, 0u);
  }
}

TEST(TetFiber, ATearGivesTheSameBitsAndBreaksOnOneToFourThreads) {
  for (Solver solver : {Solver::serial_colored, Solver::colored, Solver::jacobi, Solver::block}) {
    SCOPED_TRACE(name(solver));
    std::vector<std::uint64_t> hashes;
    std::vector<std::vector<std::int64_t>> logs;
    std::size_t most = 0;
    for (int threads = 1; threads <= 4; ++threads) {
      tbb::task_arena arena(threads);
      FiberBlock b(solver, 0.0);
      std::vector<std::int64_t> log;
      arena.execute([&] {
        for (int step = 0; step < 100; ++step) {
          b.w.step();
          for (const FiberBreak& f : b.w.last_breaks()) log.insert(log.end(), {f.step, std::int64_t(f.fiber)});
          most = std::max(most, b.w.last_breaks().size());
        }
      });
      b.w.validate();
      hashes.push_back(position_hash(b.w));
      logs.push_back(log);
    }
    EXPECT_FALSE(logs[0].empty());
    EXPECT_GE(most, 2u);  // several in one step
    for (int i = 1; i < 4; ++i) {
      EXPECT_EQ(hashes[i], hashes[0]) << i + 1 << " threads";
      EXPECT_EQ(logs[i], logs[0]) << i + 1 << " threads";
    }
  }
}

// The plastic strain is kept with the tet fibers: a world described after yielding is rebuilt with the rest shapes
// they have grown to, and steps on from there as the original does, bit for bit.
TEST(TetFiber, AWorldRebuiltFromItsDescriptionKeepsThePlasticStrains) {
  Bar bar(Solver::serial);
  for (int step = 1; step <= 1000; ++step) bar.step_to(kRate * step);  // past yield: 10% against 8%
  W copy = build_world<double>(describe_world(bar.w));
  const auto a = bar.w.material_readings<TetFiberConstraint<double>>();
  const auto b = copy.material_readings<TetFiberConstraint<double>>();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_GT(a[i].plastic, 0.01);
    EXPECT_EQ(b[i].plastic, a[i].plastic);
  }
  for (W* w : {&bar.w, &copy}) {
    for (Index v : bar.grip) w->positions()(0, v) = Bar::kLength * 1.1001;
    w->step();
  }
  EXPECT_EQ(position_hash(copy), position_hash(bar.w));
}

TEST(TetFiber, ItsDirectionIsTheXAxisUnlessGivenAndNotZero) {
  W w;
  for (int i = 0; i < 4; ++i) w.add_particle(W::Vec(i == 1, i == 2, i == 3), 1);
  const Index set = w.add_constraint_set(Stiffness::fiber(tendon()));
  TetFiberConstraint<double> c = blank_constraint<TetFiberConstraint<double>>();
  c.particles = {0, 1, 2, 3};
  c.set = set;
  test::expect_words(test::error_of([&] { w.add(c, FieldMask(2)); }), {"tet fiber 0", "fiber direction must be finite and not zero"});
  EXPECT_EQ(w.add(c, FieldMask(0)), 0u);  // the x axis: Dm = I, so b = a0
  EXPECT_EQ(w.constraints<TetFiberConstraint<double>>()[0].direction, W::Vec(1, 0, 0));
  EXPECT_EQ(w.constraints<TetFiberConstraint<double>>()[0].weights, W::Vec(1, 0, 0));
  c.direction = W::Vec(0, 0, 2);  // its unit vector is used: b = Dm⁻¹·(0, 0, 1)
  EXPECT_EQ(w.add(c, FieldMask(2)), 1u);
  EXPECT_EQ(w.constraints<TetFiberConstraint<double>>()[1].weights, W::Vec(0, 0, 1));
  const TetMesh mesh = tet_box_mesh({1, 1, 1}, {1, 1, 1});
  TetConstraintSets sets;
  sets.fibers = set;
  sets.direction = {0.0, 0.0, 0.0};
  test::expect_words(test::error_of([&] { add_tet_body(w, mesh, TetBodyOptions{}, sets); }),
                     {"add_tet_body", "direction must be finite and not zero"});
}

}  // namespace
}  // namespace pbd
