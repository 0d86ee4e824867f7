#pragma once
/// \file anchor.hpp
/// Position anchor: C = |p − p0|, pulls one particle towards a fixed target.
#include "pbd/types.hpp"

#include <array>

namespace pbd {

/// Pulls a particle to a fixed point (a soft or hard pin for a particle that keeps its mass).
template <class Real> struct AnchorConstraint {
  static constexpr const char* kName = "anchor";  ///< name in reports and on the command line
  static constexpr int kArity = 1;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  static constexpr bool kUnitGradients = true; ///< |∇C| = 1
  std::array<Index, 1> particles;             ///< the anchored particle
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Vec3<Real> target;                          ///< the anchor point p0
};

/// C = |p − p0|, ∇C = (p − p0)/|p − p0|.
/// Guard: at the target (|p − p0|² below tiny_squared) the constraint holds and has no direction: returns false.
template <class Real>
inline bool evaluate(const AnchorConstraint<Real>& c, const Vec3<Real> (&p)[1], Real& C, Vec3<Real> (&grad)[1]) {
  const Vec3<Real> d = p[0] - c.target;
  const Real len2 = d.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  C = std::sqrt(len2);
  grad[0] = d * (Real(1) / C);
  return true;
}

}  // namespace pbd
