// Triangle area constraint: gradient, momentum, projection, and its guards (zero area, coincident, all pinned).
#include "constraint_checks.hpp"
#include "pbd/constraints/area.hpp"

namespace pbd {
namespace {

TEST(Area, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(21);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3<double> p[3] = {test::random_point<double>(rng), test::random_point<double>(rng),
                               test::random_point<double>(rng)};
    checked += test::check_gradient(AreaConstraint<double>{{0, 1, 2}, 0, 0.3}, p);
  }
  EXPECT_EQ(checked, 300);
}

TEST(Area, ConservesLinearMomentumWithEqualAndUnequalMasses) {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> mass(0.01, 100.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3<double> p[3] = {test::random_point<double>(rng), test::random_point<double>(rng),
                               test::random_point<double>(rng)};
    const double m = mass(rng);
    double w[3];
    for (double& wi : w) wi = trial % 2 ? 1.0 / m : 1.0 / mass(rng);
    Vec3<double> dp[3];
    double dl;
    ASSERT_TRUE(correction(AreaConstraint<double>{{0, 1, 2}, 0, 0.1}, p, w, SolveCoefficients<double>{1, 0}, 0.0, dp, dl));
    double scale = 0;
    for (int i = 0; i < 3; ++i) scale += dp[i].norm() / w[i];
    EXPECT_LT(test::momentum_change(dp, w).norm(), 1e-9 * (1.0 + scale));
  }
}

// The area constraint's own correction (area_math.hpp: the |∇_i C|² in closed form, ¼|v|², ¼|u|², ¼|v − u|²) is
// the generic correction of projection.hpp (which sums the norms of evaluate()'s gradients) up to rounding, for
// random triangles (sharp, obtuse, near-degenerate), masses, stiffness and compliance.
TEST(Area, ClosedFormCorrectionIsTheGenericOne) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(0.05, 5.0);
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Vec3<double> p[3] = {test::random_point<double>(rng), test::random_point<double>(rng),
                         test::random_point<double>(rng)};
    if (trial % 5 == 0) p[2] = p[0] + (1.0 + 1e-3 * u(rng)) * (p[1] - p[0]) + Vec3<double>(0, 0, 1e-4);  // thin
    const double w[3] = {trial % 7 ? u(rng) : 0.0, u(rng), u(rng)};
    const SolveCoefficients<double> coeff{u(rng) / 5.0, trial % 2 ? 0.0 : 1e-3 * u(rng)};
    const double lambda = trial % 2 ? 0.0 : 0.01 * u(rng);
    const AreaConstraint<double> c{{0, 1, 2}, 0, 0.2 * u(rng)};
    Vec3<double> dp[3], dp_generic[3];
    double dl = 0, dl_generic = 0;
    const bool ok = correction(c, p, w, coeff, lambda, dp, dl);
    // the generic correction (projection.hpp) from evaluate()'s gradients
    double C;
    Vec3<double> grad[3];
    bool ok_generic = evaluate(c, p, C, grad);
    double denom = coeff.alpha_tilde;
    for (int i = 0; ok_generic && i < 3; ++i) denom += w[i] * grad[i].squaredNorm();
    ok_generic = ok_generic && denom > 0;
    ASSERT_EQ(ok, ok_generic) << trial;
    if (!ok) continue;
    dl_generic = (-coeff.k * C - coeff.alpha_tilde * lambda) / denom;
    EXPECT_NEAR(dl, dl_generic, 1e-9 * (1.0 + std::abs(dl_generic))) << trial;
    for (int i = 0; i < 3; ++i) {
      dp_generic[i] = (w[i] * dl_generic) * grad[i];
      EXPECT_LT((dp[i] - dp_generic[i]).norm(), 1e-9 * (1.0 + dp_generic[i].norm())) << trial << " corner " << i;
    }
    ++compared;
  }
  EXPECT_GT(compared, 450);
}

template <class Real> class AreaTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(AreaTest, Precisions);

TYPED_TEST(AreaTest, ProjectionRestoresTheRestArea) {
  using Real = TypeParam;
  Real p[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};  // area 2
  const Real w[3] = {1, 1, Real(0.25)};
  for (int k = 0; k < 10; ++k) {
    Real lambda = 0;
    project(AreaConstraint<Real>{{0, 1, 2}, 0, Real(0.5)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  }
  const Vec3<Real> a(p[0], p[1], p[2]), b(p[3], p[4], p[5]), c(p[6], p[7], p[8]);
  EXPECT_NEAR(triangle_area(a, b, c), 0.5, 1e-5);
}

TYPED_TEST(AreaTest, ZeroAreaAndCoincidentTrianglesAreSkipped) {
  using Real = TypeParam;
  // Guard: collinear corners and coincident corners leave no normal to grow along: skipped, nothing NaN.
  for (const std::array<Real, 9>& start : {std::array<Real, 9>{0, 0, 0, 1, 0, 0, 3, 0, 0},
                                           std::array<Real, 9>{1, 1, 1, 1, 1, 1, 2, 0, 0},
                                           std::array<Real, 9>{1, 1, 1, 1, 1, 1, 1, 1, 1}}) {
    std::array<Real, 9> p = start;
    const Real w[3] = {1, 1, 1};
    Real lambda = 0;
    project(AreaConstraint<Real>{{0, 1, 2}, 0, Real(1)}, p.data(), w, SolveCoefficients<Real>{1, 0}, lambda);
    EXPECT_EQ(p, start);
  }
}

TYPED_TEST(AreaTest, AllPinnedMovesNothing) {
  using Real = TypeParam;
  std::array<Real, 9> p = {0, 0, 0, 2, 0, 0, 0, 2, 0};
  const auto start = p;
  const Real w[3] = {0, 0, 0};
  Real lambda = 0;
  project(AreaConstraint<Real>{{0, 1, 2}, 0, Real(0.5)}, p.data(), w, SolveCoefficients<Real>{1, 0}, lambda);
  EXPECT_EQ(p, start);
}

TYPED_TEST(AreaTest, TinyTriangleIsProjectedLikeALargeOne) {
  using Real = TypeParam;
  // Scale-free guard: a 1 mm triangle is not mistaken for a degenerate one.
  Real p[9] = {0, 0, 0, Real(2e-3), 0, 0, 0, Real(2e-3), 0};
  const Real w[3] = {1, 1, 1};
  for (int k = 0; k < 10; ++k) {
    Real lambda = 0;
    project(AreaConstraint<Real>{{0, 1, 2}, 0, Real(1e-6)}, p, w, SolveCoefficients<Real>{1, 0}, lambda);
  }
  const Vec3<Real> a(p[0], p[1], p[2]), b(p[3], p[4], p[5]), c(p[6], p[7], p[8]);
  EXPECT_NEAR(triangle_area(a, b, c) / Real(1e-6), 1.0, 1e-3);
}

}  // namespace
}  // namespace pbd
