#pragma once
/// \file collision.hpp
/// Collision constraint: the inequality C = n·p − offset ≥ 0, generated each (sub)step from a collider.
#include "pbd/types.hpp"

#include <array>

namespace pbd {

/// Keeps one particle on the positive side of a plane (a collider's surface at the contact).
/// Always hard (k = 1, α = 0); skipped while satisfied.
template <class Real> struct CollisionConstraint {
  static constexpr const char* kName = "collision";  ///< name in reports and on the command line
  static constexpr int kArity = 1;           ///< particles per constraint
  static constexpr bool kInequality = true;  ///< projected only while C < 0
  static constexpr bool kUnitGradients = true;  ///< |∇C| = |n| = 1
  std::array<Index, 1> particles;            ///< the colliding particle
  Vec3<Real> normal;                         ///< unit surface normal n at the contact
  Real offset;                               ///< n·q for the contact point q
};

/// C = n·p − offset, ∇C = n.
template <class Real>
inline bool evaluate(const CollisionConstraint<Real>& c, const Vec3<Real> (&p)[1], Real& C, Vec3<Real> (&grad)[1]) {
  C = c.normal.dot(p[0]) - c.offset;
  grad[0] = c.normal;
  return true;
}

}  // namespace pbd
