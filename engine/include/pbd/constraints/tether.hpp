#pragma once
/// \file tether.hpp
/// Tether, a long-range attachment (Kim, Chentanez and Müller 2012): holds one particle within a length L of a fixed
/// point p0, the position of a pin (or an anchor's target) it hangs from. One-sided: the solver's inequalities hold
/// when C ≥ 0, so C = L − |p − p0| (the paper's |p − p0| − L ≤ 0); a tether is projected only while stretched,
/// |p − p0| > L, and never pushes: a particle within L of p0 is not touched, bit for bit.
///
/// A tether moves its one particle alone, so tethers of distinct particles never conflict: one tether per particle
/// (World::add_tethers with TetherTo::nearest) is one color, projected in parallel over the particles. It reads only
/// its own particle and its own target, so nothing it reads is written by another tether of its color. Last in the
/// list, so a Gauss-Seidel sweep ends with no particle beyond its tether.
///
/// `pin` is not a rest value: add_tethers (pbd/tethers.hpp) records the particle a tether hangs from, and at the
/// start of each step the world sets the target of every tether whose pin is pinned (inverse mass 0) to that pin's
/// position (World::step), so a host that moves a pinned particle between steps drags its tethers along. A pinned
/// particle does not move within a step, so the target is exact for every sub-step. A tether whose pin is not pinned
/// (an anchored particle: the target is its anchor's target) or that has no pin (kNoPin, e.g. add_tether) keeps its
/// target.
#include "pbd/constraints/traits.hpp"
#include "pbd/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
  /// A body's "tethers" key generates tethers (pbd::io's scenes); this listed form, {"particles": [...], "target":
  /// [x, y, z], "length": L, stiffness...}, names them one by one, so it has a key of its own.
  static constexpr const char* kSceneKey = "tether_list";
  static constexpr SceneForm kSceneForm = SceneForm::listed;   ///< one tether per listed particle
  static constexpr bool kTiesToWorld = true;                   ///< holds its particle to a fixed point
  /// Its violation is the overshoot max(0, |x − p0| − L) in m, reported in millimetres.
  static constexpr Measure kMeasure{"tether_mm", "tether overshoot", "mm", 1000.0};
  static constexpr Index kNoPin = std::numeric_limits<Index>::max();  ///< `pin` of a tether to a fixed point alone
  std::array<Index, 1> particles;  ///< the tethered particle
  Index set;                       ///< constraint set (stiffness) it belongs to
  Vec3<Real> target;               ///< the fixed point p0, m
  Real length;                     ///< the tether's length L ≥ 0, m
  Index pin = kNoPin;              ///< the particle it hangs from (its target follows it while pinned), or kNoPin
  /// The rest values: the fixed point (default: the particle's position; a scene may give it) and the length
  /// (default: its distance from the fixed point; a scene may give it).
  static constexpr auto fields() {
    return std::tuple{Field{"target", "target", &TetherConstraint::target, true},
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

/// Overshoot max(0, |x − p0| − L) in m.
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
