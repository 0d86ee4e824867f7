#pragma once
// Running `pbd study`'s measurements: a group of combinations (errors from one untimed run, timings in interleaved
// rounds A B C A B C ...), the reference runs of a scene and the records' distance from them, and the same-run
// shared-nothing reference of thread scaling.
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
/// volume if it has any, else stretch, else its first type; a chain's is its extension against α·T), the steps its
/// errors are averaged over, its name (base, or base+variant). Throws pbd::Error naming the scene's file when it
/// states a primary error it has no constraint for.
SceneInfo scene_info(const Scene& scene, int steps, const std::string& base, const std::string& variant = "plain");

/// One whole run of the reference solver at one budget.
struct ReferenceRun {
  Split split;                         ///< its budget
  Errors mean, final;                  ///< its errors, averaged over the run and at the end
  Matrix3X<double> positions;          ///< final positions
  std::vector<ReferenceSample> samples;  ///< with `sampled`: up to 5 steps, with the step at half the budget
  double step_change_mm = 0.0;         ///< RMS over the samples of the half-budget step against the full one
  double seconds = 0.0;                ///< wall time
};

/// Half of a budget: half the substeps, or half the iterations when there is one substep.
Split half_of(Split split);

/// Runs `scene` over info.steps steps with `solver` in double at `split` on `threads` (one for a one-thread
/// solver); with `sampled`, keeps the state at up to 5 sampled steps (spread over the run, the last included) and
/// steps each also at half the budget. `progress(steps done)` is called after every step.
ReferenceRun reference_run(const Scene& scene, const SceneInfo& info, const StudySolver& solver, int threads,
                           Split split, bool sampled, const std::function<void(int)>& progress = {});

/// The reference of `info.base` from a sampled run at its budget and a run at half of it (its own changes).
Reference make_reference(const SceneInfo& info, const StudySolver& solver, int threads, const ReferenceRun& full,
                         const ReferenceRun& half);

/// Each record's distance from the reference: one step from each of its samples against its own step
/// (ref_error_mm), and the final positions against its final positions (trajectory_error_mm). `scene` is the
/// records' own (variant) scene; `solvers` names their solvers.
void compare_with_reference(const Scene& scene, const std::vector<StudySolver>& solvers, const Reference& ref,
                            std::vector<Record*>& records);

/// Runs every combination of `group` (same scene, split and precision). Each solver makes one untimed whole run on
/// its most threads that measures the errors after every step (averaged, and at the end) and the final state; each
/// combination then makes an untimed warm-up and `repeats` timed samples (2 for a long run) in interleaved rounds,
/// each in its own tbb::task_arena, from the scene's initial state over the whole run, or over its first steps when
/// one thread would take over 0.5 s for the whole (at least 2). A sample is repeated until it lasts 20 ms.
/// Every thread count of a solver must end its timed runs in the same bits (else `repeatable` is false).
/// `load` samples the machine before each timed run. `progress(done, total)` is called after each run.
std::vector<Record> run_group(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                              int repeats, LoadMonitor& load, const std::function<void(int, int)>& progress = {});

/// The same-run shared-nothing reference at `threads`: `threads` copies of the world of `part` (serial solver at
/// `split`; the caller passes 1/threads of the scene's data where it can be split), each stepped on its own thread
/// in its own one-thread arena at once, against one alone; per interleaved round threads × t(alone) / t(together).
/// Returns the rounds' speed-ups.
std::vector<double> shared_nothing_speedups(const Scene& part, int steps, Split split, int threads, int rounds);

/// Estimated cost of a group and of a reference (a run at `split` and one at half of it), in work units; times
/// seconds_per_unit() it is a first estimate in seconds on this kind of machine.
double estimated_group_cost(const SceneInfo& info, const std::vector<Combination>& group, int repeats);
double estimated_reference_cost(const SceneInfo& info, Split split, int threads);
double seconds_per_unit();

}  // namespace pbd::cli
