// Hard cases: pbd keeps working (issue 7). Every case runs a fixed number of steps with the serial reference, the
// colored solver on 1 and 2 threads and Jacobi, in float and in double, and checks after every step that positions
// and velocities are finite; then it checks the kinetic energy, the stretch and the end state against bounds stated
// with their reasons. Each (case, solver, precision) prints one line
//   STABILITY case=... solver=... real=... steps=... max_stretch=... max_ke=... energy_gain=... end=...
// (`engine_tests --gtest_filter='Stability*'` or `ctest -R Stability -V`). Scene builders: stability_cases.hpp.
//
// Bounds used by several cases:
//  - energy:  gravity is the only source of energy in cases 1, 2, 3a, 6, 7 and 8 (after landing): the symplectic
//             Euler prediction does not create any (a free fall loses ½ m g² h² per sub-step), nor do projections
//             onto constraints that start satisfied and can all be satisfied at once (collisions only take velocity
//             away), so the total (kinetic + gravitational) energy must never exceed its initial value
//             (+ energy_tolerance: rounding of the state). Constraints in permanent conflict are another matter: see
//             the known failures at the end.
//  - blow-up: where the solver turns stored constraint error into velocity by design (a collapsed cloth springing
//             open, a squashed ball re-inflating, a pressure target), no energy budget exists; the bound is then that
//             no particle crosses the region the body can occupy (diameter D) within one sub-step: KE ≤ ½ M (D/h)².
//  - stretch: swing_stretch_bound (6 × the steady sag stretch of few-sweep PBD, from the momentum balance at the
//             pins: stability_cases.hpp) where a body swings from rest lengths; the geometric D / rest − 1 where it
//             starts collapsed.
//  - at rest: with velocity damping d, a swinging body's energy decays as e^(−2 d ⟨KE⟩/E · t); it swings with at
//             least a quarter of its energy kinetic on average (half for a harmonic swing), so its kinetic energy
//             at the end is at most the peak's × e^(−d (T − t_peak) / 2).
#include "stability_cases.hpp"
#include "world_access.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace pbd {
namespace {
using namespace stability;

template <class Real> class Stability : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Stability, Precisions);

constexpr double kPi = 3.14159265358979323846;

template <class Real> constexpr double eps() { return double(std::numeric_limits<Real>::epsilon()); }

// The "at rest" bound above (the world's damping and step; peak and end from the run).
template <class Real> double settled_ke_bound(const World<Real>& w, const Figures& f) {
  const double elapsed = double(f.steps - 1 - f.peak_step) * double(w.params().dt);
  return f.max_ke * std::exp(-double(w.params().damping) * elapsed / 2.0);
}

// The blow-up bound above for a body of movable mass M that stays within a region of diameter D.
template <class Real> double blowup_ke_bound(const World<Real>& w, double diameter) {
  const double h = double(w.params().dt) / w.params().substeps;
  return 0.5 * movable_mass(w) * (diameter / h) * (diameter / h);
}

// Kinetic energy a body keeps from rounding alone: a step rounds each coordinate of a particle at most some 64 times
// (the prediction, one addition per projection touching it — at most ~18 per sweep in these meshes — in 2 sweeps, the
// velocity update; ½ ulp each), so rounding can leave it moving at up to 64 ulp(x)/h.
template <class Real> double rounding_ke(const World<Real>& w, double extent) {
  const double ulp = eps<Real>() * extent;
  const double v = 64.0 * ulp / (double(w.params().dt) / w.params().substeps);
  return 0.5 * movable_mass(w) * v * v;
}

template <class Real> std::vector<Real> state_of(const World<Real>& w) {
  std::vector<Real> s(w.positions().data(), w.positions().data() + w.positions().size());
  s.insert(s.end(), w.velocities().data(), w.velocities().data() + w.velocities().size());
  return s;
}

// ---- 1. A rope with a 1000:1 heavy end, 4 sweeps, 1 and 8 sub-steps -------------------------------------------

