#pragma once
/// \file step_limits.hpp
/// The most work one World::step() may be asked for. check_params (World::set_params) and the scene parser refuse
/// StepParams beyond these, so that a typo (100000 for 100) is an error at once, not a step that runs for days with
/// no sign of progress. The bounds leave wide headroom over real use: the built-in scenes take at most 16 sub-steps
/// of 10 sweeps, and `pbd study`'s converged references a few thousand sweeps a step.
namespace pbd {

inline constexpr int kMaxSubsteps = 100'000;            ///< StepParams::substeps, at most
inline constexpr int kMaxIterations = 100'000;          ///< StepParams::iterations, at most
inline constexpr long kMaxSweepsPerStep = 1'000'000;    ///< substeps × max(1, iterations), at most

/// The sweeps a step takes as the limit counts them: a sub-step of 0 iterations still costs about one.
inline long sweeps_per_step(int substeps, int iterations) { return long(substeps) * long(iterations > 1 ? iterations : 1); }

}  // namespace pbd
