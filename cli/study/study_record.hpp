#pragma once
// What `pbd study` measures: the scenes it ran, the converged reference of each, one record per measured
// combination (one row of the table, one record of the JSON report), and the error measures in physical units.
#include "pbd/metrics.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pbd::cli {

/// The ranges of `pbd study`'s options (study_options.cpp), which a report read back keeps to as well.
inline constexpr int kMaxStudyThreads = 1024;         ///< --threads (and no more than the machine runs)
inline constexpr int kMaxStudyBudget = 4096;          ///< --budgets: sweeps per step
inline constexpr int kMaxSubsteps = 10000;            ///< substeps of a split (--reference, --split)
inline constexpr int kMaxIterations = 100000;         ///< iterations of a split
inline constexpr int kMaxRepeats = 1000;              ///< --repeats: timed runs
inline constexpr int kMaxSteps = 100000000;           ///< --steps: steps per run
inline constexpr int kMaxReferenceBudget = 1000000;   ///< --reference-max: sweeps per step of the reference
inline constexpr double kMaxReferenceSeconds = 1e7;   ///< --reference-seconds

/// RMS and maximum of one error measure over its items, in the measure's unit.
struct ErrorValue {
  double rms = 0.0;  ///< RMS over the items
  double max = 0.0;  ///< maximum over the items
};

/// Error measures by name, in physical units: each type's Measure as its header declares it (stretch_pct, relative
/// stretch in %; bending_rad; area_pct; anchor_mm; volume_pct; penetration_mm; overlap_pct, % of the radii sum; the
/// whole list: pbd::violation_measures()); a type without one keeps its own name and unit.
using Errors = std::map<std::string, ErrorValue>;

/// The measure of a scene whose primary_error is "reference": Record::ref_error_mm, one step's distance from the
/// converged reference's step (run-averaged; Record::trajectory_error_mm is its "final"). An elastic body's strain is
/// its physics, not the solver's error, and ranks nothing; how far the solver lands from converged does.
inline constexpr const char* kReferenceMeasure = "ref_error_mm";

/// The label and unit of the measures known_answer_errors (study_scenes.hpp) adds, for the report's "measures".
struct ExtraMeasure {
  std::string key, label, unit;
};
inline std::vector<ExtraMeasure> known_answer_measures() {
  return {{"extension_pct", "link extension error", "% of alpha*T"},
          {"curve_pct", "fiber force off its curve", "% of the yield force"}};
}

/// The measure name and unit scale of an engine violation type ("stretch" → {"stretch_pct", 100}), from its Measure.
std::pair<std::string, double> measure_of(const std::string& violation_type);

/// The violations of a state as Errors (measure_of applied to each type).
Errors errors_of(const std::vector<NamedViolation>& violations);

/// One scene as the study ran it.
struct SceneInfo {
  std::string name;            ///< scene name
  std::size_t particles = 0;   ///< particles
  std::size_t constraints = 0; ///< persistent constraints (a volume constraint counts once)
  int steps = 0;               ///< steps per run
  double size_m = 1.0;         ///< bounding-box diagonal of the initial positions, m
  std::string primary_error;   ///< the measure its results are judged by (a key of Errors)
  std::string family;          ///< "cloth" for the generated cloth<N>, else ""
  std::vector<std::string> measures;  ///< the error measures it has
  std::string base;            ///< the scene as named (name is base+variant for a variant other than plain)
  std::string variant = "plain";  ///< the variant run (scene_variants.hpp)
  std::string known_answer;    ///< "rest" or "chain" for a quasi-static scene with a closed form (study_scenes.hpp)
  int average_from = 1;        ///< errors are averaged over steps average_from .. steps (1-based): the whole run,
                               ///< or for a quasi-static scene its last quarter (once it has settled)
};

/// One sampled step of the reference: the state before it and the positions after it.
struct ReferenceSample {
  int step = 0;                 ///< 0-based step index
  double time = 0.0;            ///< simulated time before the step, s
  Matrix3X<double> x, v;        ///< positions (m) and velocities (m/s) before the step
  Matrix3X<double> x_after;     ///< positions after the step, m
  Matrix3X<double> x_half;      ///< positions after the same step at half the reference's budget, m
};

