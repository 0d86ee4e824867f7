// Shape matching (constraints/shape_match.hpp) against what it must do, for every solver. Each check prints one
// greppable line
//   SHAPEMATCH check=<name> [solver=<...>] real=<float|double> <measured>=<x> ...
//   - rest shape: a box body of overlapping clusters, deformed at random and released, returns to its rest shape up
//     to a rigid motion
//   - momentum: one projection changes neither momentum nor angular momentum (rigid and linear modes), and a
//     spinning free body keeps both
//   - the same bits on 1–4 threads
//   - degenerate and reflected clusters (coplanar, collinear, collapsed to a point, mirrored): no NaN, and the
//     projection moves them to a proper rotation of the rest shape
//   - compliance: a cube clamped at its base sags under its own weight by the XPBD closed form
#include "pbd/io/shape_match_clusters.hpp"
#include "pbd/io/tet_mesh.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace pbd {
namespace {

using test::momenta;
using test::run_on;

template <class Real> class ShapeMatch : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ShapeMatch, Precisions);

template <class Real> using Cluster = ShapeMatchConstraint<Real>;

template <class Real> const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

void print_line(const std::string& check, const char* real, const std::string& rest) {
  std::printf("SHAPEMATCH check=%s real=%s %s\n", check.c_str(), real, rest.c_str());
}

// A number in [−1, 1) from the generator's raw output (mt19937's sequence is fixed by the standard; the library's
// distributions are not).
double uniform(std::mt19937& rng) { return double(rng()) / 2147483648.0 - 1.0; }

Vec3<double> random_vector(std::mt19937& rng) { return {uniform(rng), uniform(rng), uniform(rng)}; }

// A random direction (rejection from the cube, so that every direction is as likely).
Vec3<double> random_direction(std::mt19937& rng) {
  for (;;) {
    const Vec3<double> v = random_vector(rng);
    if (v.squaredNorm() <= 1.0 && v.squaredNorm() > 1e-4) return v.normalized();
  }
}

// The distance of each particle from the best proper rigid fit of the rest positions to x (Kabsch, equal
// weights: the rotation nearest to the cross-covariance, its sign fixed), in m. Written here with its own SVD, so the
// check does not lean on the header's fit.
Eigen::VectorXd fit_distances(const Matrix3X<double>& rest, const Matrix3X<double>& x) {
  const Vec3<double> cr = rest.rowwise().mean(), cx = x.rowwise().mean();
  const Matrix3X<double> q = rest.colwise() - cr, p = x.colwise() - cx;
  const Eigen::Matrix3d h = p * q.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r = svd.matrixU() * d * svd.matrixV().transpose();
  return (p - r * q).colwise().norm().transpose();
}

// The largest distance of a particle from the best rigid fit of the rest shape, m.
double rigid_residual(const Matrix3X<double>& rest, const Matrix3X<double>& x) {
  return fit_distances(rest, x).maxCoeff();
}

// The RMS distance from the best rigid fit: C of the rigid mode at equal masses, m.
double rigid_rms(const Matrix3X<double>& rest, const Matrix3X<double>& x) {
  const Eigen::VectorXd d = fit_distances(rest, x);
  return std::sqrt(d.squaredNorm() / double(d.size()));
}

template <class Real> Matrix3X<double> positions_of(const World<Real>& w) { return w.positions().template cast<double>(); }

// ---- the box body ----

// A 0.4 × 0.3 × 0.3 m box of 4 × 3 × 3 cells of 0.1 m cut into tets, one cluster per vertex (shape_match_clusters).
const TetMesh& box_mesh() {
  static const TetMesh mesh = tet_box_mesh({4, 3, 3}, {0.4, 0.3, 0.3});
  return mesh;
}
constexpr double kCell = 0.1;
const double kDiagonal = std::sqrt(0.4 * 0.4 + 0.3 * 0.3 + 0.3 * 0.3);

