#pragma once
/// \file colliders.hpp
/// Static colliders (infinite planes, solid spheres) and the continuous generation of collision constraints.
#include "pbd/constraints/collision.hpp"
#include "pbd/types.hpp"

#include <vector>

namespace pbd {

/// Half-space n·x ≥ offset; particles are kept on the side the unit normal points to.
template <class Real> struct Plane {
  Vec3<Real> normal;  ///< unit normal, pointing out of the solid
  Real offset;        ///< n·x of any point x on the plane
  ContactMaterial<Real> material{};  ///< friction and restitution of its surface
};

/// Solid ball; particles are kept outside it.
template <class Real> struct Sphere {
  Vec3<Real> center;  ///< centre
  Real radius;        ///< radius > 0
  ContactMaterial<Real> material{};  ///< friction and restitution of its surface
};

/// All static colliders of a world; empty = no collision pass at all.
template <class Real> struct Colliders {
  std::vector<Plane<Real>> planes;    ///< infinite planes
  std::vector<Sphere<Real>> spheres;  ///< solid spheres
  bool empty() const { return planes.empty() && spheres.empty(); }  ///< true when there is nothing to collide with
};

/// What a particle brings to its contacts with colliders (from its contact body, if any).
template <class Real> struct ParticleSurfaces {
  const Real* radius = nullptr;                   ///< per particle, m (nullptr: every particle is a point)
  const ContactMaterial<Real>* material = nullptr;  ///< per particle (nullptr: the collider's material alone)
};

/// Appends to `out` one collision constraint per (movable particle, collider) pair whose path x → p enters the
/// collider or ends inside it (continuous: a path that passes through a sphere is caught at its entry point), or
/// whose p ends within `margin` of it (speculative: the inequality stays idle unless the solve pushes the particle
/// in). A particle of radius r keeps its centre r away from the surface. Each contact records the particle's start
/// x and its normal velocity (v: velocities after forces, m/s) for friction and restitution, and the contact's
/// material (mix_materials). Order: particle by particle, planes before spheres, so the result is deterministic.
template <class Real>
void generate_collisions(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                         const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin, ParticleSurfaces<Real> surfaces,
                         std::vector<CollisionConstraint<Real>>& out);

}  // namespace pbd
