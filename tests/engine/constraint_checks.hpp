#pragma once
// Shared checks for fixed-arity constraints: random configurations, finite-difference gradients, momentum.
#include "pbd/constraints/projection.hpp"

#include <gtest/gtest.h>

#include <random>

namespace pbd::test {

/// Random point in [-1, 1]^3.
template <class Real> Vec3<Real> random_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(u(rng)));
}

/// Checks evaluate()'s gradient against central differences of C at p (double precision). Returns false if the
/// constraint is undefined at p (the caller then skips that sample).
template <class Constraint>
bool check_gradient(const Constraint& c, const Vec3<double> (&p)[Constraint::kArity], double tol = 1e-6) {
  constexpr int n = Constraint::kArity;
  double C;
  Vec3<double> grad[n];
  if (!evaluate(c, p, C, grad)) return false;
  const double h = 1e-6;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      Vec3<double> plus[n], minus[n];
      for (int j = 0; j < n; ++j) plus[j] = minus[j] = p[j];
      plus[i][d] += h;
      minus[i][d] -= h;
      double Cp = 0, Cm = 0;
      Vec3<double> g[n];
      EXPECT_TRUE(evaluate(c, plus, Cp, g));
      EXPECT_TRUE(evaluate(c, minus, Cm, g));
      const double fd = (Cp - Cm) / (2 * h);
      EXPECT_NEAR(grad[i][d], fd, tol * (1.0 + std::abs(fd))) << "particle " << i << " axis " << d;
    }
  return true;
}

/// Σ m_i Δp_i of one correction, for movable particles (inverse masses w > 0).
template <class Real, int N>
Vec3<double> momentum_change(const Vec3<Real> (&dp)[N], const Real (&w)[N]) {
  Vec3<double> sum = Vec3<double>::Zero();
  for (int i = 0; i < N; ++i) sum += dp[i].template cast<double>() / double(w[i]);
  return sum;
}

}  // namespace pbd::test
