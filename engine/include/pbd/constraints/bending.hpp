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
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/bending_math.hpp"
#include "pbd/stiffness.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pbd {

/// Keeps the dihedral angle between triangles (p1, p2, p3) and (p1, p2, p4) at its rest value φ0.
template <class Real> struct BendingConstraint {
  static constexpr const char* kName = "bending";  ///< name in reports and on the command line
  static constexpr int kArity = 4;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  static constexpr const char* kNoun = "bending constraint";                          ///< the item in messages
  static constexpr std::array<const char*, 4> kParticleNames{"p1", "p2", "p3", "p4"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "bending";       ///< a body's key: bending on its interior edges
  static constexpr SceneForm kSceneForm = SceneForm::mesh;  ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;               ///< between four particles
  static constexpr Measure kMeasure{"bending_rad", "bending", "rad", 1.0};  ///< angle error, in radians
  std::array<Index, 4> particles;             ///< p1, p2 (the shared edge), p3, p4 (the opposite corners)
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Real rest;                                  ///< rest angle φ0 in [0, π]
  /// The rest value: angle φ0 in rad (default: the current dihedral angle).
  static constexpr auto fields() { return std::tuple{Field{"rest", "rest angle", &BendingConstraint::rest}}; }
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
/// The arithmetic is detail/bending_math.hpp's, shared with the float SIMD kernel (so both give the same bits); in
/// float acos is a polynomial there (within 2.4e-7 rad of the true angle), in double std::acos.
template <class Real>
inline bool evaluate(const BendingConstraint<Real>& c, const Vec3<Real> (&p)[4], Real& C, Vec3<Real> (&grad)[4]) {
  using V = detail::bend::V3<Real>;
  const V q[4] = {{p[0].x(), p[0].y(), p[0].z()}, {p[1].x(), p[1].y(), p[1].z()}, {p[2].x(), p[2].y(), p[2].z()},
                  {p[3].x(), p[3].y(), p[3].z()}};
  const auto r = detail::bend::bending_gradient<Real>(q, c.rest);
  if (!r.ok) return false;
  C = r.C;
  for (int i = 0; i < 4; ++i) grad[i] = Vec3<Real>(r.g[i].x, r.g[i].y, r.g[i].z);
  return true;
}

/// Bending's own correction (projection.hpp's generic one, in the arithmetic the float kernel shares): Δλ =
/// (−k·C − α̃·λ) / (Σ_i w_i|∇_i C|² + α̃), Δp_i = w_i ∇_i C Δλ; false where the generic one gives false.
template <class Real>
inline bool correction(const BendingConstraint<Real>& c, const Vec3<Real> (&p)[4], const Real (&w)[4],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[4], Real& dlambda) {
  using V = detail::bend::V3<Real>;
  const V q[4] = {{p[0].x(), p[0].y(), p[0].z()}, {p[1].x(), p[1].y(), p[1].z()}, {p[2].x(), p[2].y(), p[2].z()},
                  {p[3].x(), p[3].y(), p[3].z()}};
  const auto r = detail::bend::bending_step<Real>(q, w, c.rest, -coeff.k, coeff.alpha_tilde, lambda);
  if (!r.ok) return false;
  dlambda = r.dlambda;
  for (int i = 0; i < 4; ++i) dp[i] = Vec3<Real>(r.dp[i].x, r.dp[i].y, r.dp[i].z);
  return true;
}

/// Angle error |φ − φ0| in rad; negative when a triangle is degenerate (not measured).
template <class Real> double violation(const BendingConstraint<Real>& c, const PositionsView<Real>& x) {
  const double phi = dihedral_angle<double>(detail::position_of<Real>(x, c.particles[0]),
                                            detail::position_of<Real>(x, c.particles[1]),
                                            detail::position_of<Real>(x, c.particles[2]),
                                            detail::position_of<Real>(x, c.particles[3]));
  return phi < 0.0 ? -1.0 : std::abs(phi - double(c.rest));
}

/// Default rest angle: the dihedral angle in x; undefined where a triangle is degenerate.
template <class Real, class X> const char* measure_rest(BendingConstraint<Real>& c, const X& x, FieldMask given) {
  if (given & 1u) return nullptr;
  const auto& p = c.particles;
  c.rest = dihedral_angle<Real>(x.col(p[0]), x.col(p[1]), x.col(p[2]), x.col(p[3]));
  return c.rest < Real(0) ? "a triangle is degenerate, so the rest angle is undefined (give it)" : nullptr;
}

/// A rest angle is in [0, π]; π rounded to float (just above π in double) is accepted, so a float world's rest
/// angles describe a double one.
template <class Real> std::string rest_error(const BendingConstraint<Real>& c) {
  if (!(c.rest >= Real(0) && c.rest <= Real(3.14159265358979323846f)))
    return detail::message("rest angle must be in [0, pi], got ", c.rest);
  return {};
}

}  // namespace pbd