// The box's particles (uneven masses, 10 to 30 g, so that the fit's weights matter) and its clusters in one set of
// stiffness s and mode beta; gravity off.
template <class Real> World<Real> box_body(const Stiffness& s, double beta, Solver solver, int substeps, int iterations) {
  const TetMesh& mesh = box_mesh();
  World<Real> w;
  VectorX<Real> masses(mesh.num_vertices());
  for (Index i = 0; i < mesh.num_vertices(); ++i) masses[i] = Real(0.01 * (1 + i % 3));
  w.add_particles(mesh.positions.cast<Real>(), masses);
  const Index set = w.add_constraint_set(s);
  for (const auto& particles : shape_match_clusters(mesh)) {
    Cluster<Real> c = blank_constraint<Cluster<Real>>();
    c.particles = particles;
    c.set = set;
    c.beta = Real(beta);
    w.add(c, FieldMask(1) << 8);  // β given, the offsets measured at rest
  }
  StepParams<Real> p;
  p.gravity.setZero();
  p.solver = solver;
  p.substeps = substeps;
  p.iterations = iterations;
  w.set_params(p);
  return w;
}

// Moves every particle by `amount` m in a random direction (seed fixed).
template <class Real> void deform(World<Real>& w, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  Matrix3X<Real> x = w.positions();
  for (Index i = 0; i < w.num_particles(); ++i) x.col(i) += (amount * random_direction(rng)).template cast<Real>();
  w.positions() = x;
}

// Deformed by 20% of the cell size at every particle and released (rigid mode, k = 1): the body returns to its
// rest shape up to a rigid motion, measured as the largest distance of a particle from the best rigid fit of the
// rest shape, over the box's diagonal. In double within 1e-5 (it reaches rounding); in float the fixed point is
// held only to the projection's rounding, each sweep moving particles by a few ulps of their coordinates
// (ε·0.5 m ≈ 3e-8 m), so the bound there is 1e-6.
TYPED_TEST(ShapeMatch, DeformedBoxReturnsToItsRestShape) {
  using Real = TypeParam;
  const double bound = sizeof(Real) == 8 ? 1e-5 : 1e-6;
  for (Solver s : kSolvers) {
    World<Real> w = box_body<Real>(Stiffness::pbd_k(1.0), 0.0, s, 4, s == Solver::jacobi ? 8 : 4);
    const Matrix3X<double> rest = box_mesh().positions;
    deform(w, 0.2 * kCell, 20240601u);
    const double before = rigid_residual(rest, positions_of(w)) / kDiagonal;
    for (int step = 0; step < 180; ++step) w.step();
    const Matrix3X<double> x = positions_of(w);
    ASSERT_TRUE(x.allFinite()) << name(s);
    const double after = rigid_residual(rest, x) / kDiagonal;
    const double violation = constraint_violations(w)[0].value.max;
    print_line("rest-shape", real_name<Real>(),
               "solver=" + std::string(name(s)) + " residual_before=" + fmt(before) + " residual_after=" + fmt(after) +
                   " max_violation_mm=" + fmt(violation * 1e3));
    EXPECT_GT(before, 0.01);
    EXPECT_LT(after, bound) << name(s);
  }
}

// ---- momentum ----

