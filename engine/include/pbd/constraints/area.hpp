#pragma once
/// \file area.hpp
/// Triangle area constraint: C = ½|(p2 − p1) × (p3 − p1)| − A0 (Müller et al. 2006).
#include "pbd/constraints/degenerate.hpp"
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/area_math.hpp"
#include "pbd/stiffness.hpp"

#include <array>
#include <cmath>

namespace pbd {

/// Keeps a triangle's area at its rest area A0 (the triangle may shear and bend freely).
template <class Real> struct AreaConstraint {
  static constexpr const char* kName = "area";  ///< name in reports and on the command line
  static constexpr int kArity = 3;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  static constexpr const char* kNoun = "area constraint";                        ///< the item in error messages
  static constexpr std::array<const char*, 3> kParticleNames{"a", "b", "c"};      ///< argument names (Python)
  static constexpr const char* kSceneKey = "area";          ///< a body's key: area on its triangles
  static constexpr SceneForm kSceneForm = SceneForm::mesh;  ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;               ///< between three particles
  static constexpr Measure kMeasure{"area_pct", "area error", "%", 100.0};  ///< relative area error, in percent
  std::array<Index, 3> particles;             ///< the triangle's corners p1, p2, p3
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Real rest;                                  ///< rest area A0 ≥ 0
  /// The rest value: area A0 in m² (default: the current area).
  static constexpr auto fields() { return std::tuple{Field{"rest", "rest area", &AreaConstraint::rest}}; }
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

/// The area constraint's own correction (projection.hpp's generic one, in the arithmetic the AVX2 kernel shares,
/// detail/area_math.hpp): Δλ = (−k·C − α̃·λ) / (Σ_i w_i|∇_i C|² + α̃), Δp_i = w_i ∇_i C Δλ, with the |∇_i C|² in
/// closed form; false where the generic one gives false.
template <class Real>
inline bool correction(const AreaConstraint<Real>& c, const Vec3<Real> (&p)[3], const Real (&w)[3],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[3], Real& dlambda) {
  using V = detail::lane::V3<Real>;
  const V q[3] = {{p[0].x(), p[0].y(), p[0].z()}, {p[1].x(), p[1].y(), p[1].z()}, {p[2].x(), p[2].y(), p[2].z()}};
  const auto r = detail::area::area_step<Real>(q, w, c.rest, -coeff.k, coeff.alpha_tilde, lambda);
  if (!r.ok) return false;
  dlambda = r.dlambda;
  for (int i = 0; i < 3; ++i) dp[i] = Vec3<Real>(r.dp[i].x, r.dp[i].y, r.dp[i].z);
  return true;
}

/// Area of the triangle (a, b, c).
template <class Real> Real triangle_area(const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
  return Real(0.5) * (b - a).cross(c - a).norm();
}

/// Relative area error |A − A0| / A0 (absolute area in m² where A0 = 0).
template <class Real> double violation(const AreaConstraint<Real>& c, const PositionsView<Real>& x) {
  return detail::relative_error(triangle_area<double>(detail::position_of<Real>(x, c.particles[0]),
                                                      detail::position_of<Real>(x, c.particles[1]),
                                                      detail::position_of<Real>(x, c.particles[2])),
                                double(c.rest));
}

/// Default rest area: the triangle's area in x.
template <class Real, class X> const char* measure_rest(AreaConstraint<Real>& c, const X& x, FieldMask given) {
  const auto& p = c.particles;
  if (!(given & 1u)) c.rest = triangle_area<Real>(x.col(p[0]), x.col(p[1]), x.col(p[2]));
  return nullptr;
}

/// A rest area is finite and ≥ 0.
template <class Real> std::string rest_error(const AreaConstraint<Real>& c) {
  if (!std::isfinite(c.rest) || c.rest < Real(0))
    return detail::message("rest area must be finite and >= 0, got ", c.rest);
  return {};
}

}  // namespace pbd
