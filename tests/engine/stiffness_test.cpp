// Stiffness formulations: PBD k, iteration-independent k', XPBD compliance.
#include "pbd/constraints/projection.hpp"
#include "pbd/constraints/stretch.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pbd {
namespace {

// Particle 0 pinned at the origin, particle 1 on the x axis at `x1`, rest length 1; returns C after `n` sweeps.
double violation_after(double x1, const Stiffness& s, int n, double h = 0.01) {
  double p[6] = {0, 0, 0, x1, 0, 0};
  const double w[2] = {0, 2};
  double lambda = 0;
  const auto coeff = coefficients<double>(s, h, n);
  for (int i = 0; i < n; ++i) project(StretchConstraint<double>{{0, 1}, 0, 1.0}, p, w, coeff, lambda);
  return p[3] - 1.0;
}

TEST(Stiffness, PbdStiffnessRemovesFractionKPerSweep) {
  EXPECT_NEAR(violation_after(3.0, Stiffness::pbd_k(0.25), 1), 2.0 * 0.75, 1e-12);
  EXPECT_NEAR(violation_after(3.0, Stiffness::pbd_k(0.25), 4), 2.0 * std::pow(0.75, 4), 1e-12);
}

TEST(Stiffness, IterationIndependentStiffnessGivesTheSameResultForAnyIterationCount) {
  for (int n : {1, 2, 5, 10, 40}) EXPECT_NEAR(violation_after(3.0, Stiffness::iteration_independent(0.3), n), 2.0 * 0.7, 1e-12) << n;
}

TEST(Stiffness, XpbdReachesTheComplianceEquilibriumAndStaysThere) {
  // One free particle (w = 2): C converges to C0·α̃/(w + α̃) with α̃ = α/h², whatever the number of sweeps.
  const double alpha = 1e-4, h = 0.01, at = alpha / (h * h);
  const double expected = 2.0 * at / (2.0 + at);
  for (int n : {1, 3, 20}) EXPECT_NEAR(violation_after(3.0, Stiffness::xpbd_compliance(alpha), n, h), expected, 1e-12) << n;
}

TEST(Stiffness, CoefficientsOfEachMode) {
  EXPECT_DOUBLE_EQ(coefficients<double>(Stiffness::pbd_k(0.4), 0.1, 7).k, 0.4);
  EXPECT_DOUBLE_EQ(coefficients<double>(Stiffness::iteration_independent(0.75), 0.1, 2).k, 0.5);
  const auto x = coefficients<double>(Stiffness::xpbd_compliance(0.02), 0.1, 7);
  EXPECT_DOUBLE_EQ(x.k, 1.0);
  EXPECT_DOUBLE_EQ(x.alpha_tilde, 2.0);
}

// A compliance of −0 gives α̃ = +0: the stretch kernel leaves "− α̃·λ" out where no set has α̃ ≠ 0, which changes
// no bit only when α̃ is +0 (−0·0 = −0, and −0 − (−0) = +0 where the scalar projection's −0 − (+0) stays −0).
TEST(Stiffness, NegativeZeroComplianceGivesPositiveZeroAlphaTilde) {
  for (double h : {0.01, 1.0}) {
    EXPECT_FALSE(std::signbit(coefficients<float>(Stiffness::xpbd_compliance(-0.0), h, 4).alpha_tilde)) << h;
    EXPECT_FALSE(std::signbit(coefficients<double>(Stiffness::xpbd_compliance(-0.0), h, 4).alpha_tilde)) << h;
  }
}

}  // namespace
}  // namespace pbd
