#pragma once
/// \file degenerate.hpp
/// The scale-free test shared by the triangle-based constraints: when are two directions parallel?
#include "pbd/types.hpp"

#include <Eigen/Geometry>
#include <limits>

namespace pbd {

/// Sine of the angle below which two directions count as parallel (64 ulps of 1: 7.6e-6 in float, 1.4e-14 in
/// double). Scale-free: a 1 cm triangle and a 1 km triangle are judged alike.
template <class Real> constexpr Real parallel_sine() { return Real(64) * std::numeric_limits<Real>::epsilon(); }

/// True when u × v (`cross`, already computed) is too short to give a direction: |u × v|² ≤ sin²·|u|²|v|²
/// (u, v parallel at this precision, or one of them zero) or below tiny_squared (underflow).
template <class Real>
inline bool degenerate_cross(const Vec3<Real>& cross, const Vec3<Real>& u, const Vec3<Real>& v) {
  const Real c2 = cross.squaredNorm();
  const Real s = parallel_sine<Real>();
  return !(c2 > tiny_squared<Real>()) || !(c2 > s * s * u.squaredNorm() * v.squaredNorm());
}

}  // namespace pbd
