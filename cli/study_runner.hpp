#pragma once
// Running `pbd study`'s measurements: the converged reference of a scene, a group of combinations timed in
// interleaved rounds (A B C A B C ...), and the same-run shared-nothing reference of thread scaling.
#include "pbd/io/scene.hpp"
#include "load_monitor.hpp"
#include "study_options.hpp"
#include "study_record.hpp"

#include <functional>

namespace pbd::cli {

/// One combination to run.
struct Combination {
  StudySolver solver;            ///< solver
  int threads = 1;               ///< threads of the task arena it runs in
  Split split;                   ///< substeps × iterations
  int steps = 1;                 ///< steps per run
  bool double_precision = false; ///< World<double> instead of World<float>
};

/// The scene as the study runs it: sizes, steps, its primary error measure (the scene's `primary_error`, else
/// volume if it has any, else stretch, else its first type). Throws pbd::Error naming the scene's file when it
/// states a primary error it has no constraint for.
SceneInfo scene_info(const Scene& scene, int steps);

/// The reference of `scene` over `info.steps` steps: the serial solver in double at `split`. Keeps its state at
/// up to 5 sampled steps (spread over the run, the last included) with the positions after each, and measures how
/// converged it is: one step at half the iterations, and one at half the substeps, from the last two sampled states.
/// `progress(steps done)` is called after every step.
Reference compute_reference(const Scene& scene, const SceneInfo& info, Split split,
                            const std::function<void(int)>& progress = {});

/// Runs every combination of `group` (same scene, split and precision): each once untimed (warm-up; it also
/// measures the errors and the hash), then `repeats` interleaved rounds in which each takes one timed sample in its
/// own tbb::task_arena: runs from the scene's initial state, repeated until the sample lasts 20 ms (a run of a tiny
/// scene is too short to time alone). With a reference, each combination also steps once from each
/// of the reference's sampled states (ref_error_mm) and its final state is compared with the reference's
/// (trajectory_error_mm). `load` samples the machine before each timed run.
/// `progress(done, total)` is called after each run (warm-ups and timed samples).
std::vector<Record> run_group(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                              const Reference* ref, int repeats, LoadMonitor& load,
                              const std::function<void(int, int)>& progress = {});

/// The same-run shared-nothing reference at `threads`: `threads` copies of the world of `part` (serial solver at
/// `split`; the caller passes 1/threads of the scene's data where it can be split), each stepped on its own thread
/// in its own one-thread arena at once, against one alone; per interleaved round threads × t(alone) / t(together).
/// Returns the rounds' speed-ups.
std::vector<double> shared_nothing_speedups(const Scene& part, int steps, Split split, int threads, int rounds);

/// Relative cost of a group and of a reference, for the estimate of the time left.
double estimated_group_cost(const SceneInfo& info, const std::vector<Combination>& group, int repeats);
double estimated_reference_cost(const SceneInfo& info, Split split);

}  // namespace pbd::cli
