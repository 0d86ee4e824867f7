#pragma once
/// \file tether.hpp
/// Tether: holds one particle within a length L of a fixed point p0, C = L − |p − p0| ≥ 0. A one-sided distance (an
/// inequality): projected only while the tether is stretched (|p − p0| > L); a slack tether exerts nothing.
///
/// This is the throwaway type of tests/new_type (issue 43's proof that a constraint type is one header and one
/// entry in constraint_types.hpp): check_new_type.sh copies it to engine/include/pbd/constraints/tether.hpp in a
/// copy of the tree, adds it to the list, and checks that every pass takes it with no other edit.
#include "pbd/constraints/traits.hpp"
#include "pbd/types.hpp"

#include <array>
#include <cmath>
#include <string>

namespace pbd {

/// Keeps a particle within `length` of `target`.
template <class Real> struct TetherConstraint {
  static constexpr const char* kName = "tether";      ///< name in reports and on the command line
  static constexpr int kArity = 1;                    ///< particles per constraint
  static constexpr bool kInequality = true;           ///< projected only while C < 0 (stretched)
  static constexpr bool kUnitGradients = true;        ///< |∇C| = 1
  static constexpr const char* kNoun = "tether";                           ///< the item in error messages
  static constexpr std::array<const char*, 1> kParticleNames{"particle"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "tethers";          ///< {"particles": [...], "length": L, stiffness...}
  static constexpr SceneForm kSceneForm = SceneForm::listed;   ///< one tether per listed particle, from where it starts
  static constexpr bool kTiesToWorld = true;                   ///< holds its particle to a fixed point
  /// Its violation is the overstretch max(0, |x − p0| − L) in m, reported in millimetres.
  static constexpr Measure kMeasure{"tether_mm", "tether overstretch", "mm", 1000.0};
  std::array<Index, 1> particles;  ///< the tethered particle
  Index set;                       ///< constraint set (stiffness) it belongs to
  Vec3<Real> target;               ///< the fixed point p0, m
  Real length;                     ///< the tether's length L ≥ 0, m
  /// The rest values: the fixed point (default: the particle's position) and the length (default: its distance
  /// from the fixed point; a scene may give it).
  static constexpr auto fields() {
    return std::tuple{Field{"target", "target", &TetherConstraint::target},
                      Field{"length", "length", &TetherConstraint::length, true}};
  }
};

/// C = L − |p − p0|, ∇C = −(p − p0)/|p − p0|. Guard: at the fixed point there is no direction (and the tether is
/// slack unless L = 0): returns false.
template <class Real>
inline bool evaluate(const TetherConstraint<Real>& c, const Vec3<Real> (&p)[1], Real& C, Vec3<Real> (&grad)[1]) {
  const Vec3<Real> d = p[0] - c.target;
  const Real len2 = d.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real len = std::sqrt(len2);
  C = c.length - len;
  grad[0] = d * (Real(-1) / len);
  return true;
}

/// Overstretch max(0, |x − p0| − L) in m.
template <class Real> double violation(const TetherConstraint<Real>& c, const PositionsView<Real>& x) {
  const double d = (detail::position_of<Real>(x, c.particles[0]) - c.target.template cast<double>()).norm();
  return std::max(0.0, d - double(c.length));
}

/// Defaults: the fixed point where the particle is, the length its distance from the fixed point.
template <class Real, class X> const char* measure_rest(TetherConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 1u)) c.target = x.col(c.particles[0]);
  if (!(given & 2u)) c.length = (Vec3<Real>(x.col(c.particles[0])) - c.target).norm();
  return nullptr;
}

/// A fixed point is finite, a length finite and ≥ 0.
template <class Real> std::string rest_error(const TetherConstraint<Real>& c) {
  if (!c.target.allFinite()) return "target is not finite";
  if (!std::isfinite(c.length) || c.length < Real(0))
    return detail::message("length must be finite and >= 0, got ", c.length);
  return {};
}

}  // namespace pbd
