#pragma once
// The results of `pbd study`: what is derived from the records (Pareto front, best split per budget, dominance,
// strong scaling), the table, CSV and JSON forms of the report, and the merge of shards' reports.
#include "study_record.hpp"

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <vector>

namespace pbd::cli {

/// The same-run shared-nothing reference of one scene at one thread count (study_runner.hpp).
struct SharedNothing {
  std::string scene;             ///< scene
  int threads = 2;               ///< copies stepping at once
  std::vector<double> speedups;  ///< threads × t(alone) / t(together), one per round
};

/// Per (scene, solver, threads, budget): the split with the lowest primary error (the faster one on a tie).
struct BestSplit {
  std::string scene, solver;     ///< scene and solver
  int threads = 1, budget = 1;   ///< threads and sweeps per step
  int substeps = 1, iterations = 1;  ///< the best split
  double ms_per_step = 0.0;      ///< its median time per step, ms
  double primary_error = 0.0;    ///< its primary error
};

/// Does a parallel solver at its most threads dominate the serial solver on one scene? For every serial point it
/// looks for a point of the solver that is faster (median ms per step) with no higher primary error.
struct Dominance {
  std::string scene, solver, measure;  ///< scene, parallel solver, the primary measure compared
  int threads = 0;                     ///< threads of its points
  int serial_points = 0;               ///< serial points on this scene
  std::vector<std::string> undominated;  ///< splits "SxI" of the serial points none of its points dominates
};

/// The headline: per (scene and variant, solver, threads), the fastest point whose run-averaged primary error is
/// at or below the target (in % measures only), or the lowest error it reached.
struct TimeToTarget {
  std::string scene, base, variant, solver;  ///< scene (base+variant), the scene as named, variant, solver
  int threads = 1;                ///< threads
  std::string measure;            ///< the primary measure
  double target = 1.0;            ///< the target, in the measure's unit (%)
  bool reached = false;           ///< some point is at or below it
  int substeps = 0, iterations = 0;  ///< the fastest such point, or the lowest-error point when not reached
  double ms_per_step = 0.0;       ///< its time per step, ms
  double primary_error = 0.0;     ///< its run-averaged primary error
};

/// The reference check: the reference's own change at half its budget must be at most a tenth of the smallest
/// error it is compared with, over every record of its scene (all variants): the one-step change against the
/// smallest ref_error_mm, the change of the run's end against the smallest trajectory_error_mm, and the change of
/// each averaged error measure (RMS) against that measure's smallest averaged RMS, except for a scene judged by its
/// distance from the reference (`by_reference`: its measures are physics, such as an elastic body's strain, not
/// errors to be at most a tenth of). Sets ref.converged, ref.step_converged and ref.failures (one text per failed
/// comparison).
constexpr double kReferenceMargin = 0.1;
void check_reference(Reference& ref, const std::vector<Record>& records, bool by_reference);

/// Strong scaling of one solver on one scene (scaling mode): speed-up over the same solver on 1 thread, per round.
struct StrongScaling {
  std::string scene, solver;     ///< scene and solver
  std::size_t particles = 0;     ///< particles
  int threads = 1;               ///< threads
  double ms_per_step = 0.0, ms_per_step_min = 0.0, ms_per_step_max = 0.0;  ///< its time, ms
  double speedup = 0.0, speedup_min = 0.0, speedup_max = 0.0;  ///< median, min, max over rounds of t(1) / t(T)
};

/// Everything one report holds.
struct Report {
  nlohmann::json study;                   ///< command, date, git_commit, seconds, mode, context, options, warnings
  std::vector<SceneInfo> scenes;          ///< scenes run
  std::vector<Reference> references;      ///< their references (main mode)
  std::vector<Record> records;            ///< every measured combination
  std::vector<SharedNothing> shared_nothing;  ///< shared-nothing references
  // Derived by finish():
  std::vector<BestSplit> best_splits;     ///< best split per budget
  std::vector<Dominance> dominance;       ///< dominance of serial by each parallel solver
  std::vector<StrongScaling> strong;      ///< strong scaling (scaling mode)
  std::vector<TimeToTarget> time_to_target;  ///< the headline (main mode)
};

/// Derives the Pareto flags, best splits, dominance, strong scaling and the time to the target from the records,
/// re-checks each reference against them, and the warnings (busy points, a busy machine, a reference that is not
/// converged, a quasi-static run that did not settle) into study["warnings"] and study["busy"].
void finish(Report& report);

/// The report as JSON (schema 3; docs/results.md describes every field).
nlohmann::json report_json(const Report& report);
/// (The report read back from a file: report_reader.hpp.)

/// What `pbd study merge` lets through.
struct MergeRules {
  bool allow_mixed_machines = false;  ///< shards of other CPUs or core counts (--allow-mixed-machines)
};

/// Joins shards' reports: their records, scenes, references and shared-nothing references. The parts must be the
/// whole set of one study: shards 1..N of one N, each once (or one whole run); the same options apart from the
/// shard, mode, pbd version, commit and build (compiler, flags, build type); and the same machine (CPU and cores)
/// unless `rules` allow mixed machines. The context is the first part's with the highest load any part saw; each
/// part's own is kept under study["parts"], each machine (CPU, cores, hosts, files) under study["machines"], and with
/// mixed machines the context's cpu names them all, its cores is null and context["mixed_machines"] is true.
/// Throws pbd::Error naming the file and the field that do not fit.
Report merge_reports(const std::vector<Report>& parts, const std::vector<std::string>& sources,
                     const MergeRules& rules = {});

/// The table on stdout: context, one section per scene, the best splits, the dominance check, the warnings.
void print_table(std::ostream& out, const Report& report);
/// CSV on stdout: a header and one line per record.
void print_csv(std::ostream& out, const Report& report);

}  // namespace pbd::cli
