#pragma once
/// \file area.hpp
/// Triangle area constraint: C = ½|(p2 − p1) × (p3 − p1)| − A0 (Müller et al. 2006).
#include "pbd/constraints/degenerate.hpp"

#include <array>
#include <cmath>

namespace pbd {

/// Keeps a triangle's area at its rest area A0 (the triangle may shear and bend freely).
template <class Real> struct AreaConstraint {
  static constexpr const char* kName = "area";  ///< name in reports and on the command line
  static constexpr int kArity = 3;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  std::array<Index, 3> particles;             ///< the triangle's corners p1, p2, p3
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Real rest;                                  ///< rest area A0 ≥ 0
};

/// C = ½|u × v| − A0 with u = p2 − p1, v = p3 − p1 and unit normal n = u × v / |u × v|:
/// ∇2 C = ½ v × n, ∇3 C = ½ n × u, ∇1 C = −∇2 C − ∇3 C.
/// Guard: a zero-area triangle (collinear or coincident corners, degenerate_cross) has no normal, so no
/// direction to grow in: returns false and the constraint is skipped until the triangle opens up again.
template <class Real>
inline bool evaluate(const AreaConstraint<Real>& c, const Vec3<Real> (&p)[3], Real& C, Vec3<Real> (&grad)[3]) {
  const Vec3<Real> u = p[1] - p[0], v = p[2] - p[0];
  const Vec3<Real> cross = u.cross(v);
  if (degenerate_cross(cross, u, v)) return false;
  const Real len = std::sqrt(cross.squaredNorm());
  const Vec3<Real> n = cross / len;
  C = Real(0.5) * len - c.rest;
  grad[1] = Real(0.5) * v.cross(n);
  grad[2] = Real(0.5) * n.cross(u);
  grad[0] = -grad[1] - grad[2];
  return true;
}

/// Area of the triangle (a, b, c).
template <class Real> Real triangle_area(const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
  return Real(0.5) * (b - a).cross(c - a).norm();
}

}  // namespace pbd
