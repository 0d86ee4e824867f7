#pragma once
/// \file constraint_arrays.hpp
/// The constraints of a world: one contiguous array per constraint type, plus the stiffness of each set.
#include "pbd/constraints/anchor.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/stiffness.hpp"

#include <vector>

namespace pbd {

/// Every persistent constraint of a world, one array per type; a type the scene never uses stays empty.
template <class Real> struct ConstraintArrays {
  std::vector<Stiffness> sets;                     ///< stiffness of each constraint set, indexed by the constraints' `set`
  std::vector<StretchConstraint<Real>> stretch;    ///< distance constraints
  std::vector<AnchorConstraint<Real>> anchor;      ///< position anchors

  /// Total number of persistent constraints of all types.
  std::size_t size() const { return stretch.size() + anchor.size(); }
};

/// One XPBD multiplier per constraint, in the same order as the arrays; reset at every (sub)step.
template <class Real> struct Multipliers {
  std::vector<Real> stretch;    ///< λ of each stretch constraint
  std::vector<Real> anchor;     ///< λ of each anchor
  std::vector<Real> collision;  ///< λ of each collision constraint of the current (sub)step

  /// Sizes every array for `c` and the given number of collisions and sets all λ to 0.
  void reset(const ConstraintArrays<Real>& c, std::size_t collisions) {
    stretch.assign(c.stretch.size(), Real(0));
    anchor.assign(c.anchor.size(), Real(0));
    collision.assign(collisions, Real(0));
  }
};

}  // namespace pbd
