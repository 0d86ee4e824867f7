#pragma once
/// \file step_params.hpp
/// What World::step() does: time step, sub-steps, sweeps, forces, the solver; and what it reports afterwards.
#include "pbd/solver.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <vector>

namespace pbd {

/// Parameters of step(); validated by World::set_params.
template <class Real> struct StepParams {
  Real dt = Real(1) / Real(60);              ///< time step in seconds, > 0
  int substeps = 1;                          ///< sub-steps per step, ≥ 1, each with its own sweeps
  int iterations = 10;                       ///< Gauss-Seidel sweeps per sub-step, ≥ 0
  Vec3<Real> gravity{Real(0), Real(0), Real(-9.81)};  ///< acceleration applied to every movable particle, m/s²
  Real damping = 0;                          ///< velocity damping rate in 1/s, ≥ 0: v ← v·max(0, 1 − damping·h), before forces
  Real collision_margin = Real(0.01);        ///< contacts are generated for particles ending within this distance, m, ≥ 0
  Solver solver = Solver::colored;           ///< which solver step() runs
  Real jacobi_omega = 1;                     ///< Jacobi over-relaxation factor ω, in (0, 2)
  SweepOrder sweep_order = SweepOrder::forward;  ///< Gauss-Seidel sweep order (symmetric: for closed bodies)
};

/// What the last step() did and how long each phase took (wall-clock seconds, summed over sub-steps).
struct StepStats {
  double seconds = 0.0;             ///< the whole step
  double seconds_integrate = 0.0;   ///< forces, damping, prediction and velocity update
  double seconds_collisions = 0.0;  ///< generating (and coloring) collision constraints
  double seconds_coloring = 0.0;    ///< coloring persistent constraints (only when they changed)
  double seconds_solve = 0.0;       ///< the sweeps
  int substeps = 0;                 ///< sub-steps taken
  int sweeps = 0;                   ///< sweeps taken (substeps × iterations)
  Index colors = 0;                 ///< colors of the persistent constraints (0 for the serial solver)
  std::size_t collisions = 0;       ///< collision constraints of the last sub-step
  std::vector<NamedViolation> violation;  ///< per type, at the end of the step (only with measure_violation on)
};

}  // namespace pbd
