#pragma once
/// \file collision.hpp
/// Collision constraint: the inequality C = n·p − offset ≥ 0, generated each (sub)step from a collider, with the
/// contact's friction and restitution.
#include "pbd/constraints/contact_material.hpp"
#include "pbd/constraints/projection.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <array>

namespace pbd {

/// Keeps one particle on the positive side of a plane (a collider's surface at the contact).
/// Always hard (k = 1, α = 0); skipped while satisfied.
template <class Real> struct CollisionConstraint {
  static constexpr const char* kName = "collision";  ///< name in reports and on the command line
  static constexpr int kArity = 1;           ///< particles per constraint
  static constexpr bool kInequality = true;  ///< projected only while C < 0
  static constexpr bool kUnitGradients = true;  ///< |∇C| = |n| = 1
  /// Its violation is the penetration depth in m (metrics.hpp), reported in millimetres.
  static constexpr Measure kMeasure{"penetration_mm", "penetration", "mm", 1000.0};
  std::array<Index, 1> particles;            ///< the colliding particle
  Vec3<Real> normal;                         ///< unit surface normal n at the contact
  Real offset;                               ///< n·q for the contact point q (plus the particle's radius)
  Vec3<Real> start = Vec3<Real>::Zero();     ///< the particle's position x at the start of the sub-step, m
  Real approach = 0;                         ///< n·v before the solve, m/s (< 0: moving into the surface)
  ContactMaterial<Real> material{};          ///< the contact's friction and restitution
};

/// C = n·p − offset, ∇C = n.
template <class Real>
inline bool evaluate(const CollisionConstraint<Real>& c, const Vec3<Real> (&p)[1], Real& C, Vec3<Real> (&grad)[1]) {
  C = c.normal.dot(p[0]) - c.offset;
  grad[0] = c.normal;
  return true;
}

/// The projection of a collision (chosen over the generic one in projection.hpp): the normal correction, then, if
/// the contact has friction, Macklin et al. 2014 §6.1 on the slip p − start. `lambda` counts the projections that
/// moved the particle (restitution acts only on contacts that were touched). Always in place (contacts are
/// projected in place under every update rule).
template <class Real>
[[gnu::always_inline]] inline void project_into(const CollisionConstraint<Real>& c, const Real* p, const Real* w,
                                                SolveCoefficients<Real> coeff, Real& lambda, Real* out,
                                                Real /*relax*/ = Real(1)) {
  const Index i = c.particles[0];
  const Vec3<Real> q[1] = {Eigen::Map<const Vec3<Real>>(p + 3 * std::size_t(i))};
  const Real wi[1] = {w[i]};
  Vec3<Real> dp[1];
  Real dlambda;
  if (wi[0] == Real(0) || !correction(c, q, wi, coeff, lambda, dp, dlambda)) return;
  lambda += Real(1);
  Eigen::Map<Vec3<Real>> o(out + 3 * std::size_t(i));
  o += dp[0];
  if (c.material.static_friction == Real(0) && c.material.kinetic_friction == Real(0)) return;
  const Real depth = dlambda * wi[0];  // −C: how far the normal correction moved the particle
  o += friction_correction<Real>(Vec3<Real>(o - c.start), c.normal, depth, c.material);
}

}  // namespace pbd
