// Volumetric soft bodies (Neo-Hookean and volume tets) against closed forms, for every solver (issue 45). Each check
// prints one greppable line
//   SOFTBODY check=<name> solver=<...> real=<float|double> <measured>=<x> <closed form>=<y> error=<relative>
//   - column: a block clamped at its base and compressed by its own weight shortens by ρgH²/(2E) (ν = 0: uniaxial)
//   - cantilever: a bar clamped at one end sags at its tip by Timoshenko's ρgA(L⁴/(8EI) + L²/(2κGA)); linear tets
//     are too stiff in bending on coarse meshes (shear locking), so the check is the mesh limit: the error falls
//     as the mesh is refined, and the Richardson extrapolation of two meshes (error ∝ n⁻², n cells through the
//     thickness) is within 5% of the closed form
//   - free body: no pins, contacts or gravity, tets squeezed out of shape and spinning: momentum and angular
//     momentum kept to rounding
//   - crushed: a body pressed flat and partly inverted recovers its rest volume without NaN
//   - the pig: the built-in pig-tets scene (Neo-Hookean, ν = 0.49) dropped on the ground keeps its volume within 1%
//     and bounces
//   - the same bits on 1–4 threads
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh.hpp"
#include "solve/free_bodies.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace pbd {
namespace {

using test::momenta;
using test::run_on;

template <class Real> class SoftBody : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(SoftBody, Precisions);

template <class Real> const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

void print_line(const char* check, Solver s, const char* real, const std::string& rest) {
  std::printf("SOFTBODY check=%s solver=%s real=%s %s\n", check, std::string(name(s)).c_str(), real, rest.c_str());
}

// A box of cells[0..2] cells of size[0..2] m, density 1000, Neo-Hookean (E, ν), the face `clamped` (axis·2 + max)
// pinned, under gravity g along −z, damped (the checks want the state at rest).
template <class Real>
World<Real> block(std::array<int, 3> cells, std::array<double, 3> size, double E, double nu, int clamped, double g,
                  Solver s, int substeps, int iterations, double damping) {
  World<Real> w;
  const TetMesh mesh = tet_box_mesh(cells, size);
  const NeoHookeanMaterial m = young_poisson(E, nu);
  TetConstraintSets sets;
  sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
  sets.ratio = m.ratio();
  TetBodyOptions o;
  o.density = 1000.0;
  if (clamped >= 0) o.pinned = tet_mesh_face_vertices(mesh, clamped / 2, clamped % 2 == 1);
  add_tet_body(w, mesh, o, sets);
  StepParams<Real> p;
  p.gravity = Vec3<Real>(0, 0, Real(-g));
  p.solver = s;
  p.substeps = substeps;
  p.iterations = iterations;
  p.damping = Real(damping);
  w.set_params(p);
  return w;
}

// Mean displacement along z of the particles whose rest coordinate `axis` is `at`.
template <class Real>
double mean_drop(const World<Real>& w, const Matrix3X<Real>& x0, int axis, double at) {
  double sum = 0;
  int count = 0;
  for (Index i = 0; i < w.num_particles(); ++i)
    if (std::abs(double(x0(axis, i)) - at) < 1e-6) {
      sum += double(x0(2, i)) - double(w.positions()(2, i));
      ++count;
    }
  return sum / count;
}

// Sub-steps × iterations of each solver for a quasi-static check that wants `substeps` in double with Gauss-Seidel.
// Jacobi averages its corrections, so it takes more iterations per sub-step to reach the same state (4 here, at
// the same sub-steps: with fewer, the sub-step grows past what the tets' coupled solve follows and the bar sags
// twice too far). In float, gravity's move per sub-step, h²g, falls below the coordinates' rounding step at these
// loads (1e-8 m against 6e-8 m at 0.5 m): Gauss-Seidel takes half the sub-steps with two iterations each instead.
template <class Real> std::pair<int, int> split(Solver s, int substeps) {
  if (s == Solver::jacobi) return {substeps, 4};
  if constexpr (sizeof(Real) == 4) return {substeps / 2, 2};
  else return {substeps, 1};
}

// Column 0.2 × 0.2 × 1 m (4 × 4 × 20 cells), E = 1 MPa, ν = 0, clamped at z = 0; g chosen for a 1% shortening.
TYPED_TEST(SoftBody, ColumnShortensUnderItsOwnWeightAsRhoGH2Over2E) {
  using Real = TypeParam;
  const double E = 1e6, H = 1.0, rho = 1000.0, g = 0.01 * 2 * E / (rho * H);
  const double closed = rho * g * H * H / (2 * E);
  for (Solver s : kSolvers) {
    if (s == Solver::serial_colored) continue;  // colored's bits
    const auto [substeps, iterations] = split<Real>(s, 80);
    World<Real> w = block<Real>({4, 4, 20}, {0.2, 0.2, H}, E, 0.0, 4, g, s, substeps, iterations, 10.0);
    const Matrix3X<Real> x0 = w.positions();
    for (int step = 0; step < 75; ++step) w.step();  // 1.25 s: damped to rest
    const double drop = mean_drop(w, x0, 2, H), error = drop / closed - 1;
    print_line("column", s, real_name<Real>(),
               "shortening=" + fmt(drop) + " closed_form=" + fmt(closed) + " error=" + fmt(error));
    EXPECT_LT(std::abs(error), 0.01) << name(s);
  }
}

// Cantilever 0.5 × 0.1 × 0.1 m, E = 1 MPa, ν = 0, clamped at x = 0, g for a tip sag of 0.5% of L, on meshes of
// n = 4 and 6 cells through the thickness (5n along); sub-steps grow with n so that each mesh is solved as finely
// (a cell's elastic wave crossing time over the sub-step stays the same). In double only: a sag this small is
// resolved in float by how h²g rounds against the coordinates (split's comment), which the extrapolation
// amplifies (float, at the same splits: -1.9%, -1.4%, +23% and -6.9% under serial, colored, Jacobi and block).
TEST(SoftBodyMeshLimit, CantileverSagConvergesToTimoshenkoUnderRefinement) {
  using Real = double;
  const double E = 1e6, nu = 0.0, h = 0.1, L = 0.5, rho = 1000.0;
  const double I = h * h * h * h / 12, A = h * h, G = E / (2 * (1 + nu)), kappa = 10 * (1 + nu) / (12 + 11 * nu);
  const double per_g = rho * A * (std::pow(L, 4) / (8 * E * I) + L * L / (2 * kappa * G * A));
  const double g = 0.005 * L / per_g, closed = per_g * g;
  for (Solver s : kSolvers) {
    if (s == Solver::serial_colored) continue;
    double sag[2];
    const int ns[2] = {4, 6};
    for (int k = 0; k < 2; ++k) {
      const int n = ns[k];
      const auto [substeps, iterations] = split<Real>(s, 20 * n);
      World<Real> w = block<Real>({5 * n, n, n}, {L, h, h}, E, nu, 0, g, s, substeps, iterations, 15.0);
      const Matrix3X<Real> x0 = w.positions();
      for (int step = 0; step < 45; ++step) w.step();  // 0.75 s: damped to rest
      sag[k] = mean_drop(w, x0, 0, L);
    }
    const double limit = (36 * sag[1] - 16 * sag[0]) / 20;  // Richardson: sag(n) = limit − c/n²
    print_line("cantilever", s, real_name<Real>(),
               "sag_n4=" + fmt(sag[0]) + " sag_n6=" + fmt(sag[1]) + " extrapolated=" + fmt(limit) +
                   " closed_form=" + fmt(closed) + " error=" + fmt(limit / closed - 1));
    EXPECT_LT(std::abs(sag[1] - closed), std::abs(sag[0] - closed)) << name(s) << ": refining must help";
    EXPECT_LT(std::abs(limit / closed - 1), 0.05) << name(s);
  }
}

// A free 3 × 2 × 2 block (0.3 × 0.2 × 0.2 m of 1000 kg/m³, E = 0.1 MPa, ν = 0.45), started
// squashed to half its height and spinning at 5 rad/s about a tilted axis: no pins, contacts or gravity. Every
// projection moves the corners by w_i ∇C Δλ with Σ_i ∇_i C = 0, central about the positions it reads; the velocity
// update gives a free body back the angular momentum it had (free_bodies.hpp). So both stay at their start values
// up to rounding: 2·10⁴ rounding errors of the body's scale (mass × speed, × size for the angular one).
TYPED_TEST(SoftBody, FreeBlockKeepsItsMomentumWhileItSpringsBack) {
  using Real = TypeParam;
  for (Solver s : kSolvers)
    for (bool volume : {false, true}) {
      World<Real> w;
      const TetMesh mesh = tet_box_mesh({3, 2, 2}, {0.3, 0.2, 0.2});
      const NeoHookeanMaterial m = young_poisson(1e5, 0.45);
      TetConstraintSets sets;
      sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
      sets.ratio = m.ratio();
      if (volume) sets.volume = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
      add_tet_body(w, mesh, TetBodyOptions{}, sets);
      Matrix3X<Real> x = w.positions();
      const Vec3<double> axis = Vec3<double>(1, 2, 3).normalized();
      Matrix3X<Real> v(3, w.num_particles());
      for (Index i = 0; i < w.num_particles(); ++i) {
        x(2, i) *= Real(0.5);
        v.col(i) = (5.0 * axis.cross(Vec3<double>(x.col(i).template cast<double>()))).template cast<Real>();
      }
      w.positions() = x;
      w.velocities() = v;
      StepParams<Real> p;
      p.gravity.setZero();
      p.substeps = 4;
      p.iterations = 3;
      p.solver = s;
      w.set_params(p);
      const auto [p0, l0] = momenta(w);
      double max_dp = 0, max_dl = 0;
      for (int step = 0; step < 120; ++step) {
        w.step();
        const auto [p1, l1] = momenta(w);
        max_dp = std::max(max_dp, (p1 - p0).norm());
        max_dl = std::max(max_dl, (l1 - l0).norm());
      }
      const double mass = 1000.0 * 0.3 * 0.2 * 0.2, speed = 5.0 * 0.2, eps = std::numeric_limits<Real>::epsilon();
      print_line("free-block", s, real_name<Real>(),
                 std::string("volume=") + (volume ? "1" : "0") + " max_momentum_change=" + fmt(max_dp) +
                     " max_angular_momentum_change=" + fmt(max_dl) + " height=" + fmt(w.positions().row(2).maxCoeff() -
                                                                                      w.positions().row(2).minCoeff()));
      EXPECT_LE(max_dp, 2e4 * eps * mass * speed) << name(s);
      EXPECT_LE(max_dl, 2e4 * eps * mass * speed * 0.3) << name(s);
      EXPECT_TRUE(w.positions().allFinite());
    }
}

// Two free bodies of 1000 particles each, squashed and spinning: the free bodies' sums run over chunks of 512
// particles, one of which holds both bodies, and every loop forks. The bits are the same on 1–4 threads (the chunks'
// sums are added in chunk order however they were shared), and each body keeps its momentum and angular momentum (the
// sums reach the right body across the chunks: a run summed into the other body would spin both).
TYPED_TEST(SoftBody, FreeBodiesAcrossChunksKeepTheirMomentaWithTheSameBitsOnOneToFourThreads) {
  using Real = TypeParam;
  World<Real> w;
  const TetMesh mesh = tet_box_mesh({9, 9, 9}, {0.2, 0.2, 0.2});
  ASSERT_EQ(mesh.num_vertices(), 1000);
  const NeoHookeanMaterial m = young_poisson(1e5, 0.45);
  TetConstraintSets sets;
  sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
  sets.ratio = m.ratio();
  for (double x0 : {0.0, 0.5}) {
    TetBodyOptions o;
    o.origin = {x0, 0.0, 0.0};
    add_tet_body(w, mesh, o, sets);
  }
  ASSERT_GT(w.num_particles(), 3 * Index(pbd::detail::kSpinChunk));
  Matrix3X<Real> x = w.positions(), v(3, w.num_particles());
  const Vec3<double> axis = Vec3<double>(1, 2, 3).normalized();
  for (Index i = 0; i < w.num_particles(); ++i) {
    const double sign = i < 1000 ? 1.0 : -1.0, centre = i < 1000 ? 0.1 : 0.6;
    x(2, i) *= Real(0.5);
    const Vec3<double> r = x.col(i).template cast<double>() - Vec3<double>(centre, 0.1, 0.05);
    v.col(i) = (sign * 5.0 * axis.cross(r)).template cast<Real>();
  }
  w.positions() = x;
  w.velocities() = v;
  StepParams<Real> p;
  p.gravity.setZero();
  p.substeps = 4;
  p.iterations = 2;
  p.solver = Solver::colored;
  w.set_params(p);
  w.set_parallel_config({1, 16});
  auto body_momenta = [](const World<Real>& world, Index b) { return momenta(world, 1000 * b, 1000 * (b + 1)); };
  const std::uint64_t bits = run_on(w, 1, 30);
  for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(w, threads, 30), bits) << threads << " threads";
  const double mass = 1000.0 * 0.2 * 0.2 * 0.1, speed = 5.0 * 0.15, eps = std::numeric_limits<Real>::epsilon();
  for (Index b : {0, 1}) {
    const auto [p0, l0] = body_momenta(w, b);
    World<Real> run = w;
    for (int step = 0; step < 30; ++step) run.step();
    const auto [p1, l1] = body_momenta(run, b);
    EXPECT_LE((p1 - p0).norm(), 2e4 * eps * mass * speed) << "body " << b;
    EXPECT_LE((l1 - l0).norm(), 2e4 * eps * mass * speed * 0.2) << "body " << b;
  }
}

