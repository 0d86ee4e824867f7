#pragma once
// `pbd study`: its options as given on the command line, and the plan they resolve to (lists parsed, checked,
// --quick defaults applied).
#include "pbd/solver.hpp"

#include <string>
#include <vector>

namespace pbd::cli {

/// The options exactly as the command line gave them (lists still comma-separated text).
struct StudyOptions {
  std::vector<std::string> scenes;                  ///< --scene (repeatable or comma-separated); empty: default
  std::string solvers = "serial,colored,jacobi,block";    ///< --solvers
  std::string threads = "1,2";                      ///< --threads
  std::string iterations = "1,2,4,8,16,32";         ///< --iterations
  std::string substeps = "1";                       ///< --substeps
  int steps = 0;                                    ///< --steps; 0: each scene's own
  std::string precision = "float";                  ///< --precision
  int repeats = 0;                                  ///< --repeats (timed runs after the warm-up); 0: default
  int reference_iterations = 0;                     ///< --reference-iterations; 0: default
  std::string json;                                 ///< --json FILE
  std::string plots;                                ///< --plots DIR
  bool quick = false;                               ///< --quick
  bool given_iterations = false;                    ///< --iterations was given (so --quick keeps it)
};

/// One solver of the study: its command-line name and the engine's enum.
struct StudySolver {
  std::string name;  ///< serial, serial-colored, colored or jacobi
  Solver solver;     ///< the engine's solver
  bool threaded;     ///< false for the one-thread solvers (serial, serial-colored): run once, at the fewest threads
};

/// What a study runs: every scene × substeps × iterations × solver × threads (one-thread solvers once).
struct StudyPlan {
  std::vector<std::string> scenes;       ///< scene names or files, in the order given
  std::vector<StudySolver> solvers;      ///< solvers, in the order given
  std::vector<int> threads;              ///< thread counts, ascending
  std::vector<int> iterations;           ///< iterations per substep, ascending
  std::vector<int> substeps;             ///< substeps per step, ascending
  int steps = 0;                         ///< steps per run; 0: each scene's own
  bool double_precision = false;         ///< World<double> instead of World<float>
  int repeats = 5;                       ///< timed runs per combination after one warm-up run
  int reference_iterations = 200;        ///< iterations of the converged reference (serial, double)
  std::string json;                      ///< JSON report file ("" = none)
  std::string plots;                     ///< plot directory ("" = none)
  bool quick = false;                    ///< the smoke-test study
};

/// Checks the options and resolves them into a plan; throws pbd::Error naming the bad value and listing the valid
/// ones (unknown solver or scene, empty list, value out of range).
StudyPlan make_plan(const StudyOptions& options);

/// Default scenes of the study: the built-in scenes.
std::vector<std::string> default_study_scenes();

}  // namespace pbd::cli
