#pragma once
/// \file leash.hpp
/// Leash: holds one particle within a length L of a fixed point p0, C = L − |p − p0| ≥ 0. A one-sided distance (an
/// inequality): projected only while the leash is stretched (|p − p0| > L); a slack leash exerts nothing.
///
/// This is the throwaway type of tests/new_type (issue 43's proof that a constraint type is one header and one
/// entry in constraint_types.hpp): check_new_type.sh copies it to engine/include/pbd/constraints/leash.hpp in a
/// copy of the tree, adds it to the list, and checks that every pass takes it with no other edit. It is the
/// built-in tether (constraints/tether.hpp) under another name, so that the two can sit in the list together.
#include "pbd/constraints/traits.hpp"
#include "pbd/types.hpp"

#include <array>
#include <cmath>
#include <string>

namespace pbd {

/// Keeps a particle within `length` of `target`.
template <class Real> struct LeashConstraint {
  static constexpr const char* kName = "leash";      ///< name in reports and on the command line
  static constexpr int kArity = 1;                    ///< particles per constraint
  static constexpr bool kInequality = true;           ///< projected only while C < 0 (stretched)
  static constexpr bool kUnitGradients = true;        ///< |∇C| = 1
  static constexpr const char* kNoun = "leash";                           ///< the item in error messages
  static constexpr std::array<const char*, 1> kParticleNames{"particle"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "leashes";          ///< {"particles": [...], "length": L, stiffness...}
  static constexpr SceneForm kSceneForm = SceneForm::listed;   ///< one leash per listed particle, from where it starts
  static constexpr bool kTiesToWorld = true;                   ///< holds its particle to a fixed point
  /// Its violation is the overstretch max(0, |x − p0| − L) in m, reported in millimetres.
  static constexpr Measure kMeasure{"leash_mm", "leash overstretch", "mm", 1000.0};
  std::array<Index, 1> particles;  ///< the leashed particle
  Index set;                       ///< constraint set (stiffness) it belongs to
  Vec3<Real> target;               ///< the fixed point p0, m
  Real length;                     ///< the leash's length L ≥ 0, m
  /// The rest values: the fixed point (default: the particle's position) and the length (default: its distance
  /// from the fixed point; a scene may give it).
  static constexpr auto fields() {
    return std::tuple{Field{"target", "target", &LeashConstraint::target},
                      Field{"length", "length", &LeashConstraint::length, true}};
  }
};

/// C = L − |p − p0|, ∇C = −(p − p0)/|p − p0|. Guard: at the fixed point there is no direction (and the leash is
/// slack unless L = 0): returns false.
template <class Real>
inline bool evaluate(const LeashConstraint<Real>& c, const Vec3<Real> (&p)[1], Real& C, Vec3<Real> (&grad)[1]) {
  const Vec3<Real> d = p[0] - c.target;
  const Real len2 = d.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real len = std::sqrt(len2);
  C = c.length - len;
  grad[0] = d * (Real(-1) / len);
  return true;
}

/// Overstretch max(0, |x − p0| − L) in m.
template <class Real> double violation(const LeashConstraint<Real>& c, const PositionsView<Real>& x) {
  const double d = (detail::position_of<Real>(x, c.particles[0]) - c.target.template cast<double>()).norm();
  return std::max(0.0, d - double(c.length));
}

/// Defaults: the fixed point where the particle is, the length its distance from the fixed point.
template <class Real, class X> const char* measure_rest(LeashConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 1u)) c.target = x.col(c.particles[0]);
  if (!(given & 2u)) c.length = (Vec3<Real>(x.col(c.particles[0])) - c.target).norm();
  return nullptr;
}

/// A fixed point is finite, a length finite and ≥ 0.
template <class Real> std::string rest_error(const LeashConstraint<Real>& c) {
  if (!c.target.allFinite()) return "target is not finite";
  if (!std::isfinite(c.length) || c.length < Real(0))
    return detail::message("length must be finite and >= 0, got ", c.length);
  return {};
}

}  // namespace pbd
