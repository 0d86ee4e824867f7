#pragma once
/// \file stretch.hpp
/// Stretch (distance) constraint: C = |p0 − p1| − d.
#include "pbd/constraints/traits.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"

#include <array>

namespace pbd {

/// Keeps two particles at rest distance `rest`. 16 bytes in float.
template <class Real> struct StretchConstraint {
  static constexpr const char* kName = "stretch";  ///< name in reports and on the command line
  static constexpr int kArity = 2;             ///< particles per constraint
  static constexpr bool kInequality = false;   ///< an equality: projected whatever the sign of C
  static constexpr bool kUnitGradients = true; ///< |∇_i C| = 1 for every particle (saves work in the projection)
  static constexpr const char* kNoun = "stretch constraint";        ///< the item in error messages
  static constexpr std::array<const char*, 2> kParticleNames{"a", "b"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "stretch";             ///< a body's key: stretch on its edges
  static constexpr SceneForm kSceneForm = SceneForm::mesh;        ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;                     ///< between two particles
  static constexpr Measure kMeasure{"stretch_pct", "stretch", "%", 100.0};  ///< relative stretch, in percent
  std::array<Index, 2> particles;              ///< the two particles
  Index set;                                   ///< constraint set (stiffness) it belongs to
  Real rest;                                   ///< rest distance d ≥ 0
  /// The rest value: distance d in m (default: the particles' current distance).
  static constexpr auto fields() { return std::tuple{Field{"rest", "rest length", &StretchConstraint::rest}}; }
};

/// |d|² summed as x² + (y² + z²), the order the SIMD kernels' lanes use (stretch_kernel.hpp), in both precisions.
template <class Real> inline Real squared_length(const Vec3<Real>& d) {
  return d.x() * d.x() + (d.y() * d.y() + d.z() * d.z());
}

/// C = |p0 − p1| − d, ∇0 C = n, ∇1 C = −n with n = (p0 − p1)/|p0 − p1|.
/// Guard: coincident particles (|p0 − p1|² below tiny_squared) have no direction: returns false, nothing moves.
template <class Real>
inline bool evaluate(const StretchConstraint<Real>& c, const Vec3<Real> (&p)[2], Real& C, Vec3<Real> (&grad)[2]) {
  const Vec3<Real> d = p[0] - p[1];
  const Real len2 = squared_length(d);
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real len = std::sqrt(len2);
  C = len - c.rest;
  grad[0] = d * (Real(1) / len);
  grad[1] = -grad[0];
  return true;
}

/// Stretch's own correction (the generic one in projection.hpp, with one division fewer): with t = 1/(denom·|d|),
/// Δλ = (−k·C − α̃·λ)·|d|·t and Δp_0 = w_0·(−k·C − α̃·λ)·t·d = −Δp_1/w_1·w_0. Same guards as the generic one.
template <class Real>
inline bool correction(const StretchConstraint<Real>& c, const Vec3<Real> (&p)[2], const Real (&w)[2],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[2], Real& dlambda) {
  const Vec3<Real> d = p[0] - p[1];
  const Real len2 = squared_length(d);
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real denom = coeff.alpha_tilde + w[0] + w[1];
  if (!(denom > Real(0))) return false;
  const Real len = std::sqrt(len2);
  const Real num = -coeff.k * (len - c.rest) - coeff.alpha_tilde * lambda;
  const Real s = num / (denom * len);
  dlambda = s * len;
  dp[0] = (w[0] * s) * d;
  dp[1] = (-w[1] * s) * d;
  return true;
}

/// Relative stretch |(|x_a − x_b| − d)| / d (absolute length in m where d = 0).
template <class Real> double violation(const StretchConstraint<Real>& c, const PositionsView<Real>& x) {
  return detail::relative_error((detail::position_of<Real>(x, c.particles[0]) -
                                 detail::position_of<Real>(x, c.particles[1])).norm(),
                                double(c.rest));
}

/// Default rest distance: the particles' distance in positions x.
template <class Real, class X> const char* measure_rest(StretchConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 1u)) c.rest = (x.col(c.particles[0]) - x.col(c.particles[1])).norm();
  return nullptr;
}

/// A rest distance is finite and ≥ 0.
template <class Real> std::string rest_error(const StretchConstraint<Real>& c) {
  if (!std::isfinite(c.rest) || c.rest < Real(0))
    return detail::message("rest distance must be finite and >= 0, got ", c.rest);
  return {};
}

}  // namespace pbd