// Total signed volume of the body's tets at the world's positions.
template <class Real> double tets_volume(const World<Real>& w, const TetMesh& mesh) {
  double v = 0;
  for (const auto& t : mesh.tets)
    v += signed_tet_volume(w.positions().col(t[0]).template cast<double>(), w.positions().col(t[1]).template cast<double>(),
                           w.positions().col(t[2]).template cast<double>(), w.positions().col(t[3]).template cast<double>());
  return v;
}

// A 4 × 4 × 2 block crushed: every particle put on the plane z = 0 and some pushed through it (a third of the tets
// flat or inverted), then released with gravity off. Neo-Hookean's det F − γ changes sign with the tet, so the
// inverted ones are pushed back out: the body recovers its rest volume (1%) with no NaN, under every solver.
TYPED_TEST(SoftBody, CrushedFlatAndInvertedBlockRecoversWithoutNaN) {
  using Real = TypeParam;
  const TetMesh mesh = tet_box_mesh({4, 4, 2}, {0.2, 0.2, 0.1});
  const double rest = 0.2 * 0.2 * 0.1;
  for (Solver s : kSolvers) {
    World<Real> w = block<Real>({4, 4, 2}, {0.2, 0.2, 0.1}, 1e5, 0.3, -1, 0.0, s, split<Real>(s, 20).first,
                                split<Real>(s, 20).second, 2.0);
    Matrix3X<Real> x = w.positions();
    for (Index i = 0; i < w.num_particles(); ++i) x(2, i) = x(0, i) > Real(0.1) ? Real(-0.3) * x(2, i) : Real(0);
    w.positions() = x;
    const double crushed = tets_volume(w, mesh);
    for (int step = 0; step < 120; ++step) w.step();
    const double back = tets_volume(w, mesh);
    print_line("crushed", s, real_name<Real>(),
               "crushed_volume=" + fmt(crushed / rest) + " recovered_volume=" + fmt(back / rest));
    ASSERT_TRUE(w.positions().allFinite()) << name(s);
    EXPECT_LT(crushed, 0.1 * rest);
    EXPECT_NEAR(back / rest, 1.0, 0.01) << name(s);
  }
}

