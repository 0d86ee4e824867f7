#pragma once
/// \file constraint_arrays.hpp
/// The constraints of a world: one contiguous array per constraint type, plus the stiffness of each set.
#include "pbd/constraints/anchor.hpp"
#include "pbd/constraints/area.hpp"
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/stiffness.hpp"

#include <vector>

namespace pbd {

/// Coefficients of constraint `c`: those of its set, or hard (k = 1, α̃ = 0) for types without a set (collisions).
template <class Constraint, class Real>
inline SolveCoefficients<Real> coefficients_of(const Constraint& c, const SolveCoefficients<Real>* coeff) {
  if constexpr (requires { c.set; }) return coeff[c.set];
  else return SolveCoefficients<Real>{Real(1), Real(0)};
}

/// Every persistent constraint of a world, one array per type; a type the scene never uses stays empty.
template <class Real> struct ConstraintArrays {
  std::vector<Stiffness> sets;                     ///< stiffness of each constraint set, indexed by the constraints' `set`
  std::vector<StretchConstraint<Real>> stretch;    ///< distance constraints
  std::vector<AnchorConstraint<Real>> anchor;      ///< position anchors
  std::vector<BendingConstraint<Real>> bending;    ///< dihedral bending on pairs of triangles
  std::vector<AreaConstraint<Real>> area;          ///< triangle areas
  VolumeConstraints<Real> volume;                  ///< closed-mesh volumes (not fixed-arity: projected after the others)

  /// Total number of persistent constraints of all types.
  std::size_t size() const { return stretch.size() + anchor.size() + bending.size() + area.size() + volume.size(); }

  /// Calls f(array) for each fixed-arity constraint type's array, in solver order (the one place that lists the
  /// types; volume constraints are handled on their own, after these).
  template <class F> void for_each(F&& f) const {
    f(stretch);
    f(anchor);
    f(bending);
    f(area);
  }
};

/// One XPBD multiplier per constraint, in the same order as the arrays; reset at every (sub)step.
template <class Real> struct Multipliers {
  std::vector<Real> stretch;    ///< λ of each stretch constraint
  std::vector<Real> anchor;     ///< λ of each anchor
  std::vector<Real> bending;    ///< λ of each bending constraint
  std::vector<Real> area;       ///< λ of each area constraint
  std::vector<Real> volume;     ///< λ of each volume constraint
  std::vector<Real> collision;  ///< λ of each collision constraint of the current (sub)step

  /// Sizes every array for `c` (ConstraintArrays or ColoredConstraints) and `collisions`, and sets all λ to 0.
  template <class Arrays> void reset(const Arrays& c, std::size_t collisions) {
    stretch.assign(c.stretch.size(), Real(0));
    anchor.assign(c.anchor.size(), Real(0));
    bending.assign(c.bending.size(), Real(0));
    area.assign(c.area.size(), Real(0));
    volume.assign(c.volume.size(), Real(0));
    collision.assign(collisions, Real(0));
  }

  /// True when every array already has the size reset(c, collisions) would give it.
  template <class Arrays> bool sized_for(const Arrays& c, std::size_t collisions) const {
    return stretch.size() == c.stretch.size() && anchor.size() == c.anchor.size() &&
           bending.size() == c.bending.size() && area.size() == c.area.size() && volume.size() == c.volume.size() &&
           collision.size() == collisions;
  }

  /// Calls f(array_of_constraints, its_lambdas) for each fixed-arity persistent type of `c` (same order as for_each).
  template <class Arrays, class F> void zip(const Arrays& c, F&& f) {
    f(c.stretch, stretch);
    f(c.anchor, anchor);
    f(c.bending, bending);
    f(c.area, area);
  }
};

}  // namespace pbd