// A random cluster (rest offsets in a 2 m cube), uneven masses and a random deformed, rotated and moved copy of it:
// one projection, rigid (β = 0) and linear (β = 0.5, 1), PBD and XPBD. The correction's momentum Σ m_i Δx_i and
// angular momentum Σ m_i (x_i − x̄) × Δx_i, each over its scale (Σ m_i |Δx_i|, resp. × |x_i − x̄|), stay at
// rounding: Σ μ_i q̂_i = 0 and T·A_pqᵀ symmetric (the header's comment).
TYPED_TEST(ShapeMatch, OneProjectionKeepsMomentumAndAngularMomentum) {
  using Real = TypeParam;
  const double eps = std::numeric_limits<Real>::epsilon();
  std::mt19937 rng(7);
  for (double beta : {0.0, 0.5, 1.0}) {
    double worst_p = 0, worst_l = 0;
    for (int trial = 0; trial < 200; ++trial) {
      Cluster<Real> c = blank_constraint<Cluster<Real>>();
      constexpr auto offsets = Cluster<Real>::offsets();
      Vec3<Real> x[8];
      Real w[8];
      const Eigen::Matrix3d turn = Eigen::AngleAxisd(3.14159 * uniform(rng), random_direction(rng)).toRotationMatrix();
      const Vec3<double> shift = 10.0 * random_vector(rng);
      for (int i = 0; i < 8; ++i) {
        const Vec3<double> q = random_vector(rng);
        c.*offsets[i] = q.cast<Real>();
        x[i] = (turn * (q + 0.4 * random_vector(rng)) + shift).template cast<Real>();
        w[i] = Real(1.0 / (0.1 + uniform(rng) + 1.0));
      }
      c.beta = Real(beta);
      for (Real alpha_tilde : {Real(0), Real(0.3)}) {
        Vec3<Real> dp[8];
        Real dlambda;
        ASSERT_TRUE(correction(c, x, w, SolveCoefficients<Real>{Real(1), alpha_tilde}, Real(0.01), dp, dlambda));
        Vec3<double> centre = Vec3<double>::Zero();
        for (const auto& xi : x) centre += xi.template cast<double>() / 8.0;
        Vec3<double> p = Vec3<double>::Zero(), l = Vec3<double>::Zero();
        double p_scale = 0, l_scale = 0;
        for (int i = 0; i < 8; ++i) {
          const double m = 1.0 / double(w[i]);
          const Vec3<double> d = dp[i].template cast<double>(), r = x[i].template cast<double>() - centre;
          p += m * d;
          l += m * r.cross(d);
          p_scale += m * d.norm();
          l_scale += m * r.norm() * d.norm();
        }
        worst_p = std::max(worst_p, p.norm() / p_scale / eps);
        worst_l = std::max(worst_l, l.norm() / l_scale / eps);
      }
    }
    print_line("projection-momentum", real_name<Real>(),
               "beta=" + fmt(beta) + " max_momentum_over_scale_in_eps=" + fmt(worst_p) +
                   " max_angular_momentum_over_scale_in_eps=" + fmt(worst_l));
    EXPECT_LT(worst_p, 64.0) << "beta " << beta;
    EXPECT_LT(worst_l, 64.0) << "beta " << beta;
  }
}

// The box deformed and spinning at 5 rad/s about a tilted axis, no gravity, pins or contacts, XPBD (α = 1e-4 m/N),
// rigid and linear mode: momentum and angular momentum stay at their start values up to rounding (2·10⁴ rounding
// errors of the body's scale, as soft_body_test's free block). The velocity update also gives a free body back its
// angular momentum (engine/src/solve/free_bodies.hpp), so this checks the whole step; the check of the projection
// alone is the one above.
TYPED_TEST(ShapeMatch, FreeSpinningBodyKeepsItsMomentum) {
  using Real = TypeParam;
  for (double beta : {0.0, 0.5})
    for (Solver s : kSolvers) {
      World<Real> w = box_body<Real>(Stiffness::xpbd_compliance(1e-4), beta, s, 4, 3);
      deform(w, 0.2 * kCell, 99u);
      const Vec3<double> axis = Vec3<double>(1, 2, 3).normalized(), centre(0.2, 0.15, 0.15);
      Matrix3X<Real> v(3, w.num_particles());
      for (Index i = 0; i < w.num_particles(); ++i)
        v.col(i) = (5.0 * axis.cross(positions_of(w).col(i) - centre)).template cast<Real>();
      w.velocities() = v;
      const auto [p0, l0] = momenta(w);
      double max_dp = 0, max_dl = 0;
      for (int step = 0; step < 120; ++step) {
        w.step();
        const auto [p1, l1] = momenta(w);
        max_dp = std::max(max_dp, (p1 - p0).norm());
        max_dl = std::max(max_dl, (l1 - l0).norm());
      }
      double mass = 0;
      for (Index i = 0; i < w.num_particles(); ++i) mass += 1 / double(w.inverse_masses()[i]);
      const double speed = 5.0 * kDiagonal, eps = std::numeric_limits<Real>::epsilon();
      print_line("free-spin", real_name<Real>(),
                 "solver=" + std::string(name(s)) + " beta=" + fmt(beta) + " max_momentum_change=" + fmt(max_dp) +
                     " max_angular_momentum_change=" + fmt(max_dl) + " momentum_scale=" + fmt(mass * speed));
      EXPECT_TRUE(w.positions().allFinite());
      EXPECT_LE(max_dp, 2e4 * eps * mass * speed) << name(s);
      EXPECT_LE(max_dl, 2e4 * eps * mass * speed * kDiagonal) << name(s);
    }
}

