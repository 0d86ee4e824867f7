#pragma once
// A step's sub-steps (private): steps 1–5 of engine/src/solve/solver.hpp's design note, one function run on one of two
// runners (substep.cpp). Outside solve/ and contact/, since a sub-step runs both (contacts in step 3, the solve in
// step 4) and neither of those includes the other.
#include "solve/solver.hpp"

#include <functional>

namespace pbd::detail {

/// What one step's sub-steps work on: the world's parts and the step's inputs (run_substeps).
template <class Real> struct StepContext {
  Model<Real>& model;
  State<Real>& state;
  Scratch<Real>& scratch;
  const StepParams<Real>& params;
  const ParallelConfig& config;
  const Real* forces;  ///< external forces (N, 3 per particle) for the whole step, or nullptr
  /// The world's force callback (may be empty), called at every sub-step.
  const std::function<void(double, Eigen::Ref<const Matrix3X<Real>>, Eigen::Ref<Matrix3X<Real>>)>* callback;
  Real h;                      ///< sub-step length, s
  long long first_substep;     ///< number of the step's first sub-step, round(time / dt) · substeps
  bool flow = false;           ///< fibers flow plastically after each sub-step's sweeps (fibers.hpp)
};

/// What run_substeps reports (seconds summed over the sub-steps).
struct SubstepsReport {
  bool on_team = false;            ///< one team ran the whole step
  int threads = 0;                 ///< most threads that ran one sub-step's sweeps together
  int chebyshev_fallbacks = 0;     ///< sub-steps whose Chebyshev guard stopped the acceleration
  double seconds_integrate = 0.0;  ///< steps 1, 2 and 5
  double seconds_collisions = 0.0; ///< step 3
  double seconds_solve = 0.0;      ///< step 4 (with each sub-step's λ reset)
  double seconds_waiting = 0.0;    ///< of seconds_solve, the sweeps' threads' time waiting for one another
  double seconds_hierarchy = 0.0;  ///< of seconds_solve, the hierarchy's passes
};

/// Every sub-step of a step (steps 1–5 each; x and p trade places after each, so an odd count leaves the positions
/// in the scratch's buffer: the caller puts them back). One sub-step function runs them on one of two runners,
/// chosen here and nowhere else: one team of threads (team.hpp) for the whole step when the step is only predict,
/// sweeps and update (step_on_team: a parallel Gauss-Seidel solver, no Chebyshev acceleration, no user type, volume,
/// collider, force callback, free body or plastic flow, and a model whose sweeps would form a team anyway); otherwise sub-step by
/// sub-step with loops that fork (run_range), where solve() may still hold a team for its sweeps. The bits are the
/// same on both. An error (the force callback's, an allocation's) propagates with the state half-stepped: the caller
/// puts it back (step_undo.hpp).
template <class Real> SubstepsReport run_substeps(StepContext<Real>& context);

/// Whether a step may run on one team (run_substeps), from what the step and the model hold.
template <class Real> bool step_on_team(const StepContext<Real>& context);

}  // namespace pbd::detail
