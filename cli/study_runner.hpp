#pragma once
// Running one combination of `pbd study` (timed, then measured) and computing the converged reference.
#include "pbd/io/scene.hpp"
#include "study_options.hpp"
#include "study_record.hpp"

namespace pbd::cli {

/// One combination to run.
struct Combination {
  StudySolver solver;            ///< solver
  int threads = 1;               ///< threads of the task arena it runs in
  int iterations = 1;            ///< iterations per substep
  int substeps = 1;              ///< substeps per step
  int steps = 1;                 ///< steps per run
  bool double_precision = false; ///< World<double> instead of World<float>
};

/// The reference of `scene` at `substeps` and `steps`: the serial solver in double with `iterations` per substep
/// (its final positions); also measures how converged it is against iterations / 2, per step (from the same states)
/// and over the whole trajectory.
Reference compute_reference(const Scene& scene, int substeps, int steps, int iterations);

/// Runs `c` once untimed (warm-up) and `repeats` times timed, each run from the scene's initial state, inside a
/// tbb::task_arena of c.threads. The warm-up run also measures the per-step error: at 10 steps spread over the run
/// (the last included), the state before the step is also stepped by the reference solver (serial, double,
/// ref.iterations) and the two results are compared. The final state is measured against ref (trajectory error,
/// violations, energy drift).
Record run_combination(const Scene& scene, const Combination& c, const Reference& ref, int repeats);

/// Relative cost of running `c` (`repeats` + 1 runs) in the units of estimated_reference_cost, for progress.
double estimated_cost(const Scene& scene, const Combination& c, int repeats, int reference_iterations);
/// Relative cost of compute_reference.
double estimated_reference_cost(const Scene& scene, int substeps, int steps, int iterations);

}  // namespace pbd::cli