// ---- threads ----

// The deformed box, XPBD so that λ is carried, in the linear mode: the same bits on 1–4 threads.
TYPED_TEST(ShapeMatch, SameBitsOnOneToFourThreads) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
    World<Real> w = box_body<Real>(Stiffness::xpbd_compliance(1e-5), 0.3, s, 2, 3);
    deform(w, 0.2 * kCell, 5u);
    ParallelConfig small;  // every loop cut small, so that the threads do share the work of 80 clusters
    small.inline_below = 4;
    small.min_grain = 4;
    w.set_parallel_config(small);
    const std::uint64_t one = run_on(w, 1, 20);
    for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(w, threads, 20), one) << name(s) << " threads " << threads;
  }
}

// ---- degenerate and reflected clusters ----

// Eight rest points in general position (a skewed, uneven box).
Matrix3X<double> general_rest() {
  Matrix3X<double> r(3, 8);
  r << 0.0, 1.0, 0.1, 1.2, -0.1, 0.9, 0.2, 1.1,  //
      0.0, 0.1, 0.8, 0.9, 0.1, 0.0, 1.0, 0.7,    //
      0.0, -0.1, 0.1, 0.0, 0.9, 1.0, 0.8, 1.2;
  return r;
}

// The rest shape turned and moved, then spoiled: "coplanar" (flattened onto a plane), "collinear" (onto a line),
// "point" (all at one point), "reflected" (mirrored through a plane).
Matrix3X<double> spoiled(const std::string& how) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(2.0, Vec3<double>(1, -1, 2).normalized()).toRotationMatrix();
  Matrix3X<double> x = (turn * general_rest()).colwise() + Vec3<double>(3, -2, 1);
  if (how == "coplanar") x.row(2).setConstant(0.5);
  if (how == "collinear") x.bottomRows(2).setConstant(0.5);
  if (how == "point") x.colwise() = Vec3<double>(3, -2, 1);
  if (how == "reflected") x.row(0) *= -1.0;
  return x;
}

// One cluster on rest points `rest` (offsets as measured: from their centroid).
template <class Real> Cluster<Real> cluster_on(const Matrix3X<double>& rest) {
  Cluster<Real> c = blank_constraint<Cluster<Real>>();
  constexpr auto offsets = Cluster<Real>::offsets();
  const Vec3<double> mean = rest.rowwise().mean();
  for (int i = 0; i < 8; ++i) {
    c.particles[std::size_t(i)] = Index(i);
    c.*offsets[std::size_t(i)] = (rest.col(i) - mean).cast<Real>();
  }
  return c;
}

