#pragma once
/// \file particle_contact.hpp
/// Particle contact: the inequality C = |p_a − p_b| − (r_a + r_b) ≥ 0 between two particles of contact bodies
/// (contacts.hpp), generated each sub-step from their paths, with the contact's friction and restitution.
#include "pbd/constraints/contact_material.hpp"
#include "pbd/constraints/projection.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <array>

namespace pbd {

/// Keeps two particles' spheres apart. Always hard (k = 1, α = 0); skipped while satisfied. While the particles are
/// on the side of each other they met on (n·(p_a − p_b) > 0) C is the distance minus the radii sum, so resting
/// contacts roll and stack; a pair whose paths crossed within the sub-step is pushed back along the normal n of
/// first contact instead (C = n·(p_a − p_b) − (r_a + r_b)), so fast particles never pass through each other.
template <class Real> struct ParticleContact {
  static constexpr const char* kName = "particle contact";  ///< name in reports
  static constexpr int kArity = 2;                  ///< particles per constraint
  static constexpr bool kInequality = true;         ///< projected only while C < 0
  static constexpr bool kUnitGradients = true;      ///< |∇_a C| = |∇_b C| = 1
  /// Its violation is the overlap as a fraction of the radii sum (metrics.hpp), reported in percent.
  static constexpr Measure kMeasure{"overlap_pct", "overlap", "%", 100.0};
  std::array<Index, 2> particles;                   ///< a, b (a < b)
  Vec3<Real> normal;                                ///< unit normal of first contact, from b to a
  Real distance;                                    ///< r_a + r_b, m
  Vec3<Real> start = Vec3<Real>::Zero();            ///< x_a − x_b at the start of the sub-step, m
  Real approach = 0;                                ///< n·(v_a − v_b) before the solve, m/s (< 0: closing)
  ContactMaterial<Real> material{};                 ///< the contact's friction and restitution
};

/// See ParticleContact.
template <class Real>
inline bool evaluate(const ParticleContact<Real>& c, const Vec3<Real> (&p)[2], Real& C, Vec3<Real> (&grad)[2]) {
  const Vec3<Real> d = p[0] - p[1];
  const Real len2 = d.squaredNorm();
  if (c.normal.dot(d) > Real(0) && len2 > tiny_squared<Real>()) {
    const Real len = std::sqrt(len2);
    C = len - c.distance;
    grad[0] = d / len;
  } else {
    C = c.normal.dot(d) - c.distance;
    grad[0] = c.normal;
  }
  grad[1] = -grad[0];
  return true;
}

/// The projection of a particle contact (chosen over the generic one in projection.hpp): the normal correction,
/// then, if the contact has friction, Macklin et al. 2014 §6.1 on the relative slip (p_a − p_b) − start, shared by
/// inverse mass. `lambda` counts the projections that moved the pair (restitution acts only on touched contacts).
/// Always in place.
template <class Real>
[[gnu::always_inline]] inline void project_into(const ParticleContact<Real>& c, const Real* p, const Real* w,
                                                SolveCoefficients<Real> coeff, Real& lambda, Real* out,
                                                Real /*relax*/ = Real(1)) {
  const Index a = c.particles[0], b = c.particles[1];
  const Vec3<Real> q[2] = {Eigen::Map<const Vec3<Real>>(p + 3 * std::size_t(a)),
                           Eigen::Map<const Vec3<Real>>(p + 3 * std::size_t(b))};
  const Real wi[2] = {w[a], w[b]};
  Vec3<Real> dp[2];
  Real dlambda;
  if (!correction(c, q, wi, coeff, lambda, dp, dlambda)) return;
  lambda += Real(1);
  Eigen::Map<Vec3<Real>> oa(out + 3 * std::size_t(a)), ob(out + 3 * std::size_t(b));
  if (wi[0] != Real(0)) oa += dp[0];
  if (wi[1] != Real(0)) ob += dp[1];
  if (c.material.static_friction == Real(0) && c.material.kinetic_friction == Real(0)) return;
  const Vec3<Real> n = (q[0] - q[1]).normalized();
  const Real depth = dlambda * (wi[0] + wi[1]);  // −C: how far the normal correction moved the pair apart
  const Vec3<Real> f = friction_correction<Real>(Vec3<Real>((oa - ob) - c.start), n.allFinite() ? n : c.normal, depth,
                                                 c.material) / (wi[0] + wi[1]);
  if (wi[0] != Real(0)) oa += wi[0] * f;
  if (wi[1] != Real(0)) ob -= wi[1] * f;
}

}  // namespace pbd
