// Bodies of tets that tear along broken fibers (engine/src/tear_cells.hpp): a fiber that breaks takes the tets
// holding both its ends with it, and no other; a free block torn by its own motion keeps its mass and momentum;
// the same bits on 1-4 threads under every parallel solver; validate() holds after each tear.
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh.hpp"
#include "pbd/world.hpp"
#include "pieces.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <numeric>
#include <set>
#include <vector>

namespace pbd {
namespace {

using W = World<double>;
using Tet = std::array<Index, 4>;

// A block of nx x 1 x 1 cells of 1 cm (1000 kg/m³) with Neo-Hookean and volume constraints on every tet and a fiber
// on every edge (k = 20 N, rupture at 10%). Free, its halves moving apart at `speed` along x; or, `speed` 0, held at
// x = 0 with its far end pinned and pulled at 0.5 m/s.
struct TetBlock {
  static constexpr int nx = 4;
  W w;
  TetBlock(Solver solver, double speed) {
    const TetMesh mesh = tet_box_mesh({nx, 1, 1}, {0.01 * nx, 0.01, 0.01});
    TetBodyOptions o;
    o.density = 1000.0;
    if (speed == 0.0) {
      o.pinned = tet_mesh_face_vertices(mesh, 0, false);
      for (Index v : tet_mesh_face_vertices(mesh, 0, true)) o.pinned.push_back(v);
    }
    TetConstraintSets sets;
    sets.volume = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
    sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(1e-3));
    sets.ratio = 0.5;
    Material m;
    m.stiffness = 20.0;
    m.rupture_strain = 0.1;
    sets.stretch = w.add_constraint_set(Stiffness::fiber(m));
    add_tet_body(w, mesh, o, sets);
    for (Index i = 0; i < w.num_particles(); ++i) {
      const double x = w.positions()(0, i);
      if (speed != 0.0) w.velocities()(0, i) = x < 0.005 * nx ? -speed : speed;
      else if (x > 0.01 * nx - 1e-9) w.velocities()(0, i) = 0.5;
    }
    w.set_params(test::weightless<double>(solver, 4, 4));
  }
  std::set<Tet> tets() const {  // the corners of every tet constraint left, sorted
    std::set<Tet> out;
    auto add = [&](Tet t) {
      std::sort(t.begin(), t.end());
      out.insert(t);
    };
    for (const auto& c : w.constraints<NeoHookeanConstraint<double>>()) add(c.particles);
    for (const auto& c : w.constraints<TetVolumeConstraint<double>>()) add(c.particles);
    return out;
  }
};

bool holds(const Tet& t, Index a, Index b) {
  return std::find(t.begin(), t.end(), a) != t.end() && std::find(t.begin(), t.end(), b) != t.end();
}

using test::pieces;

// Each step, the tets that left the model are exactly those that held both ends of a fiber the step broke: both
// tet types of each, and no other constraint than the broken fibers (the fibers along the torn tets' other edges
// stay). Until the block is in two pieces.
TEST(TearCells, ABrokenFiberTakesTheTetsOnItsEdgeAndNoOthersUnderEverySolver) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    TetBlock b(solver, 0.0);
    std::set<Tet> before = b.tets();
    const std::size_t tets0 = before.size();
    std::size_t broken = 0, fibers = b.w.constraints<FiberConstraint<double>>().size();
    for (int step = 0; step < 200 && pieces(before, b.w.num_particles()) < 2; ++step) {
      const std::size_t nh = b.w.constraints<NeoHookeanConstraint<double>>().size();
      b.w.step();
      b.w.validate();
      const std::set<Tet> after = b.tets();
      std::set<Tet> expected;
      for (const Tet& t : before) {
        bool torn = false;
        for (const FiberBreak& f : b.w.last_breaks()) torn = torn || holds(t, f.particles[0], f.particles[1]);
        if (!torn) expected.insert(t);
      }
      ASSERT_EQ(after, expected) << "step " << step;
      ASSERT_EQ(b.w.constraints<NeoHookeanConstraint<double>>().size(), nh - (before.size() - after.size()));
      ASSERT_EQ(b.w.constraints<TetVolumeConstraint<double>>().size(), after.size());
      broken += b.w.last_breaks().size();
      ASSERT_EQ(b.w.constraints<FiberConstraint<double>>().size(), fibers - broken) << "step " << step;
      before = after;
    }
    EXPECT_GT(broken, 0u);
    EXPECT_LT(before.size(), tets0);
    EXPECT_EQ(pieces(before, b.w.num_particles()), 2u);
  }
}

// A free block whose halves fly apart tears: its particles, masses and momentum stay what they were.
TEST(TearCells, AFreeBlockTornByItsOwnMotionKeepsItsMassAndMomentum) {
  for (Solver solver : kSolvers) {
    SCOPED_TRACE(name(solver));
    TetBlock b(solver, 10.0);
    const std::size_t tets0 = b.tets().size();
    const Index n = b.w.num_particles();
    const VectorX<double> w0 = b.w.inverse_masses();
    const auto [p0, l0] = test::momenta(b.w);
    std::size_t broken = 0;
    for (int step = 0; step < 100; ++step) {
      b.w.step();
      broken += b.w.last_breaks().size();
      const auto [p1, l1] = test::momenta(b.w);
      ASSERT_LT((p1 - p0).norm(), 1e-14) << "step " << step;
    }
    EXPECT_EQ(b.w.num_particles(), n);
    EXPECT_EQ(b.w.inverse_masses(), w0);
    EXPECT_GT(broken, 0u);
    EXPECT_LT(b.tets().size(), tets0);
  }
}

TEST(TearCells, ATetTearGivesTheSameBitsOnOneToFourThreads) {
  for (Solver solver : {Solver::serial_colored, Solver::colored, Solver::jacobi, Solver::block}) {
    SCOPED_TRACE(name(solver));
    std::vector<std::uint64_t> hashes;
    std::vector<std::size_t> left;
    for (int threads = 1; threads <= 4; ++threads) {
      tbb::task_arena arena(threads);
      TetBlock b(solver, 0.0);
      arena.execute([&] {
        for (int step = 0; step < 100; ++step) b.w.step();
      });
      b.w.validate();
      hashes.push_back(position_hash(b.w));
      left.push_back(b.tets().size());
    }
    EXPECT_LT(left[0], std::size_t(6 * TetBlock::nx));  // Kuhn: 6 tets a cube
    for (int i = 1; i < 4; ++i) {
      EXPECT_EQ(hashes[i], hashes[0]) << i + 1 << " threads";
      EXPECT_EQ(left[i], left[0]) << i + 1 << " threads";
    }
  }
}

}  // namespace
}  // namespace pbd
