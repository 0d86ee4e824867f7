#include "study_runner.hpp"

#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>

namespace pbd::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// E_end − E_0 in units of M |g| size (the potential energy of lifting the movable mass by the scene's size); only
// for scenes without colliders (contacts remove energy on purpose).
template <class Real>
std::optional<double> energy_drift(const World<Real>& world, const Energy& initial, double size) {
  if (!world.colliders().empty()) return std::nullopt;
  const double scale = movable_mass(world) * double(world.params().gravity.norm()) * size;
  if (!(scale > 0.0)) return std::nullopt;
  return (energy(world).total() - initial.total()) / scale;
}

template <class Real> World<Real> prepared_world(const Scene& scene, Solver solver, int iterations, int substeps) {
  World<Real> world = build_world<Real>(scene.world);
  StepParams<Real> params = world.params();
  params.solver = solver;
  params.iterations = iterations;
  params.substeps = substeps;
  world.set_params(params);
  if (solver != Solver::serial) world.num_colors();  // color now: not part of any timed step
  return world;
}

template <class Real> void advance(World<Real>& world, int steps) {
  for (int s = 0; s < steps; ++s) world.step();
}

// RMS and maximum, over the sampled steps, of one step's distance from the reference step taken from the same state.
struct StepErrors {
  double sum2 = 0.0, max = 0.0;
  int count = 0;
  void add(const Violation& d, double size) {
    sum2 += (d.rms / size) * (d.rms / size);
    max = std::max(max, d.max / size);
    ++count;
  }
  double rms() const { return count ? std::sqrt(sum2 / count) : 0.0; }
};

// The steps (0-based) whose error is measured: kStepSamples of them, evenly spread, the last step included.
constexpr int kStepSamples = 10;
bool is_sample(int step, int steps) {
  const int n = std::min(kStepSamples, steps);
  for (int k = 0; k < n; ++k)
    if (int((long(k) + 1) * steps / n) - 1 == step) return true;
  return false;
}

// `world` in double: a copy, or for float the same model (its values in double) in the same state at the same time.
template <class Real> World<double> in_double(const World<Real>& world) {
  if constexpr (std::is_same_v<Real, double>) {
    return world;
  } else {
    World<double> copy = build_world<double>(describe_world(world));
    copy.set_time(world.time());
    return copy;
  }
}

// Steps `world` once and returns the distance of the result from the reference step: the same state stepped by the
// serial solver in double with `iterations`.
template <class Real> Violation step_against_reference(World<Real>& world, int iterations) {
  World<double> ref = in_double(world);
  StepParams<double> params = ref.params();
  params.solver = Solver::serial;
  params.iterations = iterations;
  ref.set_params(params);
  ref.step();
  world.step();
  return position_distance(world, Matrix3X<double>(ref.positions()));
}

template <class Real> Record run_typed(const Scene& scene, const Combination& c, const Reference& ref, int repeats) {
  Record r;
  r.scene = scene.name;
  r.solver = c.solver.name;
  r.threads = c.threads;
  r.iterations = c.iterations;
  r.substeps = c.substeps;
  r.steps = c.steps;
  r.precision = sizeof(Real) == sizeof(float) ? "float" : "double";
  r.repeats = repeats;
  tbb::task_arena arena(c.threads);
  arena.execute([&] {
    World<Real> initial = prepared_world<Real>(scene, c.solver.solver, c.iterations, c.substeps);
    r.particles = initial.num_particles();
    r.constraints = initial.num_constraints();
    r.colors = c.solver.solver == Solver::serial ? 0 : std::size_t(initial.num_colors());
    const Energy e0 = energy(initial);
    std::vector<double> ms;
    // Warm-up run (caches, page faults, thread start-up), which also measures the per-step error.
    World<Real> world = initial;
    StepErrors step_errors;
    for (int s = 0; s < c.steps; ++s) {
      if (is_sample(s, c.steps)) step_errors.add(step_against_reference(world, ref.iterations), ref.size);
      else world.step();
    }
    r.ref_error = step_errors.rms();
    r.ref_error_max = step_errors.max;
    r.trajectory_error = position_distance(world, ref.positions).rms / ref.size;
    r.state_hash = position_hash(world);
    for (int k = 0; k < repeats; ++k) {
      world = initial;  // copied outside the timed region
      const auto t0 = Clock::now();
      advance(world, c.steps);
      ms.push_back(1e3 * seconds_since(t0) / double(c.steps));
      r.repeatable = r.repeatable && position_hash(world) == r.state_hash;
    }
    std::sort(ms.begin(), ms.end());
    const std::size_t n = ms.size();
    r.ms_per_step = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    r.ms_per_step_min = ms.front();
    r.violations = constraint_violations(world);
    const Violation all = pooled(r.violations);
    r.rms_violation = all.rms;
    r.max_violation = all.max;
    r.energy_drift = energy_drift(world, e0, ref.size);
  });
  return r;
}

