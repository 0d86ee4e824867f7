#pragma once
// `pbd study`: its options as given on the command line, and the plan they resolve to (lists parsed, checked,
// --quick and --scaling defaults applied, the shard chosen).
#include "pbd/solver.hpp"

#include <string>
#include <vector>

namespace pbd::cli {

/// The options exactly as the command line gave them (lists still comma-separated text; "" = the default).
struct StudyOptions {
  std::vector<std::string> scenes;  ///< --scene (repeatable or comma-separated); empty: the default list
  std::string solvers;              ///< --solvers
  std::string threads;              ///< --threads
  std::string budgets;              ///< --budgets: sweeps per step (substeps × iterations)
  std::string split;                ///< --split SxI of --scaling
  int steps = 0;                    ///< --steps; 0: each scene's own
  std::string precision = "float";  ///< --precision
  int repeats = 0;                  ///< --repeats (timed runs after the warm-up); 0: default
  std::string reference;            ///< --reference SxI: the reference's first budget, substeps × iterations
  std::string reference_solver;     ///< --reference-solver
  int reference_max = 0;            ///< --reference-max: the most sweeps per step the reference may be raised to
  double reference_seconds = 0.0;   ///< --reference-seconds: the longest a scene's reference may take
  std::string variants;             ///< --variants
  double target = 1.0;              ///< --target: the error the headline asks for, in % (run-averaged)
  std::string json;                 ///< --json FILE
  std::string plots;                ///< --plots DIR
  std::string format = "table";     ///< --format table|csv|json (stdout)
  std::string shard;                ///< --shard I/N, or "auto": from a Slurm job array (make_plan reads it)
  std::string commit;               ///< --commit / $PBD_COMMIT: the commit the program was built from ("" = unknown)
  bool quick = false;               ///< --quick
  bool scaling = false;             ///< --scaling
  bool estimate = false;            ///< --estimate
};

/// One solver of the study: its command-line name and the engine's enum.
struct StudySolver {
  std::string name;        ///< serial, serial-colored, colored, jacobi or block; "+chebyshev" for the accelerated
  Solver solver;           ///< the engine's solver
  bool threaded;           ///< false for the one-thread solvers (serial, serial-colored): run once, on 1 thread
  bool chebyshev = false;  ///< Chebyshev acceleration on (ρ estimated by the engine, which needs 4 iterations or more:
                           ///< splits with fewer are left out for it)
};

/// One split of a sweep budget: substeps × iterations.
struct Split {
  int substeps = 1;    ///< substeps per step
  int iterations = 1;  ///< iterations per substep
  friend bool operator==(const Split&, const Split&) = default;
};

/// What a study runs. Main mode: every scene × budget × split of it × solver × threads (one-thread solvers once).
/// Scaling mode: every scene × parallel solver × thread count at one split, with the shared-nothing reference.
struct StudyPlan {
  std::vector<std::string> scenes;       ///< scene names or files, in the order given
  std::vector<StudySolver> solvers;      ///< solvers, in the order given
  std::vector<int> threads;              ///< thread counts, ascending
  std::vector<int> budgets;              ///< sweeps per step, ascending (main mode)
  Split split{1, 10};                    ///< the split of scaling mode
  int steps = 0;                         ///< steps per run; 0: each scene's own
  int max_steps = 0;                     ///< cap on each scene's own steps (0: none; --quick: 20)
  bool double_precision = false;         ///< World<double> instead of World<float>
  int repeats = 3;                       ///< timed runs per combination after one warm-up run
  bool default_budgets = true;           ///< --budgets not given: scenes other than the generated ones and those
                                         ///< whose fibers have a curve (their error needs ~100 sweeps a step) stop
                                         ///< at kOtherSceneBudget sweeps (their steps with contacts cost the most)
  bool default_solvers = true;           ///< --solvers not given: one-thread solvers only where affordable, the
                                         ///< large cloths with the colored solver alone, variants without serial
  std::vector<std::string> variants;     ///< --variants (empty: every one that applies to each scene)
  Split reference{512, 1};               ///< the reference's first budget (default: twice the largest, as substeps)
  StudySolver reference_solver;          ///< its solver (double precision; default colored, bitwise identical on
                                         ///< any thread count, run on the most threads)
  int reference_max = 4096;              ///< the most sweeps per step it is raised to when not converged
  double reference_seconds = 120.0;      ///< the longest one scene's reference may take (the next doubling is
                                         ///< estimated from the last)
  double target = 1.0;                   ///< the headline's error, in % of the primary measure (run-averaged)
  std::string json;                      ///< JSON report file ("" = none)
  std::string plots;                     ///< plot directory ("" = none)
  std::string format = "table";          ///< what stdout gets: table, csv or json
  std::string commit;                    ///< the commit the report names ("" = "unknown")
  int shard = 1, shards = 1;             ///< this run is part `shard` (1-based) of `shards`
  bool quick = false;                    ///< the smoke-test study
  bool scaling = false;                  ///< the scaling study
  bool estimate = false;                 ///< print the plan and its estimated cost per scene, run nothing
};

/// The most threads this process runs at once: oneTBB's max_allowed_parallelism (the CPUs it may use), which a task
/// arena of more threads does not exceed (`pbd run --threads` runs on as many). `pbd study --threads` is refused
/// above it, but with --estimate.
int machine_threads();

/// Checks the options and resolves them into a plan; throws pbd::Error naming the bad value and listing the valid
/// ones (unknown solver, scene or format, empty list, value out of range, more threads than machine_threads(), a
/// shard outside 1..N, --shard auto outside a contiguous Slurm job array).
StudyPlan make_plan(const StudyOptions& options);

/// Every split of `budget` sweeps: s × (budget / s) for each divisor s, from 1 × budget to budget × 1.
std::vector<Split> splits_of(int budget);

/// The splits the study runs of `budget`: every one up to kAllSplitsBudget sweeps; above it substeps alone
/// (budget × 1): substeps win at high budgets (README), and the other splits would cost as much again each.
constexpr int kAllSplitsBudget = 8;
/// The largest default budget of a scene that is not generated (the headline's budgets are for the cloths and the
/// chain).
constexpr int kOtherSceneBudget = 8;
std::vector<Split> study_splits(int budget);

/// Parses "SxI" (e.g. "2x5"); throws pbd::Error naming `flag`.
Split parse_split(const std::string& flag, const std::string& text);

/// Default scenes of the main study: the built-in scenes, then the cloths of 30², 100² and 300² particles.
std::vector<std::string> default_study_scenes();
/// Default scenes of the scaling study: the cloths of 30² to 1000² particles.
std::vector<std::string> default_scaling_scenes();

}  // namespace pbd::cli
