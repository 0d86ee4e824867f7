#pragma once
// One measured combination of `pbd study` (one row of the table, one record of the JSON report), and the converged
// reference its error is measured against.
#include "pbd/metrics.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pbd::cli {

/// The converged reference of one (scene, substeps): serial solver, double precision, many iterations.
struct Reference {
  std::string scene;              ///< scene name
  int substeps = 1;               ///< substeps per step
  int steps = 0;                  ///< steps run
  int iterations = 0;             ///< iterations per substep (N)
  Matrix3X<double> positions;     ///< final positions
  double size = 0.0;              ///< scene size: bounding-box diagonal of the initial positions, m
  double step_convergence = 0.0;      ///< per step: RMS distance of N/2- from N-iteration steps, / size (RMS over samples)
  double step_convergence_max = 0.0;  ///< per step: maximum distance between them, / size
  double trajectory_convergence = 0.0;  ///< whole run: RMS distance of the final N/2- from the N-iteration positions, / size
  double rms_violation = 0.0;     ///< pooled RMS violation of the reference's final state
  double max_violation = 0.0;     ///< pooled maximum violation of the reference's final state
  std::optional<double> energy_drift;  ///< the reference's own energy drift (scenes without colliders)
  double seconds = 0.0;           ///< wall time spent computing it (both runs)
};

/// What one combination measured.
struct Record {
  std::string scene;            ///< scene name
  std::string solver;           ///< solver name
  int threads = 1;              ///< threads of the task arena
  int iterations = 0;           ///< iterations per substep
  int substeps = 1;             ///< substeps per step
  int steps = 0;                ///< steps per run
  std::string precision;        ///< float or double
  int repeats = 0;              ///< timed runs (after one warm-up run)
  double ms_per_step = 0.0;     ///< median over the timed runs of (run time / steps), ms
  double ms_per_step_min = 0.0; ///< fastest timed run, ms per step
  std::size_t particles = 0;    ///< particles
  std::size_t constraints = 0;  ///< persistent constraints (a volume constraint counts once)
  std::size_t colors = 0;       ///< colors of the persistent constraints (0 for solvers that do not color)
  double rms_violation = 0.0;   ///< RMS of the normalized violation over all constraints of all types (metrics.hpp)
  double max_violation = 0.0;   ///< maximum of it
  std::vector<NamedViolation> violations;  ///< the same per constraint type
  double ref_error = 0.0;       ///< per-step error: RMS over sampled steps of the RMS distance from the reference
                                ///< step taken from the same state, / scene size
  double ref_error_max = 0.0;   ///< maximum over sampled steps and particles of that distance, / scene size
  double trajectory_error = 0.0;  ///< RMS distance of the final positions from the reference run's, / scene size
  std::optional<double> energy_drift;  ///< (E_end − E_0) / (M |g| size), scenes without colliders only
  std::uint64_t state_hash = 0; ///< FNV-1a of the final positions' bytes
  bool repeatable = true;       ///< every run (warm-up included) ended with the same hash
  /// Nanoseconds per constraint projection: ms_per_step / (constraints × substeps × iterations).
  double ns_per_projection() const;
};

}  // namespace pbd::cli