TYPED_TEST(Stability, HeavyEndRope) {
  using Real = TypeParam;
  for (int substeps : {1, 8})
    for (const SolverRun& run : kSolverRuns) {
      World<Real> w = heavy_rope<Real>(20, 4, substeps);
      const double tol_e = energy_tolerance(w);
      const Index end = w.num_particles() - 1;
      const Figures f = simulate(w, run, 600);  // 10 s
      const std::string name = substeps == 1 ? "rope-1000-1sub" : "rope-1000-8sub";
      // End state: at rest, hanging below the pin (0, 0, 2) at the sag the momentum balance predicts.
      const double sag = sag_stretch(w);
      const double depth = 2.0 - double(w.positions()(2, end));
      const double off = std::hypot(double(w.positions()(0, end)), double(w.positions()(1, end)));
      print_line<Real>(name, run, f,
                       "depth=" + fmt(depth) + ",predicted=" + fmt(1.0 + sag) + ",offset=" + fmt(off) +
                           ",end_ke=" + fmt(f.end.kinetic));
      const std::string what = name + " " + run.label;
      ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
      EXPECT_LE(f.max_energy_gain, tol_e) << what;
      EXPECT_LE(f.max_stretch, swing_stretch_bound(w)) << what;
      // Jacobi at 1 sub-step is far from converged (4 sweeps over 20 links, the end 1000× heavier): with split
      // masses the heavy end gets half the correction it would get from Gauss-Seidel, and at 10 s it still bounces
      // at 45 m below the pin (KE 1.0 kJ, 5% of its peak; it was 27 m when Jacobi averaged full corrections, which
      // got XPBD's λ wrong). The end-state checks below are for the runs that settle.
      if (run.solver == Solver::jacobi && substeps == 1) continue;
      EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
      // The hanging depth is the rope's length stretched by the sag: L (1 + s), L = 1 m. The model makes every link
      // as stretched as the pinned one at the moment of its projection; links settle back a little between
      // projections, so it is a first-order prediction: ±25%.
      // Not for Jacobi: with split masses the heavy end's own link is divided by its light neighbour's count as well
      // (it was not when Jacobi averaged full corrections), which this model leaves out; Jacobi hangs 1.7-1.9x
      // deeper than it predicts, within the stretch bound checked above.
      if (run.solver != Solver::jacobi) {
        EXPECT_NEAR(depth, 1.0 + sag, 0.25 * (1.0 + sag)) << what;
      }
      // Straight below the pin, within 3°: the at-rest check above says the swing from 90° has died down; 3° leaves
      // room for the slow sideways sway that the stretchy rope's vertical bounce feeds.
      EXPECT_LE(off, std::tan(3.0 * kPi / 180.0) * depth) << what;
    }
}

// ---- 2. Very stiff cloth (k = 1, and XPBD α = 0) at dt = 1/30 s with 2 sweeps -----------------------------------

TYPED_TEST(Stability, StiffClothAtLargeStep) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = stiff_cloth<Real>(16, Stiffness::pbd_k(1.0), Real(1));
    World<Real> xpbd = stiff_cloth<Real>(16, Stiffness::xpbd_compliance(0.0), Real(1));
    const double tol_e = energy_tolerance(w);
    const Figures f = simulate(w, run, 300);  // 10 s
    const Figures fx = simulate(xpbd, run, 300);
    print_line<Real>("stiff-cloth-k1", run, f,
                     "end_stretch=" + fmt(max_relative_stretch(w)) + ",sag=" + fmt(sag_stretch(w)) +
                         ",end_ke=" + fmt(f.end.kinetic));
    print_line<Real>("stiff-cloth-xpbd0", run, fx,
                     "end_stretch=" + fmt(max_relative_stretch(xpbd)) + ",end_ke=" + fmt(fx.end.kinetic));
    const std::string what = std::string("stiff cloth ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // XPBD with α = 0 is k = 1 with α̃ = 0: the same projection, so the same bits.
    EXPECT_TRUE(state_of(w) == state_of(xpbd)) << what << ": XPBD α = 0 differs from PBD k = 1";
    EXPECT_LE(f.max_energy_gain, tol_e) << what;
    EXPECT_LE(f.max_stretch, swing_stretch_bound(w)) << what;
    // At rest at the end. The colored solver's limit cycle stays under this bound over these 10 s, not over 100 s:
    // see DISABLED_StiffClothComesToRestOverALongRun.
    EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
  }
}

