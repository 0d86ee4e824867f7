#pragma once
/// \file bending.hpp
/// Dihedral bending constraint on two triangles sharing an edge: C = acos(n1·n2) − φ0 (Müller et al. 2006, App. A).
///
///            p3
///           /  \          shared edge p1–p2; with e = p2 − p1:
///          /    \           n1 = e × (p3 − p1) / |e × (p3 − p1)|
///        p1 ---- p2         n2 = e × (p4 − p1) / |e × (p4 − p1)|
///          \    /           d  = n1·n2, φ = acos(d)
///           \  /          Two flat triangles on either side of the edge have n2 = −n1: φ = π.
///            p4           φ is unsigned: folding either way from flat lowers it.
#include "pbd/constraints/degenerate.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pbd {

/// Keeps the dihedral angle between triangles (p1, p2, p3) and (p1, p2, p4) at its rest value φ0.
template <class Real> struct BendingConstraint {
  static constexpr const char* kName = "bending";  ///< name in reports and on the command line
  static constexpr int kArity = 4;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  std::array<Index, 4> particles;             ///< p1, p2 (the shared edge), p3, p4 (the opposite corners)
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Real rest;                                  ///< rest angle φ0 in [0, π]
};

/// The dihedral angle φ = acos(n1·n2) of the sketch above, or a negative value if a triangle is degenerate.
template <class Real> Real dihedral_angle(const Vec3<Real>& p1, const Vec3<Real>& p2, const Vec3<Real>& p3,
                                          const Vec3<Real>& p4) {
  const Vec3<Real> e = p2 - p1, u = p3 - p1, v = p4 - p1;
  const Vec3<Real> a = e.cross(u), b = e.cross(v);
  if (degenerate_cross(a, e, u) || degenerate_cross(b, e, v)) return Real(-1);
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), Real(-1), Real(1)));
}

/// C = acos(d) − φ0 and ∇C = −∇d / √(1 − d²), where ∇d is Müller's Appendix A (his q_i are −∇d: with them his
/// update Δp_i = −w_i √(1 − d²)(acos d − φ0) q_i / Σ w_j|q_j|² is this same projection). With p1 at the origin:
///   ∇3 d = (n2 − d n1) × e / |e × p3|,   ∇4 d = (n1 − d n2) × e / |e × p4|,
///   ∇2 d = p3 × (n2 − d n1) / |e × p3| + p4 × (n1 − d n2) / |e × p4|,   ∇1 d = −∇2 d − ∇3 d − ∇4 d.
/// Guards (each returns false: no direction, the constraint is skipped):
///  - a triangle with collinear corners or a near-zero-length edge (degenerate_cross) has no normal;
///  - d is clamped to [−1, 1] (rounding can leave |d| slightly above 1 and acos would give NaN), and where
///    1 − d² ≤ 64 ε the pair is flat (φ = π) or folded shut (φ = 0): the unsigned angle has a kink there and no
///    gradient. A flat pair at rest angle π is satisfied anyway; a pair held exactly flat with another rest angle
///    waits for any other motion to move it off the kink.
template <class Real>
inline bool evaluate(const BendingConstraint<Real>& c, const Vec3<Real> (&p)[4], Real& C, Vec3<Real> (&grad)[4]) {
  const Vec3<Real> e = p[1] - p[0], p3 = p[2] - p[0], p4 = p[3] - p[0];
  const Vec3<Real> a = e.cross(p3), b = e.cross(p4);
  if (degenerate_cross(a, e, p3) || degenerate_cross(b, e, p4)) return false;
  const Real la = std::sqrt(a.squaredNorm()), lb = std::sqrt(b.squaredNorm());
  const Vec3<Real> n1 = a / la, n2 = b / lb;
  const Real d = std::clamp(n1.dot(n2), Real(-1), Real(1));
  const Real s2 = Real(1) - d * d;
  if (!(s2 > Real(64) * std::numeric_limits<Real>::epsilon())) return false;
  const Real scale = Real(-1) / std::sqrt(s2);  // ∇C = −∇d / √(1 − d²)
  const Vec3<Real> t1 = (n2 - d * n1) / la, t2 = (n1 - d * n2) / lb;
  grad[2] = scale * t1.cross(e);
  grad[3] = scale * t2.cross(e);
  grad[1] = scale * (p3.cross(t1) + p4.cross(t2));
  grad[0] = -grad[1] - grad[2] - grad[3];
  C = std::acos(d) - c.rest;
  return true;
}

}  // namespace pbd