// The built-in pig-tets scene as it is (float, 10 sub-steps of 3 iterations; at 10 × 1 its worst volume error is
// 2.8%, at 10 × 2 1.0%): 2 s, landing at about step 20 and bouncing. Jacobi, which spreads a stiff bulk response
// far more slowly, runs 40 × 4 (at 10 × 12 it loses 5.2%, at 40 × 3 1.1%). Its tets' total volume stays within 1% of the rest volume over the whole run, and its
// centre of mass rises again after the landing by more than a third of its fall (an elastic body stores the impact
// and gives it back: the contact has no restitution).
TEST(SoftBodyScene, PigKeepsItsVolumeAndBouncesAsItLands) {
  using Real = float;
  const Scene scene = load_scene_by_name("pig-tets", PBD_TEST_SCENE_DIR);
  for (Solver s : kSolvers) {
    if (s == Solver::serial_colored) continue;
    World<Real> w = build_world<Real>(scene.world);
    StepParams<Real> p = w.params();
    p.solver = s;
    if (s == Solver::jacobi) {
      p.substeps = 40;
      p.iterations = 4;
    }
    w.set_params(p);
    const auto& tets = w.template constraints<NeoHookeanConstraint<Real>>();
    double rest = 0;
    for (const auto& c : tets) rest += double(c.volume);
    auto volume = [&] {
      double v = 0;
      for (const auto& c : tets) {
        const auto& q = c.particles;
        v += tet_volume<double>(w.positions().col(q[0]).template cast<double>(), w.positions().col(q[1]).template cast<double>(),
                                w.positions().col(q[2]).template cast<double>(), w.positions().col(q[3]).template cast<double>());
      }
      return v;
    };
    auto height = [&] {
      double mz = 0, m = 0;
      for (Index i = 0; i < w.num_particles(); ++i) {
        mz += double(w.positions()(2, i)) / double(w.inverse_masses()[i]);
        m += 1 / double(w.inverse_masses()[i]);
      }
      return mz / m;
    };
    const double start = height();
    double worst = 0, lowest = start, rebound = 0;
    for (int step = 0; step < 120; ++step) {
      w.step();
      worst = std::max(worst, std::abs(volume() / rest - 1));
      const double z = height();
      if (z < lowest) lowest = z, rebound = z;
      rebound = std::max(rebound, z);
    }
    print_line("pig", s, real_name<Real>(),
               "worst_volume_error=" + fmt(worst) + " start_height=" + fmt(start) + " lowest=" + fmt(lowest) +
                   " rebound=" + fmt(rebound));
    ASSERT_TRUE(w.positions().allFinite()) << name(s);
    EXPECT_LT(worst, 0.01) << name(s);
    EXPECT_GT(rebound - lowest, (start - lowest) / 3) << name(s);
  }
}

