// Dihedral bending constraint: gradient, momentum, the rest angle, and its guards (collinear, flat, coincident,
// all pinned).
#include "constraint_checks.hpp"
#include "pbd/constraints/bending.hpp"

namespace pbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Two triangles hinged on the x axis: p3 in the +y half-plane, p4 rotated from -y by `fold` around the x axis.
template <class Real> void hinge(double fold, Vec3<Real> (&p)[4]) {
  p[0] = Vec3<Real>(0, 0, 0);
  p[1] = Vec3<Real>(1, 0, 0);
  p[2] = Vec3<Real>(Real(0.4), 1, 0);
  p[3] = Vec3<Real>(Real(0.6), Real(-std::cos(fold)), Real(std::sin(fold)));
}

// The float projection's arccosine (a polynomial, so the SIMD kernel's lanes compute it too): within 1.5 ulp
// of π over all of [−1, 1], every float near ±1/2 (where it switches form) and near ±1, and the ends exact.
TEST(Bending, FloatArccosineIsWithinOneAndAHalfUlpOfPi) {
  double worst = 0;
  auto check = [&](float x) { worst = std::max(worst, std::abs(double(detail::bend::acos_poly<float>(x)) - std::acos(double(x)))); };
  for (int i = 0; i <= 2'000'000; ++i) check(float(-1.0 + 2.0 * i / 2'000'000.0));
  for (float x : {0.5f, -0.5f})
    for (int i = 0; i < 1000; ++i) {
      check(x);
      x = std::nextafter(x, 0.0f);
    }
  for (float x = 1.0f, i = 0; i < 100000; ++i, x = std::nextafter(x, 0.0f)) check(x), check(-x);
  EXPECT_LT(worst, 3.6e-7);  // 1.5 ulp of π in float (std::acos in float: 0.5 ulp)
  EXPECT_EQ(detail::bend::acos_poly<float>(-1.0f), float(kPi));
  EXPECT_EQ(detail::bend::acos_poly<float>(1.0f), 0.0f);
  EXPECT_EQ(detail::bend::acos_poly<float>(0.0f), float(kPi / 2));
}

// The same in double, against long double's acos: within 2 ulp of π.
TEST(Bending, DoubleArccosineIsWithinTwoUlpOfPi) {
  long double worst = 0;
  auto check = [&](double x) {
    worst = std::max(worst, std::abs((long double)detail::bend::acos_poly<double>(x) - std::acos((long double)x)));
  };
  for (int i = 0; i <= 2'000'000; ++i) check(-1.0 + 2.0 * i / 2'000'000.0);
  for (double x : {0.5, -0.5})
    for (int i = 0; i < 1000; ++i) {
      check(x);
      x = std::nextafter(x, 0.0);
    }
  for (double x = 1.0, i = 0; i < 100000; ++i, x = std::nextafter(x, 0.0)) check(x), check(-x);
  EXPECT_LT(worst, 8.9e-16L);  // 2 ulp of π in double
  EXPECT_EQ(detail::bend::acos_poly<double>(-1.0), kPi);
  EXPECT_EQ(detail::bend::acos_poly<double>(1.0), 0.0);
}

TEST(Bending, AngleIsPiWhenFlatAndFollowsTheFold) {
  Vec3<double> p[4];
  hinge(0.0, p);
  EXPECT_NEAR(dihedral_angle(p[0], p[1], p[2], p[3]), kPi, 1e-12);
  hinge(0.5, p);
  EXPECT_NEAR(dihedral_angle(p[0], p[1], p[2], p[3]), kPi - 0.5, 1e-12);
  hinge(-0.5, p);
  EXPECT_NEAR(dihedral_angle(p[0], p[1], p[2], p[3]), kPi - 0.5, 1e-12);  // unsigned
}

TEST(Bending, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vec3<double> p[4];
    for (auto& q : p) q = test::random_point<double>(rng);
    checked += test::check_gradient(BendingConstraint<double>{{0, 1, 2, 3}, 0, 1.0}, p, 1e-5);
  }
  EXPECT_GT(checked, 290);
}

TEST(Bending, ConservesLinearMomentumWithEqualAndUnequalMasses) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> mass(0.01, 100.0);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3<double> p[4];
    for (auto& q : p) q = test::random_point<double>(rng);
    const double m = mass(rng);
    double w[4];
    for (double& wi : w) wi = trial % 2 ? 1.0 / m : 1.0 / mass(rng);
    Vec3<double> dp[4];
    double dl;
    if (!correction(BendingConstraint<double>{{0, 1, 2, 3}, 0, 1.2}, p, w, SolveCoefficients<double>{1, 0}, 0.0, dp, dl))
      continue;
    double scale = 0;
    for (int i = 0; i < 4; ++i) scale += dp[i].norm() / w[i];
    EXPECT_LT(test::momentum_change(dp, w).norm(), 1e-9 * (1.0 + scale));
  }
}