// ---- 3. Zero-length rest edges and coincident particles ---------------------------------------------------------

TYPED_TEST(Stability, WeldedRopeWithZeroLengthEdgesAndCoincidentParticles) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    std::vector<Index> welds;
    World<Real> w = welded_rope<Real>(10, 0.1, &welds);
    const double tol_e = energy_tolerance(w);
    auto gap = [&](const World<Real>& w) {
      double g = 0.0;
      for (Index k : welds) g = std::max(g, violation(test::stretch_of(w)[k], w.positions()));  // metres
      return g;
    };
    double max_gap = 0.0;
    const Figures f = simulate(w, run, 600, [&](const World<Real>& w, int) { max_gap = std::max(max_gap, gap(w)); });
    const Index last = w.num_particles() - 1;
    const double depth = 2.0 - double(w.positions()(2, last));
    const double off = std::hypot(double(w.positions()(0, last)), double(w.positions()(1, last)));
    print_line<Real>("welded-rope", run, f,
                     "max_weld_gap=" + fmt(max_gap) + ",end_weld_gap=" + fmt(gap(w)) + ",depth=" + fmt(depth) +
                         ",end_ke=" + fmt(f.end.kinetic));
    const std::string what = std::string("welded rope ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // Links start at rest length and welds closed (coincident, satisfied): no stored error, gravity only.
    EXPECT_LE(f.max_energy_gain, tol_e) << what;
    const double bound = swing_stretch_bound(w);
    EXPECT_LE(f.max_stretch, bound) << what;
    // A weld is a link of the chain with rest 0: it carries the same load, so its gap obeys the links' bound in
    // metres (bound × the 0.1 m link length).
    EXPECT_LE(max_gap, bound * 0.1) << what;
    // End: at rest, straight below the pin (within 3°, as the rope of case 1), 1 m of links long plus the sag.
    EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
    EXPECT_LE(off, std::tan(3.0 * kPi / 180.0) * depth) << what;
    // Links under tension are not shorter than at rest: at least 1 m of rope times cos 3°.
    EXPECT_GE(depth, std::cos(3.0 * kPi / 180.0)) << what << ": shorter than its links";
    EXPECT_LE(depth, 1.0 + bound) << what;
  }
}

TYPED_TEST(Stability, CollapsedClothUnfolds) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = collapsed_cloth<Real>(12);
    const std::array<Eigen::Vector3d, 2> pins = {Eigen::Vector3d(0, 1, 2), Eigen::Vector3d(1, 1, 2)};
    double reach = 0.0;  // largest distance of a particle from its nearer pin
    const Figures f = simulate(w, run, 600, [&](const World<Real>& w, int) {
      for (Index i = 0; i < w.num_particles(); ++i) {
        const Eigen::Vector3d x = w.positions().col(i).template cast<double>();
        reach = std::max(reach, std::min((x - pins[0]).norm(), (x - pins[1]).norm()));
      }
    });
    double min_ratio = 1e300;  // shortest edge over its rest length: no pair may stay coincident
    for (const auto& c : test::stretch_of(w))
      min_ratio = std::min(min_ratio, (w.positions().col(c.particles[0]) - w.positions().col(c.particles[1]))
                                              .template cast<double>().norm() / double(c.rest));
    print_line<Real>("collapsed-cloth", run, f,
                     "reach=" + fmt(reach) + ",end_stretch=" + fmt(max_relative_stretch(w)) +
                         ",min_edge_ratio=" + fmt(min_ratio) + ",end_ke=" + fmt(f.end.kinetic));
    const std::string what = std::string("collapsed cloth ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // Geometry: every particle is joined to a pin by a path of rest_reach metres of rest length, so it stays within
    // R = rest_reach (1 + s) of a pin, s the static stretch bound; the two balls around the pins 1 m apart fit in a
    // region of diameter D = 1 + 2R.
    const double s = swing_stretch_bound(w);
    const double R = rest_reach(w) * (1.0 + s), D = 1.0 + 2.0 * R;
    EXPECT_LE(reach, R) << what;
    EXPECT_LE(f.max_ke, blowup_ke_bound(w, D)) << what;
    EXPECT_LE(f.max_stretch, D / min_rest_length(w) - 1.0) << what << ": an edge longer than the region";
    // End: the cloth hangs at rest like a cloth released flat (which may fold differently, so no positions are
    // compared): nothing coincident is left (every edge ≥ half its rest length), the sag within the static bound.
    EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
    EXPECT_GE(min_ratio, 0.5) << what;
    EXPECT_LE(max_relative_stretch(w), s) << what;
  }
}

