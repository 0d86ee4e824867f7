#pragma once
/// \file anchor.hpp
/// Position anchor: C = |p − p0|, pulls one particle towards a fixed target.
#include "pbd/constraints/traits.hpp"
#include "pbd/types.hpp"

#include <array>

namespace pbd {

/// Pulls a particle to a fixed point (a soft or hard pin for a particle that keeps its mass).
template <class Real> struct AnchorConstraint {
  static constexpr const char* kName = "anchor";  ///< name in reports and on the command line
  static constexpr int kArity = 1;            ///< particles per constraint
  static constexpr bool kInequality = false;  ///< an equality
  static constexpr bool kUnitGradients = true; ///< |∇C| = 1
  static constexpr const char* kNoun = "anchor";                          ///< the item in error messages
  static constexpr std::array<const char*, 1> kParticleNames{"particle"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "anchors";     ///< {"particles": [...], stiffness...}
  static constexpr SceneForm kSceneForm = SceneForm::listed;  ///< one anchor per listed particle, where it starts
  static constexpr bool kTiesToWorld = true;              ///< holds its particle to a fixed point
  static constexpr Measure kMeasure{"anchor_mm", "anchor drift", "mm", 1000.0};  ///< distance, in millimetres
  std::array<Index, 1> particles;             ///< the anchored particle
  Index set;                                  ///< constraint set (stiffness) it belongs to
  Vec3<Real> target;                          ///< the anchor point p0
  /// The rest value: the target p0 in m (default: the particle's current position).
  static constexpr auto fields() { return std::tuple{Field{"target", "target", &AnchorConstraint::target}}; }
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

/// Distance |x − target| in m.
template <class Real> double violation(const AnchorConstraint<Real>& c, const PositionsView<Real>& x) {
  return (detail::position_of<Real>(x, c.particles[0]) - c.target.template cast<double>()).norm();
}

/// Default target: the particle's position in x.
template <class Real, class X> const char* measure_rest(AnchorConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 1u)) c.target = x.col(c.particles[0]);
  return nullptr;
}

/// A target is finite.
template <class Real> std::string rest_error(const AnchorConstraint<Real>& c) {
  return c.target.allFinite() ? std::string() : std::string("target is not finite");
}

}  // namespace pbd
