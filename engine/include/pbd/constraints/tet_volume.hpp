#pragma once
/// \file tet_volume.hpp
/// Tetrahedron volume constraint: C = V − V0 with V = (p1 − p0) × (p2 − p0) · (p3 − p0) / 6, the signed volume
/// (Müller et al. 2006, §4.3; Jolt's soft bodies keep their tets' volume the same way).
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/detail/tet_volume_math.hpp"
#include "pbd/stiffness.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <string>

namespace pbd {

/// Keeps a tet's signed volume at its rest volume V0 > 0; the tet may shear freely. Signed, so an inverted tet
/// (V < 0) is pushed back through zero instead of settling inside out at −V0.
template <class Real> struct TetVolumeConstraint {
  static constexpr const char* kName = "tet_volume";  ///< name in reports and on the command line
  static constexpr int kArity = 4;                    ///< particles per constraint
  static constexpr bool kInequality = false;          ///< an equality
  static constexpr const char* kNoun = "tet volume constraint";                      ///< the item in messages
  static constexpr std::array<const char*, 4> kParticleNames{"p0", "p1", "p2", "p3"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "tet_volume";    ///< a tet body's key: one on each of its tets
  static constexpr SceneForm kSceneForm = SceneForm::mesh;  ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;               ///< between four particles
  static constexpr bool kBreaksWithFibers = true;           ///< torn when a fiber along an edge breaks (traits.hpp)
  static constexpr bool kColoredInteriors = true;           ///< block solver: interiors color by color (traits.hpp)
  static constexpr Measure kMeasure{"tet_volume_pct", "tet volume error", "%", 100.0};  ///< |V − V0| / V0, in %
  std::array<Index, 4> particles;  ///< the corners p0..p3, positively oriented at rest
  Index set;                       ///< constraint set (stiffness) it belongs to
  Real rest;                       ///< rest volume V0 > 0, m³
  /// The rest value: volume V0 in m³ (default: the current signed volume).
  static constexpr auto fields() { return std::tuple{Field{"rest", "rest volume", &TetVolumeConstraint::rest}}; }
};

/// Signed volume of the tet (p0, p1, p2, p3).
template <class Real>
Real tet_volume(const Vec3<Real>& p0, const Vec3<Real>& p1, const Vec3<Real>& p2, const Vec3<Real>& p3) {
  return (p1 - p0).cross(p2 - p0).dot(p3 - p0) / Real(6);
}

/// C = V − V0, ∇1 C = (p2 − p0) × (p3 − p0) / 6, ∇2 C = (p3 − p0) × (p1 − p0) / 6, ∇3 C = (p1 − p0) × (p2 − p0) / 6,
/// ∇0 C = −∇1 C − ∇2 C − ∇3 C. A tet collapsed onto a line has all gradients zero: the projection's denominator
/// is then 0 and it moves nothing (projection.hpp).
template <class Real>
inline bool evaluate(const TetVolumeConstraint<Real>& c, const Vec3<Real> (&p)[4], Real& C, Vec3<Real> (&grad)[4]) {
  const Vec3<Real> a = p[1] - p[0], b = p[2] - p[0], d = p[3] - p[0];
  const Real sixth = Real(1) / Real(6);
  grad[1] = sixth * b.cross(d);
  grad[2] = sixth * d.cross(a);
  grad[3] = sixth * a.cross(b);
  grad[0] = -grad[1] - grad[2] - grad[3];
  C = grad[3].dot(d) - c.rest;
  return true;
}

/// The tet volume constraint's own correction (projection.hpp's generic one, in the arithmetic the AVX2 kernel
/// shares, detail/tet_volume_math.hpp): the gradients above, Δλ = (−k·C − α̃·λ) / (α̃ + Σ_i w_i|∇_i C|²),
/// Δp_i = w_i ∇_i C Δλ; false where the denominator is not positive.
template <class Real>
inline bool correction(const TetVolumeConstraint<Real>& c, const Vec3<Real> (&p)[4], const Real (&w)[4],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[4], Real& dlambda) {
  using V = detail::lane::V3<Real>;
  const V q[4] = {{p[0].x(), p[0].y(), p[0].z()}, {p[1].x(), p[1].y(), p[1].z()},
                  {p[2].x(), p[2].y(), p[2].z()}, {p[3].x(), p[3].y(), p[3].z()}};
  const auto r = detail::tet_volume::tet_volume_step<Real>(q, w, c.rest, -coeff.k, coeff.alpha_tilde, lambda);
  if (!r.ok) return false;
  dlambda = r.dlambda;
  for (int i = 0; i < 4; ++i) dp[i] = Vec3<Real>(r.dp[i].x, r.dp[i].y, r.dp[i].z);
  return true;
}

/// Relative volume error |V − V0| / V0.
template <class Real> double violation(const TetVolumeConstraint<Real>& c, const PositionsView<Real>& x) {
  const auto& q = c.particles;
  return detail::relative_error(tet_volume<double>(detail::position_of<Real>(x, q[0]), detail::position_of<Real>(x, q[1]),
                                                   detail::position_of<Real>(x, q[2]), detail::position_of<Real>(x, q[3])),
                                double(c.rest));
}

/// Default rest volume: the tet's signed volume in x.
template <class Real, class X> const char* measure_rest(TetVolumeConstraint<Real>& c, const X& x, FieldMask given) {
  const auto& q = c.particles;
  if (!(given & 1u))
    c.rest = tet_volume<Real>(x.col(q[0]), x.col(q[1]), x.col(q[2]), x.col(q[3]));
  return nullptr;
}

/// A rest volume is finite and > 0 (a tet inverted or flat at rest has none).
template <class Real> std::string rest_error(const TetVolumeConstraint<Real>& c) {
  if (!std::isfinite(c.rest) || !(c.rest > Real(0)))
    return detail::message("rest volume must be finite and > 0 (the tet is inverted or flat), got ", c.rest);
  return {};
}

}  // namespace pbd
