#pragma once
/// \file projection.hpp
/// The one projection every solver calls: PBD/XPBD correction of a single fixed-arity constraint.
#include "pbd/constraints/traits.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"

namespace pbd {

/// A constraint type may declare `static constexpr bool kUnitGradients = true` when every |∇_i C| is 1.
/// Corrections of one constraint: Δλ = (−k·C − α̃·λ) / (Σ_i w_i|∇_i C|² + α̃) and Δp_i = w_i ∇_i C Δλ.
/// Returns false (and leaves dp, dlambda untouched) when nothing moves: the gradient is undefined, an inequality
/// holds (C ≥ 0), or the denominator is not positive (all particles pinned and α̃ = 0).
template <class Constraint, class Real>
inline bool correction(const Constraint& c, const Vec3<Real> (&p)[Constraint::kArity],
                       const Real (&w)[Constraint::kArity], SolveCoefficients<Real> coeff, Real lambda,
                       Vec3<Real> (&dp)[Constraint::kArity], Real& dlambda) {
  constexpr int n = Constraint::kArity;
  Real C;
  Vec3<Real> grad[n];
  if (!evaluate(c, p, C, grad)) return false;
  if constexpr (Constraint::kInequality) {
    if (!(C < Real(0))) return false;
  }
  Real denom = coeff.alpha_tilde;
  if constexpr (requires { Constraint::kUnitGradients; }) {
    for (int i = 0; i < n; ++i) denom += w[i];  // every |∇_i C| is 1 by construction
  } else {
    for (int i = 0; i < n; ++i) denom += w[i] * grad[i].squaredNorm();
  }
  if (!(denom > Real(0))) return false;
  dlambda = (-coeff.k * C - coeff.alpha_tilde * lambda) / denom;
  for (int i = 0; i < n; ++i) dp[i] = (w[i] * dlambda) * grad[i];
  return true;
}

/// Computes the correction of one constraint from positions `p` (3×N, column-major) and inverse masses `w`,
/// accumulates its λ and adds Δp to `out` (3×N) for its movable particles; pinned ones (w = 0) are never written.
/// λ is accumulated only when α̃ ≠ 0: it enters the correction only as α̃·λ, so for PBD (α̃ = 0) it stays 0 and
/// the solvers need not read or write it (every solver follows this rule, so all give the same bits).
/// With out = p this is the Gauss-Seidel projection; with out = a separate buffer, the Jacobi accumulation (w then
/// holds split inverse masses and relax is the ω by which the sweep scales what it applies, so λ += relax·Δλ).
template <class Constraint, class Real>
[[gnu::always_inline]] inline void project_into(const Constraint& c, const Real* p, const Real* w,
                                                SolveCoefficients<Real> coeff, Real& lambda, Real* out,
                                                Real relax = Real(1)) {
  constexpr int n = Constraint::kArity;
  Vec3<Real> q[n];
  Real wi[n];
  for (int i = 0; i < n; ++i) {
    q[i] = Eigen::Map<const Vec3<Real>>(p + 3 * std::size_t(c.particles[i]));
    wi[i] = w[c.particles[i]];
  }
  Vec3<Real> dp[n];
  if constexpr (multipliers<Constraint>() > 1) {  // its own coupled correction: `lambda` is the first of its λ
    Real dlambda[multipliers<Constraint>()];
    Real* lam = &lambda;
    if (!correction(c, q, wi, coeff, static_cast<const Real*>(lam), dp, dlambda)) return;
    if (coeff.alpha_tilde != Real(0))
      for (int k = 0; k < multipliers<Constraint>(); ++k) lam[k] += relax * dlambda[k];
  } else {
    Real dlambda;
    if (!correction(c, q, wi, coeff, lambda, dp, dlambda)) return;
    if (coeff.alpha_tilde != Real(0)) lambda += relax * dlambda;
  }
  for (int i = 0; i < n; ++i)
    if (wi[i] != Real(0)) Eigen::Map<Vec3<Real>>(out + 3 * std::size_t(c.particles[i])) += dp[i];
}

/// Gauss-Seidel projection of one constraint in place on the predicted positions `p`; accumulates its λ.
template <class Constraint, class Real>
inline void project(const Constraint& c, Real* p, const Real* w, SolveCoefficients<Real> coeff, Real& lambda) {
  project_into(c, p, w, coeff, lambda, p);
}

/// Jacobi: adds the correction of constraint c, computed from the unchanged `p` with split inverse masses `w`, to
/// `delta` (3 per particle) and accumulates λ += omega·Δλ.
template <class Constraint, class Real>
inline void accumulate(const Constraint& c, const Real* p, const Real* w, SolveCoefficients<Real> coeff, Real& lambda,
                       Real* delta, Real omega = Real(1)) {
  project_into(c, p, w, coeff, lambda, delta, omega);
}

}  // namespace pbd
