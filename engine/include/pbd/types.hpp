#pragma once
/// \file types.hpp
/// Basic types shared by the whole engine: particle indices and Eigen vector aliases.
#include <Eigen/Core>
#include <cstdint>
#include <limits>

namespace pbd {

/// Index of a particle or constraint (32 bits keeps constraint structs small).
using Index = std::uint32_t;

/// A 3-vector of the engine's scalar type (float or double).
template <class Real> using Vec3 = Eigen::Matrix<Real, 3, 1>;

/// 3×N column-major matrix: one particle per column, x y z contiguous.
template <class Real> using Matrix3X = Eigen::Matrix<Real, 3, Eigen::Dynamic>;

/// Column vector of per-particle scalars.
template <class Real> using VectorX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

/// Smallest squared length treated as non-zero when a gradient needs a direction:
/// below it a constraint's gradient is undefined and the projection is skipped.
template <class Real> constexpr Real tiny_squared() { return std::numeric_limits<Real>::min() * Real(1e6); }

}  // namespace pbd