// ---- 4. Zero-area triangles and collinear bending pairs ---------------------------------------------------------

TYPED_TEST(Stability, ClothSquashedOntoALineUnfolds) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = line_cloth<Real>(10);
    const Figures f = simulate(w, run, 600);
    double min_area = 1e300;  // smallest triangle area over its rest area at the end
    for (const auto& c : test::area_of(w)) {
      const double a = triangle_area<double>(w.positions().col(c.particles[0]).template cast<double>(),
                                             w.positions().col(c.particles[1]).template cast<double>(),
                                             w.positions().col(c.particles[2]).template cast<double>());
      min_area = std::min(min_area, a / double(c.rest));
    }
    double max_bend = 0.0;  // largest bending error at the end, radians (degenerate pairs are not measured)
    for (const auto& c : test::bending_of(w)) max_bend = std::max(max_bend, violation(c, w.positions()));
    print_line<Real>("line-cloth", run, f,
                     "end_stretch=" + fmt(max_relative_stretch(w)) + ",min_area_ratio=" + fmt(min_area) +
                         ",max_bend=" + fmt(max_bend) + ",end_ke=" + fmt(f.end.kinetic));
    const std::string what = std::string("line cloth ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // Same geometry as the collapsed cloth (the same 1 m cloth and pins).
    const double s = swing_stretch_bound(w);
    const double D = 1.0 + 2.0 * rest_reach(w) * (1.0 + s);
    EXPECT_LE(f.max_ke, blowup_ke_bound(w, D)) << what;
    EXPECT_LE(f.max_stretch, D / min_rest_length(w) - 1.0) << what;
    // End: at rest, every triangle open again (at least a tenth of its rest area; all started at zero), hanging
    // within the static sag bound.
    EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
    EXPECT_GE(min_area, 0.1) << what;
    EXPECT_LE(max_relative_stretch(w), s) << what;
  }
}

// ---- 5. A closed mesh squashed flat, and inflated to 10× --------------------------------------------------------

TYPED_TEST(Stability, BallSquashedFlatRecovers) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = volume_ball<Real>(1, {}, 1e-4);
    const double rest = w.volumes().items[0].rest;
    w.positions().row(2).setZero();  // every vertex on the plane z = 0 (the top and bottom halves coincide)
    const Figures f = simulate(w, run, 240);  // 4 s
    const double ratio = six_volume_of(w) / rest;
    print_line<Real>("squashed-ball", run, f,
                     "end_volume_ratio=" + fmt(ratio) + ",end_stretch=" + fmt(max_relative_stretch(w)) +
                         ",end_ke=" + fmt(f.end.kinetic));
    const std::string what = std::string("squashed ball ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // The volume pushes the surface back out toward its rest shape and it may overshoot; a part of it beyond twice
    // the rest diameter (D = 2 m) would be an explosion: the blow-up bounds with that D.
    const double D = 2.0;
    EXPECT_LE(f.max_ke, blowup_ke_bound(w, D)) << what;
    EXPECT_LE(f.max_stretch, D / min_rest_length(w) - 1.0) << what << ": an edge longer than the region";
    // End: the rest sphere satisfies every constraint (target = rest volume) and damping brings it there: volume
    // within 1% (the volume is projected with k = 1 in every sweep), every edge within 5% of its rest length (the
    // rest shape is recovered, not just its volume), at rest.
    EXPECT_NEAR(ratio, 1.0, 0.01) << what;
    EXPECT_LE(max_relative_stretch(w), 0.05) << what;
    EXPECT_LE(f.end.kinetic, settled_ke_bound(w, f)) << what;
  }
}