template <class Real> class BendingPrecision : public ::testing::Test {};
TYPED_TEST_SUITE_P(BendingPrecision);

// Projects repeatedly; returns the final positions.
template <class Real> void project_n(const BendingConstraint<Real>& c, Vec3<Real> (&p)[4], const Real (&w)[4], int n) {
  Real flat[12];
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) flat[3 * i + d] = p[i][d];
  for (int k = 0; k < n; ++k) {
    Real lambda = 0;
    project(c, flat, w, SolveCoefficients<Real>{1, 0}, lambda);
  }
  for (int i = 0; i < 4; ++i) p[i] = Vec3<Real>(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
}

TYPED_TEST_P(BendingPrecision, ProjectionReachesTheRestAngle) {
  using Real = TypeParam;
  Vec3<Real> p[4];
  hinge(0.3, p);
  const Real w[4] = {1, 1, 1, Real(0.5)};
  project_n(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(kPi - 1.0)}, p, w, 20);
  EXPECT_NEAR(dihedral_angle(p[0], p[1], p[2], p[3]), kPi - 1.0, 1e-3);
}

TYPED_TEST_P(BendingPrecision, CollinearPairIsSkippedWithoutNaN) {
  using Real = TypeParam;
  // Guard: p3 on the edge's line, so triangle (p1, p2, p3) has no normal.
  Vec3<Real> p[4];
  hinge(0.3, p);
  p[2] = Vec3<Real>(2, 0, 0);
  Real C;
  Vec3<Real> g[4];
  EXPECT_FALSE(evaluate(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(1)}, p, C, g));
  const Vec3<Real> before = p[3];
  const Real w[4] = {1, 1, 1, 1};
  project_n(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(1)}, p, w, 3);
  EXPECT_EQ(p[3], before);
  for (auto& q : p) EXPECT_TRUE(q.allFinite());
}

TYPED_TEST_P(BendingPrecision, FlatPairAtItsRestAngleStaysPut) {
  using Real = TypeParam;
  // Guard: exactly flat (d = −1) is the kink of the unsigned angle: no gradient, skipped; C is 0 anyway.
  Vec3<Real> p[4], q[4];
  hinge(0.0, p);
  hinge(0.0, q);
  Real C;
  Vec3<Real> g[4];
  EXPECT_FALSE(evaluate(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(kPi)}, p, C, g));
  const Real w[4] = {1, 1, 1, 1};
  project_n(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(kPi)}, p, w, 3);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p[i], q[i]);
}

TYPED_TEST_P(BendingPrecision, CoincidentEdgeEndsAreSkipped) {
  using Real = TypeParam;
  // Guard: a zero-length shared edge gives neither triangle a normal.
  Vec3<Real> p[4];
  hinge(0.3, p);
  p[1] = p[0];
  Real C;
  Vec3<Real> g[4];
  EXPECT_FALSE(evaluate(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(1)}, p, C, g));
}

TYPED_TEST_P(BendingPrecision, AllPinnedMovesNothing) {
  using Real = TypeParam;
  Vec3<Real> p[4], q[4];
  hinge(0.3, p);
  hinge(0.3, q);
  const Real w[4] = {0, 0, 0, 0};
  project_n(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(1)}, p, w, 2);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p[i], q[i]);
}

TYPED_TEST_P(BendingPrecision, TinyPairBendsLikeALargeOne) {
  using Real = TypeParam;
  // Scale-free guards: a 1 mm hinge is projected as well as a 1 m one.
  Vec3<Real> p[4];
  hinge(0.3, p);
  for (auto& q : p) q *= Real(1e-3);
  const Real w[4] = {1, 1, 1, 1};
  project_n(BendingConstraint<Real>{{0, 1, 2, 3}, 0, Real(kPi - 1.0)}, p, w, 20);
  EXPECT_NEAR(dihedral_angle(p[0], p[1], p[2], p[3]), kPi - 1.0, 1e-3);
}

REGISTER_TYPED_TEST_SUITE_P(BendingPrecision, ProjectionReachesTheRestAngle, CollinearPairIsSkippedWithoutNaN,
                            FlatPairAtItsRestAngleStaysPut, CoincidentEdgeEndsAreSkipped, AllPinnedMovesNothing,
                            TinyPairBendsLikeALargeOne);
using Precisions = ::testing::Types<float, double>;
INSTANTIATE_TYPED_TEST_SUITE_P(P, BendingPrecision, Precisions);

}  // namespace
}  // namespace pbd