double scene_work(const Scene& scene) {
  return double(scene.world.num_constraints() + scene.world.num_particles());
}

}  // namespace

Reference compute_reference(const Scene& scene, int substeps, int steps, int iterations) {
  const auto t0 = Clock::now();
  Reference ref;
  ref.scene = scene.name;
  ref.substeps = substeps;
  ref.steps = steps;
  ref.iterations = iterations;
  World<double> half = prepared_world<double>(scene, Solver::serial, iterations / 2, substeps);
  World<double> full = prepared_world<double>(scene, Solver::serial, iterations, substeps);
  ref.size = bounding_diagonal(full);
  if (!(ref.size > 0.0)) ref.size = 1.0;
  const Energy e0 = energy(full);
  advance(half, steps);
  StepErrors step_errors;  // the N/2-iteration step against the N-iteration step, from the reference's states
  for (int s = 0; s < steps; ++s) {
    if (is_sample(s, steps)) {
      World<double> coarse = full;
      StepParams<double> params = coarse.params();
      params.iterations = iterations / 2;
      coarse.set_params(params);
      coarse.step();
      full.step();
      step_errors.add(position_distance(coarse, Matrix3X<double>(full.positions())), ref.size);
    } else {
      full.step();
    }
  }
  ref.positions = full.positions();
  ref.step_convergence = step_errors.rms();
  ref.step_convergence_max = step_errors.max;
  ref.trajectory_convergence = position_distance(half, ref.positions).rms / ref.size;
  const Violation v = pooled(constraint_violations(full));
  ref.rms_violation = v.rms;
  ref.max_violation = v.max;
  ref.energy_drift = energy_drift(full, e0, ref.size);
  ref.seconds = seconds_since(t0);
  return ref;
}

Record run_combination(const Scene& scene, const Combination& c, const Reference& ref, int repeats) {
  Record r = c.double_precision ? run_typed<double>(scene, c, ref, repeats) : run_typed<float>(scene, c, ref, repeats);
  if (!std::isfinite(r.ref_error)) r.ref_error = r.ref_error_max = std::numeric_limits<double>::infinity();
  if (!std::isfinite(r.trajectory_error)) r.trajectory_error = std::numeric_limits<double>::infinity();
  return r;
}

double estimated_cost(const Scene& scene, const Combination& c, int repeats, int reference_iterations) {
  // Sweeps dominate; a thread count of t divides the threaded solvers' share (roughly).
  const double sweeps = double(repeats + 1) * c.steps * c.substeps * std::max(1, c.iterations);
  const double reference_steps = 1.3 * std::min(kStepSamples, c.steps) * c.substeps * reference_iterations;
  return (sweeps / (c.solver.threaded ? std::sqrt(double(c.threads)) : 1.0) + reference_steps) * scene_work(scene);
}

double estimated_reference_cost(const Scene& scene, int substeps, int steps, int iterations) {
  return 1.5 * double(steps) * substeps * iterations * scene_work(scene) * 1.3;  // double is slower than float
}

}  // namespace pbd::cli