TYPED_TEST(Stability, BallInflatedTenfold) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = volume_ball<Real>(2, {1.0, 10.0, 1.0}, 1e-3);  // target 1× → 10× over 1 s, then held
    const double rest = w.volumes().items[0].rest;
    double area0 = 0.0;
    for (const auto& t : w.volumes().triangles)
      area0 += triangle_area<double>(w.positions().col(t[0]).template cast<double>(),
                                     w.positions().col(t[1]).template cast<double>(),
                                     w.positions().col(t[2]).template cast<double>());
    const double q = std::pow(area0, 1.5) / (6.0 * std::sqrt(kPi) * rest / 6.0);
    double worst = 0.0;  // worst relative volume error over the last second
    const Figures f = simulate(w, run, 180, [&](const World<Real>& w, int s) {
      if (s >= 120) worst = std::max(worst, std::abs(six_volume_of(w) / (10.0 * rest) - 1.0));
    });
    const double ratio = six_volume_of(w) / rest;
    print_line<Real>("inflate-10x", run, f,
                     "end_volume_ratio=" + fmt(ratio) + ",worst_last_s=" + fmt(worst) +
                         ",end_stretch=" + fmt(max_relative_stretch(w)) + ",stretch_needed=" +
                         fmt(std::cbrt(ratio / q) - 1.0) + ",end_ke=" + fmt(f.end.kinetic));
    const std::string what = std::string("inflated ball ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // Every solver projects the volume in place after the other constraints in every sweep (Jacobi too), with
    // k = 1: within 1% of 10× (as volume_test at 3×).
    EXPECT_LE(worst, 0.01) << what;
    // Holding the volume it reached (ratio × V0) needs some edge stretched by at least (ratio / q)^(1/3) − 1: with
    // every edge at most (1 + s) times its rest length, each (acute) triangle's area grows at most (1 + s)², and the
    // isoperimetric inequality V ≤ A^(3/2) / (6√π) gives ratio V0 ≤ (1 + s)³ q V0, q = A0^(3/2) / (6√π V0) the rest
    // mesh's isoperimetric quotient (1 for a sphere).
    // Upward we allow twice the uniform stretch 10^(1/3) − 1 = 1.154: faces bulge between vertices (and Gauss-Seidel's
    // old spin, see InflatedBallComesToRest, stretched it further); beyond that a region would be tearing open.
    const double uniform = std::cbrt(10.0) - 1.0;
    EXPECT_GE(max_relative_stretch(w), std::cbrt(ratio / q) - 1.0) << what;
    EXPECT_LE(f.max_stretch, 2.0 * uniform) << what;
    // No energy budget (a pressure target): the blow-up bound with the inflated ball's diameter, 2 × 0.5 × 10^(1/3)
    // stretched by the same factor 2.
    EXPECT_LE(f.max_ke, blowup_ke_bound(w, 2.0 * 0.5 * std::cbrt(10.0) * 2.0)) << what;
    // It also comes to rest: see InflatedBallComesToRest.
  }
}

// ---- 6. Fast particles hitting a plane and a small sphere -------------------------------------------------------