/// The reference of one scene (its plain variant): a deterministic solver in double at a large budget, verified to
/// be converged against the records it is compared with (study_reference.hpp).
struct Reference {
  std::string scene;              ///< scene name (the plain variant's; every variant of it is compared with it)
  std::string solver;             ///< its solver
  int threads = 1;                ///< threads it ran on (its solver is bitwise identical on any count)
  int substeps = 0;               ///< substeps per step
  int iterations = 0;             ///< iterations per substep
  int steps = 0;                  ///< steps run
  Matrix3X<double> positions;     ///< final positions (kept in memory only)
  std::vector<ReferenceSample> samples;  ///< the sampled steps (kept in memory only)
  Errors errors;                  ///< its errors averaged over the run
  Errors errors_final;            ///< its final state's errors
  // Its own change at half its budget (substeps halved, or iterations when it has one substep):
  double step_change_mm = 0.0;        ///< RMS over samples of one step at half the budget against the reference step
  double trajectory_change_mm = 0.0;  ///< final positions of a whole run at half the budget against its own
  Errors error_change;                ///< |averaged error at half the budget − its own|, per measure (rms and max)
  // The check (finish() redoes it over every record, e.g. after a merge):
  bool converged = false;         ///< every change at most a tenth of the smallest error it is compared with
  bool step_converged = false;    ///< the one-step change is: ref_error_mm is measured against a converged step
  std::vector<std::string> failures;  ///< the changes that are not, as text
  bool capped = false;            ///< the study could not raise its budget further (cap or time limit)
  std::vector<std::string> tried; ///< the budgets tried before it, "SxI"
  double seconds = 0.0;           ///< wall time spent computing it (every budget tried)
};

/// What one combination measured.
struct Record {
  std::string scene;            ///< scene name
  std::string solver;           ///< solver name
  int threads = 1;              ///< threads of the task arena
  int substeps = 1;             ///< substeps per step
  int iterations = 1;           ///< iterations per substep
  int steps = 0;                ///< steps per run
  std::string precision;        ///< float or double
  int repeats = 0;              ///< timed runs (after one warm-up run)
  std::vector<double> ms;       ///< each timed run, ms per step, in run order (not in the report)
  double ms_per_step = 0.0;     ///< median of the timed runs, ms per step
  double ms_per_step_min = 0.0; ///< fastest timed run, ms per step
  double ms_per_step_max = 0.0; ///< slowest timed run, ms per step
  double ms_per_step_cv = 0.0;  ///< coefficient of variation of the timed runs (standard deviation / mean)
  std::size_t particles = 0;    ///< particles
  std::size_t constraints = 0;  ///< persistent constraints
  std::size_t colors = 0;       ///< colors of the persistent constraints (0 for solvers that do not color)
  std::string variant = "plain"; ///< the variant (scene_variants.hpp); `scene` names base+variant
  int timing_steps = 0;         ///< steps of each timed run (all of them, or the first few of a long run)
  Errors errors;                ///< errors averaged over the run's steps (SceneInfo::average_from on), physical units
  Errors errors_final;          ///< the final state's errors
  double primary_error = 0.0;   ///< errors[scene's primary measure].rms: averaged over the run
  double primary_error_final = 0.0;  ///< errors_final[scene's primary measure].rms
  std::optional<double> settle_motion_mm;  ///< quasi-static scenes: RMS displacement over the averaged steps, mm
  std::optional<bool> settled;  ///< quasi-static scenes: that displacement below 1 mm
  std::optional<double> ref_error_mm;        ///< RMS over sampled steps of one step's RMS distance from the reference
                                             ///< step taken from the same reference state, mm (none in scaling mode)
  std::optional<double> ref_error_max_mm;    ///< maximum over sampled steps and particles of that distance, mm
  std::optional<double> trajectory_error_mm; ///< RMS distance of the final positions from the reference run's, mm
  std::optional<double> energy_drift;  ///< (E_end − E_0) / (M |g| size), scenes without colliders only
  std::uint64_t state_hash = 0; ///< FNV-1a of the final positions' bytes
  bool repeatable = true;       ///< every run (warm-up included) ended with the same hash
  double load = 0.0;            ///< mean number of other runnable processes sampled around its timed runs
  bool busy = false;            ///< its timing is suspect: CV above 10% or the machine was loaded
  bool pareto = false;          ///< on its scene's front of ms_per_step against primary_error
  Matrix3X<double> final_positions;  ///< the error run's final positions (kept in memory only)
  int budget() const { return substeps * iterations; }  ///< sweeps per step
  /// The scene as named, without its variant.
  std::string base() const {
    return variant == "plain" || scene.size() <= variant.size() ? scene : scene.substr(0, scene.size() - variant.size() - 1);
  }
  /// Nanoseconds per constraint projection: ms_per_step / (constraints × substeps × iterations).
  double ns_per_projection() const;
  /// "SxI": substeps × iterations.
  std::string split() const { return std::to_string(substeps) + "x" + std::to_string(iterations); }
};

}  // namespace pbd::cli
