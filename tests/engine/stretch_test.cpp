// Stretch constraint: analytic projection, gradient, momentum, pinned particles, the coincident-particle guard.
#include "constraint_checks.hpp"
#include "pbd/constraints/stretch.hpp"

namespace pbd {
namespace {

template <class Real> class StretchTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(StretchTest, Precisions);

TYPED_TEST(StretchTest, OneProjectionRestoresRestLengthInverseMassWeighted) {
  using Real = TypeParam;
  // Particles 3 m apart on x, rest 1 m, masses 1 and 3 (w = 1, 1/3): C = 2, each moves w_i/(w0+w1)·C.
  Real p[6] = {0, 0, 0, 3, 0, 0};
  const Real w[2] = {1, Real(1) / 3};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  EXPECT_NEAR(p[0], 1.5, 1e-6);   // moved 2 · (1 / (4/3)) = 1.5 towards particle 1
  EXPECT_NEAR(p[3], 2.5, 1e-6);   // moved 2 · ((1/3) / (4/3)) = 0.5 towards particle 0
  EXPECT_NEAR(p[3] - p[0], 1.0, 1e-6);
  EXPECT_EQ(p[1], 0);
  EXPECT_EQ(p[4], 0);
}

TYPED_TEST(StretchTest, StiffnessScalesTheCorrection) {
  using Real = TypeParam;
  Real p[6] = {0, 0, 0, 0, 0, 2};
  const Real w[2] = {1, 1};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{Real(0.5), 0}, lambda);
  EXPECT_NEAR(p[5] - p[2], 1.5, 1e-6);  // half of the violation of 1 removed
}

TYPED_TEST(StretchTest, PinnedParticleNeverMoves) {
  using Real = TypeParam;
  Real p[6] = {0.25, -0.5, 1, 3, 0, 0};
  const Real w[2] = {0, 2};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  EXPECT_EQ(p[0], Real(0.25));
  EXPECT_EQ(p[1], Real(-0.5));
  EXPECT_EQ(p[2], Real(1));
  EXPECT_NEAR((Vec3<Real>(p[3], p[4], p[5]) - Vec3<Real>(p[0], p[1], p[2])).norm(), 1.0, 1e-6);
}

TYPED_TEST(StretchTest, BothPinnedMovesNothing) {
  using Real = TypeParam;
  Real p[6] = {0, 0, 0, 3, 0, 0};
  const Real w[2] = {0, 0};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  EXPECT_EQ(p[3], Real(3));
  EXPECT_EQ(lambda, Real(0));
}

// λ enters a correction only as α̃·λ, so it is accumulated only when α̃ ≠ 0 (PBD's stays 0: no solver streams it).
TYPED_TEST(StretchTest, LambdaIsAccumulatedOnlyUnderCompliance) {
  using Real = TypeParam;
  Real p[6] = {0, 0, 0, 3, 0, 0};  // C = 2, w = 1 and 1
  const Real w[2] = {1, 1};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  EXPECT_NEAR(p[3] - p[0], 1.0, 1e-6);  // PBD moved the particles...
  EXPECT_EQ(lambda, Real(0));           // ...and kept no λ
  Real q[6] = {0, 0, 0, 3, 0, 0};
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, q, w, SolveCoefficients<Real>{1, Real(0.5)}, lambda);
  EXPECT_NEAR(lambda, -0.8, 1e-6);  // XPBD: Δλ = −C / (w0 + w1 + α̃) = −2 / 2.5
  EXPECT_NEAR(q[3] - q[0], 3 - 1.6, 1e-6);
}

TYPED_TEST(StretchTest, CoincidentParticlesAreSkipped) {
  using Real = TypeParam;
  // Guard: no direction to push along, so nothing moves (and nothing becomes NaN).
  Real p[6] = {1, 2, 3, 1, 2, 3};
  const Real w[2] = {1, 1};
  Real lambda = 0;
  project(StretchConstraint<Real>{{0, 1}, 0, Real(1)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  for (Real v : p) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(p[0], Real(1));
  EXPECT_EQ(p[3], Real(1));
}

TEST(Stretch, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(1);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3<double> p[2] = {test::random_point<double>(rng), test::random_point<double>(rng)};
    checked += test::check_gradient(StretchConstraint<double>{{0, 1}, 0, 0.7}, p);
  }
  EXPECT_EQ(checked, 200);
}

TEST(Stretch, ConservesLinearMomentumWithEqualAndUnequalMasses) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> mass(0.01, 100.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3<double> p[2] = {test::random_point<double>(rng), test::random_point<double>(rng)};
    const double m = mass(rng);
    const double w[2] = {1.0 / m, trial % 2 ? 1.0 / m : 1.0 / mass(rng)};
    Vec3<double> dp[2];
    double dl;
    ASSERT_TRUE(correction(StretchConstraint<double>{{0, 1}, 0, 0.5}, p, w, SolveCoefficients<double>{1, 0}, 0.0,
                           dp, dl));
    EXPECT_LT(test::momentum_change(dp, w).norm(), 1e-9 * (1.0 + dp[0].norm() / w[0]));
  }
}

TEST(Stretch, XpbdWithZeroComplianceEqualsPbdWithUnitStiffness) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    double a[6], b[6];
    for (int i = 0; i < 6; ++i) a[i] = b[i] = std::uniform_real_distribution<double>(-1, 1)(rng);
    const double w[2] = {0.3, 1.7};
    double la = 0, lb = 0;
    const StretchConstraint<double> c{{0, 1}, 0, 0.4};
    project(c, a, w, coefficients<double>(Stiffness::pbd_k(1.0), 0.01, 5), la);
    project(c, b, w, coefficients<double>(Stiffness::xpbd_compliance(0.0), 0.01, 5), lb);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(a[i], b[i]);
  }
}

}  // namespace
}  // namespace pbd
