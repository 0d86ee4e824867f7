#pragma once
/// \file serial_solver.hpp
/// The serial reference solver: plain Gauss-Seidel, every constraint in insertion order, one at a time.
#include "pbd/constraint_arrays.hpp"
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/projection.hpp"
#include "pbd/custom_constraints.hpp"

#include <span>

namespace pbd {

/// One Gauss-Seidel sweep over all constraints: type by type (stretch, anchor, bending, area, the user-defined
/// types in `custom` if given, volume, then this step's collisions), each type in insertion order, projecting each constraint in place on `p` (3×N) with inverse
/// masses `w`. `coeff` holds the coefficients of each constraint set; collisions are hard (k = 1, α = 0).
/// `volume` holds the volume targets of the current time (VolumeScratch::set_targets); without it (nullptr) the
/// targets are those of time 0 and a scratch is allocated per sweep.
template <class Real>
void sweep_serial(const ConstraintArrays<Real>& c, std::span<const CollisionConstraint<Real>> collisions,
                  std::span<const SolveCoefficients<Real>> coeff, Real* p, const Real* w, Multipliers<Real>& lambda,
                  VolumeScratch<Real>* volume = nullptr, CustomTypes<Real>* custom = nullptr) {
  lambda.zip(c, [&](const auto& array, std::vector<Real>& lam) {
    for (std::size_t i = 0; i < array.size(); ++i) project(array[i], p, w, coefficients_of(array[i], coeff.data()), lam[i]);
  });
  if (custom)
    for (const auto& t : custom->types()) t->project_serial(p, w, coeff.data());
  if (!c.volume.empty()) {
    VolumeScratch<Real> local;
    project_volumes(c.volume, coeff, p, w, lambda.volume, volume ? *volume : local);
  }
  const SolveCoefficients<Real> hard{Real(1), Real(0)};
  for (std::size_t i = 0; i < collisions.size(); ++i) project(collisions[i], p, w, hard, lambda.collision[i]);
}

}  // namespace pbd