// Each spoiled shape, unit and uneven masses, rigid and linear mode, projected directly (PBD, k = 0.5) 120 times:
// positions stay finite; in the rigid mode at unit masses C (rigid_rms: proper rotations only) falls by at least
// 1 − k per projection (the new fit can do no worse than the old goals, which the particles have come halfway to);
// and the largest distance from the rigid fit ends at rounding: the shape is a proper rotation of the rest shape,
// a mirrored one unmirrored. (The linear mode gets there more slowly: its goal follows the cluster's shear with
// weight β, so the shear shrinks by 1 − k(1 − β) = 0.75 per projection, where the rigid mode's falls by 1 − k.)
// The rotation's fast path (shape_match.hpp: newton_polar) gives the SVD's U Vᵀ to rounding wherever it applies:
// on every moderately deformed matrix (I plus noise) and on most random ones; it refuses reflected and flat ones,
// which go to the SVD (the next test).
TYPED_TEST(ShapeMatch, NewtonPolarFactorIsTheSvdsRotation) {
  using Real = TypeParam;
  using M = detail::shape_match::Mat3<Real>;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 1);
  const double tol = sizeof(Real) == 8 ? 1e-12 : 1e-5;
  int applied = 0;
  double worst = 0;
  for (int t = 0; t < 4000; ++t) {
    M a;
    for (int i = 0; i < 9; ++i) a(i) = Real(noise(rng));
    const bool mild = t % 2 == 0;
    if (mild) a = M::Identity() + Real(0.2) * a;
    M r;
    const bool ok = detail::shape_match::newton_polar(a, r);
    if (mild) {
      EXPECT_TRUE(ok) << t;
    }
    if (a.determinant() <= 0) {
      EXPECT_FALSE(ok) << t;
    }
    if (!ok) continue;
    ++applied;
    const Eigen::JacobiSVD<M> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
    worst = std::max(worst, double((r - svd.matrixU() * svd.matrixV().transpose()).norm()));
  }
  print_line("newton_polar", real_name<Real>(), "applied=" + std::to_string(applied) + " worst=" + fmt(worst));
  EXPECT_GT(applied, 2000);
  EXPECT_LT(worst, tol);
  M flat = M::Identity();
  flat(2, 2) = Real(0);
  M r;
  EXPECT_FALSE(detail::shape_match::newton_polar(flat, r));
}

TYPED_TEST(ShapeMatch, DegenerateAndReflectedClustersGoToAProperRotation) {
  using Real = TypeParam;
  const Matrix3X<double> rest = general_rest();
  const double tol = sizeof(Real) == 8 ? 1e-12 : 1e-5;
  for (const std::string how : {"coplanar", "collinear", "point", "reflected"})
    for (bool uneven : {false, true})
      for (double beta : {0.0, 0.5}) {
        Cluster<Real> c = cluster_on<Real>(rest);
        c.beta = Real(beta);
        const Matrix3X<double> start = spoiled(how);
        Vec3<Real> x[8];
        Real w[8];
        for (int i = 0; i < 8; ++i) {
          x[i] = start.col(i).cast<Real>();
          w[i] = uneven ? Real(1.0 / (1 + i % 3)) : Real(1);
        }
        const double first = rigid_residual(rest, start);
        double previous = first, rms = rigid_rms(rest, start);
        bool finite = true, falls = true;
        for (int it = 0; it < 120; ++it) {
          Vec3<Real> dp[8];
          Real dlambda;
          if (!correction(c, x, w, SolveCoefficients<Real>{Real(0.5), Real(0)}, Real(0), dp, dlambda)) break;
          Matrix3X<double> now(3, 8);
          for (int i = 0; i < 8; ++i) {
            x[i] += dp[i];
            finite = finite && x[i].allFinite();
            now.col(i) = x[i].template cast<double>();
          }
          const double now_rms = rigid_rms(rest, now);
          if (beta == 0.0 && !uneven) falls = falls && now_rms <= 0.5 * rms * (1 + 1e-9) + tol;
          rms = now_rms;
          previous = rigid_residual(rest, now);
        }
        print_line("degenerate", real_name<Real>(),
                   "shape=" + how + " uneven_masses=" + (uneven ? "1" : "0") + " beta=" + fmt(beta) +
                       " residual_start=" + fmt(first) + " residual_end=" + fmt(previous));
        EXPECT_TRUE(finite) << how;
        EXPECT_TRUE(falls) << how;
        EXPECT_GT(first, 0.1) << how;
        EXPECT_LT(previous, 2 * tol) << how << " uneven " << uneven << " beta " << beta;
      }
}