// The column with tet volume constraints too, falling onto the ground: the same bits on 1–4 threads.
TYPED_TEST(SoftBody, SameBitsOnOneToFourThreads) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
    World<Real> w;
    const TetMesh mesh = tet_box_mesh({6, 6, 6}, {0.3, 0.3, 0.3});
    const NeoHookeanMaterial m = young_poisson(1e5, 0.4);
    TetConstraintSets sets;
    sets.neo_hookean = w.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
    sets.ratio = m.ratio();
    sets.volume = w.add_constraint_set(Stiffness::pbd_k(0.5));
    TetBodyOptions o;
    o.origin = {0.0, 0.0, 0.05};
    add_tet_body(w, mesh, o, sets);
    w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
    StepParams<Real> p;
    p.solver = s;
    p.substeps = 4;
    p.iterations = 2;
    w.set_params(p);
    const std::uint64_t one = run_on(w, 1, 20);
    for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(w, threads, 20), one) << name(s) << " threads " << threads;
  }
}

// The block solver colors each block's Neo-Hookean interior on its own and runs it color by color (traits.hpp's
// colored interiors; with AVX2, by the kernel). Small blocks so the box has several: the layout validates (every
// interior run independent), the blocks change the order (not the colored solver's bits), the bits are the same on
// 1–4 threads with every loop forking, and with one block holding everything the interior's colors are the colored
// solver's own, so its bits.
TYPED_TEST(SoftBody, BlockSolverRunsTetInteriorsColorByColor) {
  using Real = TypeParam;
  auto world = [](Solver s, std::size_t per_block) {
    World<Real> w = block<Real>({4, 4, 4}, {0.2, 0.2, 0.2}, 1e5, 0.45, -1, 9.81, s, 4, 2, 0.0);
    w.add_plane(Vec3<Real>(0, 0, 1), Real(-0.01));
    w.set_blocking({per_block, true});
    w.set_parallel_config({1, 16});
    return w;
  };
  const World<Real> blocked = world(Solver::block, 64);  // 384 tets: 6 blocks
  const std::uint64_t one = run_on(blocked, 1, 15);
  World<Real> stepped = blocked;
  stepped.step();
  EXPECT_GE(stepped.num_blocks(), 4u);
  EXPECT_NO_THROW(stepped.validate());
  for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(blocked, threads, 15), one) << threads << " threads";
  EXPECT_NE(run_on(world(Solver::colored, 64), 1, 15), one);
  EXPECT_EQ(run_on(world(Solver::block, 1u << 30), 2, 15), run_on(world(Solver::colored, 64), 2, 15));
  // Large blocks (sweep_loops.hpp: about 5,000 tets each): one block a thread, the small boundary colors on one
  // thread; the same bits on 1–4 threads.
  World<Real> large = block<Real>({12, 12, 12}, {0.3, 0.3, 0.3}, 1e5, 0.45, -1, 9.81, Solver::block, 2, 2, 0.0);
  large.add_plane(Vec3<Real>(0, 0, 1), Real(-0.001));
  large.set_blocking({5184, true});
  large.set_parallel_config({1, 16});
  const std::uint64_t large_one = run_on(large, 1, 4);
  for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(large, threads, 4), large_one) << threads << " threads, large blocks";
}

}  // namespace
}  // namespace pbd
