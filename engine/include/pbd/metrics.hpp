#pragma once
/// \file metrics.hpp
/// Error measures of a world's state: how far its constraints are from being satisfied, how far its positions are
/// from a reference, its energy, and a bitwise hash of its positions. All sums are taken in double.
///
/// Normalized violation of one constraint, per type, and the unit it is reported in (Measure). A built-in type's
/// header defines its own `violation(c, x)` and kMeasure (stretch.hpp, ...: relative stretch in %, anchor distance
/// in mm, angle error in rad, relative area error in %); the others are measured here:
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

/// The violation of every constraint of built-in type C (its header's `violation`; constraints it cannot measure,
/// such as a degenerate bending pair, are left out).
template <class C, class Real> Violation violation_of(const World<Real>& world) {
  const auto x = world.positions();
  ViolationAccumulator acc;
  for (const C& c : world.template constraints<C>()) {
    const double e = violation(c, x);
    if (e >= 0.0) acc.add(e);  // negative: not measurable (degenerate), left out
  }
  return acc.result();
}

/// Relative stretch of every stretch constraint: violation_of<StretchConstraint<Real>>.
template <class Real> Violation stretch_violation(const World<Real>& world) {
  return violation_of<StretchConstraint<Real>>(world);
}

/// Penetration depth max(0, −C) of every collider for every movable particle at the current positions (m).
template <class Real> Violation penetration(const World<Real>& world);

/// Overlap of every particle contact of the last sub-step at the current positions, as a fraction of its radii sum.
template <class Real> Violation particle_overlap(const World<Real>& world);

/// Relative error |V − V_target| / V_target of every volume constraint, target taken at world.time().
template <class Real> Violation volume_violation(const World<Real>& world);

/// One entry per constraint type the world has (built-in fixed-arity types in solver order, then "volume", then
/// "collision" if it has colliders, then "particle contact" if a contact body has a radius), each with its Measure;
/// types without constraints are left out.
template <class Real> std::vector<NamedViolation> constraint_violations(const World<Real>& world);

/// A violation type's name and how it is reported.
struct NamedMeasure {
  std::string type;  ///< "stretch", ..., "volume", "collision", "particle contact"
  Measure measure;   ///< its report key, label, unit and scale
};
/// Every violation type constraint_violations can report, in its order, with its Measure.
std::vector<NamedMeasure> violation_measures();
/// The Measure of violation type `type` (violation_measures()), or nullptr for a type it does not know.
const Measure* find_measure(const std::string& type);

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