TYPED_TEST(Stability, FastParticlesNeverCrossThePlaneOrTheSphere) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = fast_particles<Real>(11, 100);
    const double tol_e = energy_tolerance(w);
    const Eigen::Vector3d n = w.colliders().planes[0].normal.template cast<double>();
    const double offset = double(w.colliders().planes[0].offset);
    const Eigen::Vector3d c = w.colliders().spheres[0].center.template cast<double>();
    const double r = double(w.colliders().spheres[0].radius);
    Matrix3X<Real> before = w.positions();
    // Signed distances in units of the rounding of the coordinates involved: a projection onto a plane (the ground,
    // or the sphere's tangent plane at the entry point) leaves the point on it up to a few ulps of |x|.
    double plane_ulps = 1e300, sphere_ulps = 1e300, path_ulps = 1e300;
    std::size_t sphere_contacts = 0;
    const Figures f = simulate(w, run, 60, [&](const World<Real>& w, int) {
      const auto x = w.positions();
      for (Index i = 0; i < w.num_particles(); ++i) {
        const Eigen::Vector3d p = x.col(i).template cast<double>(), q = before.col(i).template cast<double>();
        const double ulp = eps<Real>() * (p.norm() + q.norm() + c.norm() + r + std::abs(offset));
        plane_ulps = std::min(plane_ulps, (n.dot(p) - offset) / ulp);
        sphere_ulps = std::min(sphere_ulps, ((p - c).norm() - r) / ulp);
        // The step's path q → p must not pass through the ball either (tunnelling leaves p outside).
        const Eigen::Vector3d d = p - q;
        const double t = d.squaredNorm() > 0.0 ? std::clamp((c - q).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
        path_ulps = std::min(path_ulps, ((q + t * d - c).norm() - r) / ulp);
      }
      for (const auto& k : w.last_collisions()) sphere_contacts += k.normal.template cast<double>().dot(n) < 0.999;
      before = x;
    });
    print_line<Real>("fast-particles", run, f,
                     "min_plane_ulps=" + fmt(plane_ulps) + ",min_sphere_ulps=" + fmt(sphere_ulps) +
                         ",min_path_ulps=" + fmt(path_ulps) + ",sphere_contacts=" + std::to_string(sphere_contacts));
    const std::string what = std::string("fast particles ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    EXPECT_GT(sphere_contacts, 0u) << what << ": the case must hit the sphere";
    EXPECT_GE(plane_ulps, -4.0) << what << ": a particle behind the plane";
    EXPECT_GE(sphere_ulps, -4.0) << what << ": a particle inside the sphere";
    EXPECT_GE(path_ulps, -4.0) << what << ": a particle tunnelled through the sphere";
    // Contacts only take velocity away (the projection onto a half-space containing x shortens p − x).
    EXPECT_LE(f.max_energy_gain, tol_e) << what;
  }
}

// ---- 7. Everything pinned; constraints between pinned particles -------------------------------------------------

TYPED_TEST(Stability, AllPinnedNothingMoves) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = all_pinned<Real>();
    const std::vector<Real> x0(w.positions().data(), w.positions().data() + w.positions().size());
    const Figures f = simulate(w, run, 100);
    const bool same = std::memcmp(x0.data(), w.positions().data(), x0.size() * sizeof(Real)) == 0;
    const bool still = (w.velocities().array() == Real(0)).all();
    print_line<Real>("all-pinned", run, f,
                     std::string("positions_bitwise_unchanged=") + (same ? "yes" : "no") +
                         ",velocities_zero=" + (still ? "yes" : "no"));
    const std::string what = std::string("all pinned ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    EXPECT_TRUE(same) << what;
    EXPECT_TRUE(still) << what;
  }
}

TYPED_TEST(Stability, ConstraintBetweenTwoPinnedParticlesChangesNothing) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = cloth_with_pinned_pair<Real>(8, true), ref = cloth_with_pinned_pair<Real>(8, false);
    const Index p0 = 7 * 8, p1 = 8 * 8 - 1;
    const Vec3<Real> x0 = w.positions().col(p0), x1 = w.positions().col(p1);
    const double tol_e = energy_tolerance(w);
    const Figures f = simulate(w, run, 120);
    simulate(ref, run, 120);
    const Violation d = position_distance(w, Matrix3X<double>(ref.positions().template cast<double>()));
    print_line<Real>("pinned-pair", run, f, "distance_to_cloth_without_pair=" + fmt(d.max));
    const std::string what = std::string("pinned pair ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    EXPECT_TRUE(w.positions().col(p0) == x0 && w.positions().col(p1) == x1) << what << ": a pinned corner moved";
    EXPECT_LE(f.max_energy_gain, tol_e) << what;
    EXPECT_LE(f.max_stretch, swing_stretch_bound(w)) << what;
    // The pinned pair's constraints never move anything: serial (insertion order) gives the same bits as the cloth
    // without them; Jacobi the same up to the summation order of its per-particle sums (rounding); the colored solver
    // colors the pair with the rest, so it may project the cloth in another order: both orders leave every link
    // within the stretch bound, so positions agree within it summed along the longest rest path from a pin.
    if (run.solver == Solver::serial) {
      EXPECT_EQ(d.max, 0.0) << what;
    } else if (run.solver == Solver::jacobi) {
      EXPECT_LE(d.max, 1e3 * eps<Real>()) << what;
    } else {
      EXPECT_LE(d.max, swing_stretch_bound(w) * rest_reach(w)) << what;
    }
  }
}

