#pragma once
/// \file metrics.hpp
/// Error measures of a world's state: how far its constraints are from being satisfied, how far its positions are
/// from a reference, its energy, and a bitwise hash of its positions. All sums are taken in double.
///
/// Normalized violation of one constraint, per type (a new fixed-arity type needs one `violation` overload below):
///   stretch    |(|x_a − x_b| − d)| / d            relative stretch (absolute length in m where d = 0)
///   anchor     |x − target|                       metres
///   bending    |φ − φ0|                           radians (a degenerate triangle is not measured)
///   area       |A − A0| / A0                      relative area error (absolute area in m² where A0 = 0)
///   volume     |V − V_target(t)| / V_target(t)    relative volume error against the target at world.time()
///   collision  max(0, depth)                      penetration in metres, per (movable particle, collider), the
///                                                 particle's contact radius included
///   particle contact  max(0, 1 − |x_a − x_b| / (r_a + r_b))  overlap as a fraction of the radii sum, per particle
///                                                 contact of the last sub-step (pairs that came that close)
#include "pbd/violation.hpp"
#include "pbd/world.hpp"

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace pbd {

/// Read-only view of 3×N positions (a Matrix3X or the map World::positions() returns), no copy.
/// (Non-deduced, so Real comes from the constraint and any matrix or map converts.)
template <class Real> using PositionsView = std::type_identity_t<Eigen::Ref<const Matrix3X<Real>>>;

/// Relative stretch |(|x_a − x_b| − d)| / d of one stretch constraint (absolute length where d = 0).
template <class Real> double violation(const StretchConstraint<Real>& c, const PositionsView<Real>& x);
/// Distance |x − target| of one anchor, metres.
template <class Real> double violation(const AnchorConstraint<Real>& c, const PositionsView<Real>& x);
/// Angle error |φ − φ0| of one bending constraint, radians; negative when a triangle is degenerate (not measured).
template <class Real> double violation(const BendingConstraint<Real>& c, const PositionsView<Real>& x);
/// Relative area error |A − A0| / A0 of one triangle (absolute area where A0 = 0).
template <class Real> double violation(const AreaConstraint<Real>& c, const PositionsView<Real>& x);

/// Relative stretch of every stretch constraint.
template <class Real> Violation stretch_violation(const World<Real>& world);

/// Penetration depth max(0, −C) of every collider for every movable particle at the current positions (m).
template <class Real> Violation penetration(const World<Real>& world);

/// Overlap of every particle contact of the last sub-step at the current positions, as a fraction of its radii sum.
template <class Real> Violation particle_overlap(const World<Real>& world);

/// Relative error |V − V_target| / V_target of every volume constraint, target taken at world.time().
template <class Real> Violation volume_violation(const World<Real>& world);

/// One entry per constraint type the world has (built-in fixed-arity types in solver order, then "volume", then "collision"
/// if it has colliders); types without constraints are left out.
template <class Real> std::vector<NamedViolation> constraint_violations(const World<Real>& world);

/// RMS and maximum over every item of every entry of `v` pooled together (count = total items).
Violation pooled(const std::vector<NamedViolation>& v);

/// Kinetic and gravitational potential energy of the movable particles (pinned ones have infinite mass and are
/// left out), in joules: E_kin = Σ ½ m |v|², E_pot = −Σ m g·x (zero at the origin).
struct Energy {
  double kinetic = 0.0;    ///< Σ ½ m |v|²
  double potential = 0.0;  ///< −Σ m g·x
  double total() const { return kinetic + potential; }  ///< kinetic + potential
};
/// The energy of `world` (gravity from its parameters).
template <class Real> Energy energy(const World<Real>& world);
/// Total mass of the movable particles, kg.
template <class Real> double movable_mass(const World<Real>& world);

/// RMS and maximum over particles of |x_i − ref_i| (metres). Throws pbd::Error if the particle counts differ.
template <class Real> Violation position_distance(const World<Real>& world, const Matrix3X<double>& ref);

/// Length of the diagonal of the particles' bounding box (metres; 0 for fewer than two distinct positions).
template <class Real> double bounding_diagonal(const World<Real>& world);

/// 64-bit FNV-1a hash of the bytes of the positions (3×N Real, column-major): equal hashes mean bitwise equal
/// states, e.g. across thread counts.
template <class Real> std::uint64_t position_hash(const World<Real>& world);

}  // namespace pbd