// The same spoiled shapes in a world, under every solver: one sub-step of one sweep at k = 1 puts the particles on
// their goals, a proper rotation of the rest shape.
TYPED_TEST(ShapeMatch, DegenerateClusterInAWorldIsMatchedByEverySolver) {
  using Real = TypeParam;
  const Matrix3X<double> rest = general_rest();
  const double tol = sizeof(Real) == 8 ? 1e-12 : 1e-5;
  for (const std::string how : {"coplanar", "collinear", "point", "reflected"})
    for (Solver s : kSolvers) {
      World<Real> w;
      w.add_particles(rest.cast<Real>(), VectorX<Real>::Constant(8, Real(1)));
      const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
      Cluster<Real> c = blank_constraint<Cluster<Real>>();
      for (int i = 0; i < 8; ++i) c.particles[std::size_t(i)] = Index(i);
      c.set = set;
      w.add(c, 0);
      StepParams<Real> p;
      p.gravity.setZero();
      p.solver = s;
      p.iterations = 1;
      w.set_params(p);
      w.positions() = spoiled(how).cast<Real>();
      w.step();
      const Matrix3X<double> x = positions_of(w);
      ASSERT_TRUE(x.allFinite()) << how << " " << name(s);
      EXPECT_LT(rigid_residual(rest, x), tol) << how << " " << name(s);
    }
}

// ---- compliance ----

// A cube of 8 particles of 0.1 kg at the corners of a 0.1 m cube, one cluster, its 4 bottom corners pinned, under
// gravity g, XPBD compliance α, damped to rest. By symmetry the fit's rotation stays I and the top corners sink by
// the same δ; the cluster's centre sinks by δ/2, so each corner is δ/2 from its goal, C = δ/2, and a top corner's
// share of the cluster's force, (m_i/M)·C/α with M = 8m (the pins weigh as the heaviest movable particle), carries
// its weight: δ = 2·M·α·g = 16·m·α·g, exactly (no linearization: C is linear in δ here). Every solver (one cluster:
// Jacobi's split masses are the masses), α over two decades; in double.
TEST(ShapeMatchCompliance, ClampedCubeSagsByTheClosedForm) {
  using Real = double;
  const double m = 0.1, a = 0.1, g = 9.81;
  for (double alpha : {2.5e-5, 1e-4, 4e-4})
    for (Solver s : kSolvers) {
      World<Real> w;
      Matrix3X<Real> corners(3, 8);
      VectorX<Real> masses(8);
      for (int i = 0; i < 8; ++i) {
        corners.col(i) = Vec3<Real>(a * (i & 1), a * ((i >> 1) & 1), a * ((i >> 2) & 1));
        masses[i] = i < 4 ? World<Real>::kPinned : m;  // i < 4: the bottom face z = 0
      }
      w.add_particles(corners, masses);
      Cluster<Real> c = blank_constraint<Cluster<Real>>();
      for (int i = 0; i < 8; ++i) c.particles[std::size_t(i)] = Index(i);
      c.set = w.add_constraint_set(Stiffness::xpbd_compliance(alpha));
      w.add(c, 0);
      StepParams<Real> p;
      p.gravity = Vec3<Real>(0, 0, -g);
      p.solver = s;
      p.substeps = 10;
      p.iterations = 10;
      p.damping = 5.0;
      w.set_params(p);
      for (int step = 0; step < 300; ++step) w.step();  // 5 s
      double sag = 0, lateral = 0;
      for (int i = 4; i < 8; ++i) {
        sag += (a - w.positions()(2, i)) / 4;
        lateral = std::max(lateral, (w.positions().col(i).head<2>() - corners.col(i).head<2>()).norm());
      }
      const double closed = 16 * m * alpha * g, error = sag / closed - 1;
      print_line("compliance", "double",
                 "solver=" + std::string(name(s)) + " alpha=" + fmt(alpha) + " sag=" + fmt(sag) +
                     " closed_form=" + fmt(closed) + " error=" + fmt(error) + " lateral=" + fmt(lateral));
      EXPECT_LT(std::abs(error), 1e-3) << name(s) << " alpha " << alpha;
      EXPECT_LT(lateral, 1e-9) << name(s);
    }
}

}  // namespace
}  // namespace pbd