// ---- 8. 10^5 steps of a cloth at rest on the ground -------------------------------------------------------------

TYPED_TEST(Stability, ClothRestingOnTheGroundFor100kSteps) {
  using Real = TypeParam;
  constexpr int kSteps = 100000, kEarly = 1000;  // by step 1000 (17 s) the cloth has landed and flattened out
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = resting_cloth<Real>(4, 0.5, false);
    const Eigen::Vector3d c0 = centroid(w);
    Eigen::Vector3d c_early = c0, c_1e4 = c0;
    double e_early = 0.0, max_e_after = -1e300, min_z = 1e300;
    // Colors and particle loops run with the default cut (inline for so small a cloth): the same bits as any other
    // cut (solver_test), and 10^5 steps stay fast.
    const Figures f = simulate(
        w, run, kSteps,
        [&](const World<Real>& w, int s) {
          if (s + 1 < kEarly) return;
          const double e = energy(w).total();
          if (s + 1 == kEarly) {
            e_early = e;
            c_early = centroid(w);
          }
          if (s + 1 == kEarly + 10000) c_1e4 = centroid(w);
          max_e_after = std::max(max_e_after, e);
          min_z = std::min(min_z, double(w.positions().row(2).minCoeff()));
        },
        ParallelConfig{});
    const Eigen::Vector3d c = centroid(w);
    const double drift = std::hypot(c.x() - c0.x(), c.y() - c0.y());
    const double drift_1e4 = std::hypot(c_1e4.x() - c_early.x(), c_1e4.y() - c_early.y());
    const double ke_early = f.ke.size() >= std::size_t(kEarly) ? f.ke[kEarly - 1] : std::nan("");
    print_line<Real>("resting-cloth-1e5", run, f,
                     "ke_at_1000=" + fmt(ke_early) + ",ke_end=" + fmt(f.end.kinetic) +
                         ",max_ke_last_half=" + fmt(f.max_ke_in(kSteps / 2, kSteps)) + ",drift=" + fmt(drift) +
                         ",drift_1e4_after_landing=" + fmt(drift_1e4) +
                         ",min_z=" + fmt(min_z));
    const std::string what = std::string("resting cloth ") + run.label;
    ASSERT_TRUE(f.finite()) << what << ": not finite after step " << f.first_nonfinite;
    // The crumpled start stores constraint error that the landing turns into motion (the blow-up bound, with the
    // 0.5 m cloth's region doubled); from step 1000 on gravity is the only source, so no creep: the total energy never
    // exceeds its value at step 1000, and the kinetic energy at the end and over the whole second half stays at most
    // what it was at step 1000 plus what rounding alone keeps it moving with.
    EXPECT_LE(f.max_ke, blowup_ke_bound(w, 2.0 * 0.5 * std::sqrt(2.0))) << what;
    EXPECT_LE(max_e_after, e_early + energy_tolerance(w)) << what;
    EXPECT_LE(f.end.kinetic, ke_early + rounding_ke(w, 1.0)) << what;
    EXPECT_LE(f.max_ke_in(kSteps / 2, kSteps), ke_early + rounding_ke(w, 1.0)) << what;
    // No drift. Every projection conserves horizontal momentum (Jacobi's too, with split masses; contacts push
    // along z), the cloth was dropped with none, so only rounding moves its centroid: at most the rounding speed of
    // rounding_ke (64 ulp of 1 m per step) at every step; and over the 10^4 steps after landing, under 1 mm (the
    // velocity update keeps a velocity no constraint changed, so damping stops what rounding starts).
    EXPECT_LE(drift, kSteps * 64.0 * eps<Real>() * 1.0) << what;
    EXPECT_LE(drift_1e4, 1e-3) << what;
    // Contacts come last in every sweep, in place under every solver (Jacobi too), so they hold up to rounding;
    // the requirement is a tenth of the collision margin.
    const double depth = 0.1 * double(w.params().collision_margin);
    EXPECT_GE(min_z, -depth) << what;
  }
}

