#pragma once
/// \file contact_material.hpp
/// Friction and restitution of a contact: what a collider's surface or a contact body brings, and how two mix.
#include "pbd/types.hpp"

#include <algorithm>
#include <cmath>

namespace pbd {

/// Coulomb friction and restitution of a surface (a collider's, or a contact body's particles').
template <class Real> struct ContactMaterial {
  Real static_friction = 0;   ///< μs ≥ 0: a contact whose slip in a sub-step is under μs × its depth sticks
  Real kinetic_friction = 0;  ///< μk ≥ 0: otherwise the slip is shortened by μk × the depth (Macklin et al. 2014)
  Real restitution = 0;       ///< e in [0, 1]: an impact's normal speed after is e × the speed before
  /// True when the material changes nothing (no friction, no restitution): contacts then project as plain
  /// inequalities.
  bool inert() const { return static_friction == Real(0) && kinetic_friction == Real(0) && restitution == Real(0); }
};

/// The material of a contact between two surfaces (Box2D's rules): friction is the geometric mean √(μa·μb),
/// restitution the larger of the two.
template <class Real> ContactMaterial<Real> mix_materials(const ContactMaterial<Real>& a, const ContactMaterial<Real>& b) {
  return {std::sqrt(a.static_friction * b.static_friction), std::sqrt(a.kinetic_friction * b.kinetic_friction),
          std::max(a.restitution, b.restitution)};
}

/// Friction of one contact after its normal correction (Macklin et al. 2014, §6.1): `slip` is the relative
/// displacement over the sub-step (m), n the contact normal, depth the penetration the normal correction just
/// removed (m, > 0). Returns the correction of the relative displacement: all of its tangential part when that is
/// under μs·depth (static friction), else that part shortened by μk·depth (kinetic friction).
template <class Real>
inline Vec3<Real> friction_correction(const Vec3<Real>& slip, const Vec3<Real>& n, Real depth, const ContactMaterial<Real>& m) {
  const Vec3<Real> t = slip - n * n.dot(slip);
  const Real len = t.norm();
  if (len < m.static_friction * depth) return -t;
  if (!(len > Real(0))) return Vec3<Real>::Zero();
  return t * (-std::min(m.kinetic_friction * depth / len, Real(1)));
}

}  // namespace pbd
