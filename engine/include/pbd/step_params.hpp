#pragma once
/// \file step_params.hpp
/// What World::step() does: time step, sub-steps, sweeps, forces, the solver; and what it reports afterwards.
#include "pbd/solver.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <vector>

namespace pbd {

/// Chebyshev semi-iterative acceleration of a sub-step's sweeps (Wang 2015; Fratarcangeli et al. 2016): after
/// sweep k + 1 has turned q_k into q̂, the positions become q_{k+1} = ω_{k+1}·(q̂ − q_{k−1}) + q_{k−1} (and every XPBD
/// λ likewise, so that λ keeps matching the positions), with ω = 2 / (2 − ρ²) at the first accelerated sweep and
/// ω ← 4 / (4 − ρ²·ω) after it. For the Jacobi, serial-colored, colored and block solvers, not the serial reference.
template <class Real> struct Chebyshev {
  bool enabled = false;  ///< accelerate the sweeps
  Real rho = 0;          ///< spectral radius of one sweep, in [0, 1); 0: the next sub-step sweeps plain and measures
                         ///< it (the rate its position changes shrink at), and later sub-steps use that measure (the
                         ///< world keeps it, StepStats::chebyshev_rho reports it; set_params with other Chebyshev
                         ///< settings forgets it)
  int delay = 4;         ///< plain sweeps before the first accelerated one, ≥ 1
  Real max_rho = Real(0.999);  ///< cap on an estimated ρ, in (0, 1)
  /// The guard: a sweep whose position change exceeds `diverge` times the smallest one of the sub-step so far ends
  /// the acceleration for the rest of the sub-step (plain sweeps from there on; counted in StepStats), > 1.
  Real diverge = Real(2);
  friend bool operator==(const Chebyshev&, const Chebyshev&) = default;  ///< same settings
};

/// Hierarchical position based dynamics (Müller 2008) over the stretch constraints' particle graph: coarser levels
/// of particles, one-sided distance constraints between them, and a coarse-to-fine pass at every sub-step before the
/// sweeps (engine/src/solve/hierarchy.hpp). Off by default; any solver.
struct Hierarchy {
  bool enabled = false;  ///< run the coarse-to-fine pass
  int levels = 4;        ///< coarse levels above the stretch constraints, in [1, 16] (fewer where a level stops shrinking)
  int parents = 2;       ///< k: every particle left out of a coarser level has >= k neighbours in it, in [1, 8]
  int sweeps = 1;        ///< sweeps of each coarse level's constraints per pass, in [1, 64]
  /// Strain a coarse constraint leaves to the sweeps, in [0, 0.1]: it pulls only a pair stretched more than
  /// (1 + slack) × its path's rest length. At 0 the pass corrects the sweeps' own small residual every sub-step,
  /// which a resting cloth at many sub-steps turns into motion that crumples it (solve/hierarchy.hpp).
  double slack = 1e-3;
  /// Also coarsen stretch constraints of compliant sets (XPBD α > 0; a coarse constraint gets its path's summed α).
  /// Off by default: a position-only coarse pass moves XPBD's fixed point (the sweeps start from λ = 0 at positions
  /// the pass moved), so a compliant body settles shorter than α·T (solve/hierarchy.hpp).
  bool compliant = false;
  friend bool operator==(const Hierarchy&, const Hierarchy&) = default;  ///< same settings
};

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
  Chebyshev<Real> chebyshev;                 ///< acceleration of the sweeps (off by default)
  Hierarchy hierarchy;                       ///< coarse-to-fine pass before the sweeps (off by default)
};

/// What the last step() did and how long each phase took (wall-clock seconds, summed over sub-steps).
struct StepStats {
  double seconds = 0.0;             ///< the whole step
  double seconds_integrate = 0.0;   ///< forces, damping, prediction and velocity update
  double seconds_collisions = 0.0;  ///< generating collision constraints and particle contacts (the broad phase)
  double seconds_coloring = 0.0;    ///< coloring persistent constraints (only when they changed)
  double seconds_solve = 0.0;       ///< the sweeps
  double seconds_hierarchy = 0.0;   ///< of seconds_solve: the hierarchy's coarse-to-fine passes
  double seconds_waiting = 0.0;     ///< of seconds_solve: the time the sweeps' threads waited for one another at
                                    ///< barriers, averaged over the threads (0 on one thread); the scaling loss
  int solve_threads = 0;            ///< most threads that ran one sub-step's sweeps together (1: one thread)
  int substeps = 0;                 ///< sub-steps taken
  int sweeps = 0;                   ///< sweeps taken (substeps × iterations)
  Index colors = 0;                 ///< groups of the persistent constraints (0 for the serial solver): colors, or
                                    ///< for the block solver every type's blocks and boundary colors
  int chebyshev_fallbacks = 0;      ///< sub-steps whose Chebyshev acceleration the guard stopped (diverging)
  double chebyshev_rho = 0.0;       ///< ρ of the acceleration after the step (given or estimated; 0: none yet)
  std::size_t collisions = 0;       ///< collision constraints and particle contacts of the last sub-step
  std::vector<NamedViolation> violation;  ///< per type, at the end of the step (only with measure_violation on)
};

}  // namespace pbd