// ---- 9. Conflicting constraints on a body nothing holds: no spin-up ---------------------------------------------

// The inflated ball of case 5 (a hard volume at 10× fighting stiff stretch, nothing else touching it) comes to rest
// after the ramp. Gauss-Seidel used to spin it up (rigid rotation at ~36 rad/s, ~500 J, for good): the conflicting
// projections are central about the positions they read, not about the start of the sub-step, and the fixed order
// turned that into a torque. The velocity update now gives a free body back the angular momentum the solve changed
// (engine/src/solve/free_bodies.hpp); end KE ~2e-6 J under Gauss-Seidel.
TYPED_TEST(Stability, InflatedBallComesToRest) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = volume_ball<Real>(2, {1.0, 10.0, 1.0}, 1e-3);
    const Figures f = simulate(w, run, 600);  // 10 s, target held from 1 s on
    print_line<Real>("inflate-10x-10s", run, f, "end_ke=" + fmt(f.end.kinetic));
    // After the ramp the ball should settle: its kinetic energy decays at least as the damping's e^(−d t / 2) from
    // the largest it had during the ramp.
    const double ramp_peak = f.max_ke_in(0, 60);
    EXPECT_LE(f.end.kinetic, ramp_peak * std::exp(-double(w.params().damping) * 9.0 / 2.0)) << run.label;
  }
}

// A cloth whose rest lengths come from a wrinkled shape (no flat embedding satisfies them) lying flat on the
// ground, undamped. Gauss-Seidel used to turn the conflict into a rigid spin about the vertical that grew for the
// whole run (serial: KE from 4e-8 J at step 1000 to 1.7e-4 J at 10^5). Contacts with the ground all push along +z,
// so they exert no torque about the vertical: the velocity update gives the cloth back its angular momentum about z
// and its horizontal momentum, which the solve changed (free_bodies.hpp); its KE now stays at rounding level.
TYPED_TEST(Stability, PrestressedClothRestingOnTheGroundDoesNotSpinUp) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = resting_cloth<Real>(8, 0.5, true);
    const Figures f = simulate(w, run, 100000, [](const World<Real>&, int) {}, ParallelConfig{});
    const double ke_early = f.ke.size() >= 1000 ? f.ke[999] : std::nan("");
    print_line<Real>("prestressed-cloth-1e5", run, f, "ke_at_1000=" + fmt(ke_early) + ",end_ke=" + fmt(f.end.kinetic));
    ASSERT_TRUE(f.finite()) << run.label;
    EXPECT_LE(f.end.kinetic, ke_early + rounding_ke(w, 1.0)) << run.label;
  }
}

// ---- Known failure (run with --gtest_also_run_disabled_tests) ---------------------------------------------------
// A hard case where a solver keeps working (finite, bounded) but does not reach the right end state; measured in
// docs/robustness.md.

// The colored order keeps the stiff cloth of case 2 (pinned at two corners, 1/30 s steps of 2 sweeps) in a limit
// cycle near its free corner instead of letting damping bring it to rest: KE 5.6e-3 J at 100 s for good, 0.1% of
// the fall's peak, in float and double (serial 5e-12 J, Jacobi 3e-11 J). The serial solver given the same
// constraints in the colored order does the same, so it is the order, not the parallel code; the symmetric sweep
// order makes it worse (serial 0.54 J, colored 1.4 J: alternating orders never agree on an unconverged state), and
// the body is held by its pins, so no momentum argument applies.
TYPED_TEST(Stability, DISABLED_StiffClothComesToRestOverALongRun) {
  using Real = TypeParam;
  for (const SolverRun& run : kSolverRuns) {
    World<Real> w = stiff_cloth<Real>(16, Stiffness::pbd_k(1.0), Real(1));
    const Figures f = simulate(w, run, 3000);  // 100 s
    print_line<Real>("stiff-cloth-100s", run, f, "end_ke=" + fmt(f.end.kinetic));
    EXPECT_LE(f.end.kinetic, std::max(settled_ke_bound(w, f), rounding_ke(w, 10.0))) << run.label;
  }
}

}  // namespace
}  // namespace pbd
