#pragma once
// Restitution (private): step 5's last pass over the contacts (Müller et al. 2006 §3.5 changes the velocities of
// colliding particles after the update). A contact the sweeps moved (its λ counts those projections) and whose
// material has e > 0 leaves with normal speed e × its approach speed before the solve (the approach is recorded at
// generation, from the velocities after forces). Slow approaches (under 2·|g|·h, Macklin et al. 2019) bounce not at
// all, so resting contacts do not jitter. One thread, in stored order: the same bits for any thread count. With no
// contact of e > 0 this changes nothing.
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/particle_contact.hpp"

#include <span>
#include <vector>

namespace pbd::detail {

/// See above; v the velocities after the update (3 per particle), g_h = |g|·h in m/s.
template <class Real>
void apply_restitution(std::span<const CollisionConstraint<Real>> collisions, const std::vector<Real>& collision_lambda,
                       std::span<const ParticleContact<Real>> pairs, const std::vector<Real>& pair_lambda,
                       const Real* w, Real* v, Real g_h) {
  const Real slow = Real(2) * g_h;
  for (std::size_t k = 0; k < collisions.size(); ++k) {
    const CollisionConstraint<Real>& c = collisions[k];
    if (c.material.restitution == Real(0) || !(collision_lambda[k] > Real(0)) || !(c.approach < -slow)) continue;
    Eigen::Map<Vec3<Real>> vi(v + 3 * std::size_t(c.particles[0]));
    vi += c.normal * (-c.material.restitution * c.approach - c.normal.dot(vi));
  }
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const ParticleContact<Real>& c = pairs[k];
    if (c.material.restitution == Real(0) || !(pair_lambda[k] > Real(0)) || !(c.approach < -slow)) continue;
    const Index a = c.particles[0], b = c.particles[1];
    const Real wsum = w[a] + w[b];
    if (!(wsum > Real(0))) continue;
    Eigen::Map<Vec3<Real>> va(v + 3 * std::size_t(a)), vb(v + 3 * std::size_t(b));
    const Real dv = -c.material.restitution * c.approach - c.normal.dot(va - vb);
    va += c.normal * (dv * w[a] / wsum);
    vb -= c.normal * (dv * w[b] / wsum);
  }
}

}  // namespace pbd::detail
