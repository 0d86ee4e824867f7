#include "study_runner.hpp"

#include "pbd/error.hpp"
#include "pbd/io/build_world.hpp"
#include "study_scenes.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>
#include <type_traits>

namespace pbd::cli {

std::pair<std::string, double> measure_of(const std::string& type) {
  if (const Measure* m = find_measure(type)) return {m->key, m->scale};
  return {type, 1.0};
}

Errors errors_of(const std::vector<NamedViolation>& violations) {
  Errors out;
  for (const NamedViolation& v : violations) {
    const auto [name, scale] = v.measure.key[0] ? std::pair<std::string, double>(v.measure.key, v.measure.scale)
                                                : measure_of(v.type);
    out[name] = {v.value.rms * scale, v.value.max * scale};
  }
  return out;
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// E_end − E_0 in units of M |g| size; only for scenes without colliders (contacts remove energy on purpose).
template <class Real>
std::optional<double> energy_drift(const World<Real>& world, const Energy& initial, double size) {
  if (!world.colliders().empty()) return std::nullopt;
  const double scale = movable_mass(world) * double(world.params().gravity.norm()) * size;
  if (!(scale > 0.0)) return std::nullopt;
  return (energy(world).total() - initial.total()) / scale;
}

template <class Real>
World<Real> prepared_world(const Scene& scene, Solver solver, Split split, bool chebyshev = false) {
  World<Real> world = build_world<Real>(scene.world);
  StepParams<Real> params = world.params();
  params.solver = solver;
  params.chebyshev.enabled = chebyshev;  // ρ = 0: the engine estimates it
  params.iterations = split.iterations;
  params.substeps = split.substeps;
  world.set_params(params);
  if (solver != Solver::serial) world.num_colors();  // color now: not part of any timed step
  return world;
}

template <class Real> void advance(World<Real>& world, int steps) {
  for (int s = 0; s < steps; ++s) world.step();
}

// The steps (0-based) the reference keeps: up to kSamples, evenly spread, the last included.
constexpr int kSamples = 5;
constexpr int kConvergenceSamples = 2;  // the reference's own convergence is checked at the last two
std::vector<int> sample_steps(int steps) {
  std::vector<int> out;
  const int n = std::min(kSamples, steps);
  for (int k = 0; k < n; ++k) out.push_back(int((long(k) + 1) * steps / n) - 1);
  return out;
}

// `world` put into a sampled reference state.
template <class Real> void load_sample(World<Real>& world, const ReferenceSample& s) {
  world.positions() = s.x.cast<Real>();
  world.velocities() = s.v.cast<Real>();
  world.set_time(s.time);
}

// RMS accumulation over samples of per-sample RMS distances.
struct Rms {
  double sum2 = 0.0, max = 0.0;
  int count = 0;
  void add(const Violation& d) {
    sum2 += d.rms * d.rms;
    max = std::max(max, d.max);
    ++count;
  }
  double rms() const { return count ? std::sqrt(sum2 / count) : 0.0; }
};

// RMS and maximum over particles of |a_i − b_i|, m.
Violation distance(const Matrix3X<double>& a, const Matrix3X<double>& b) {
  ViolationAccumulator acc;
  for (Eigen::Index i = 0; i < a.cols(); ++i) acc.add((a.col(i) - b.col(i)).norm());
  return acc.result();
}

double finite_or_inf(double v) { return std::isfinite(v) ? v : std::numeric_limits<double>::infinity(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A timed sample of a short run repeats it until it lasts this long, at most kMaxLoops times: a run of a tiny scene
// alone is too short for the clock and the scheduler's noise to be small against it.
constexpr double kMinSampleSeconds = 0.02;
constexpr int kMaxLoops = 1000;

// One combination of a group while the group runs.
template <class Real> struct Member {
  Combination c;
  std::unique_ptr<tbb::task_arena> arena;
  World<Real> initial;
  Energy e0;
  Record r;
  std::size_t first_sample = 0;
  int loops = 1;  // runs per timed sample
};

template <class Real>
std::vector<Record> run_group_typed(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                                    const Reference* ref, int repeats, LoadMonitor& load,
                                    const std::function<void(int, int)>& progress) {
  const int total = int(group.size()) * (repeats + 1);
  int done = 0;
  auto report_progress = [&] {
    ++done;
    if (progress) progress(done, total);
  };
  std::vector<Member<Real>> members;
  members.reserve(group.size());
  for (const Combination& c : group) {
    auto arena = std::make_unique<tbb::task_arena>(c.threads);
    World<Real> initial =
        arena->execute([&] { return prepared_world<Real>(scene, c.solver.solver, c.split, c.solver.chebyshev); });
    Member<Real> m{c, std::move(arena), std::move(initial), {}, {}, 0, 1};
    Record& r = m.r;
    r.scene = info.name;
    r.solver = c.solver.name;
    r.threads = c.threads;
    r.substeps = c.split.substeps;
    r.iterations = c.split.iterations;
    r.steps = c.steps;
    r.precision = std::is_same_v<Real, float> ? "float" : "double";
    r.repeats = repeats;
    r.particles = m.initial.num_particles();
    r.constraints = m.initial.num_constraints();
    r.colors = c.solver.solver == Solver::serial ? 0 : std::size_t(m.initial.num_colors());
    m.e0 = energy(m.initial);
    members.push_back(std::move(m));
  }
  // Warm-up: each member's run, untimed; it gives the final state's errors and hash, and how many runs one timed
  // sample needs to last kMinSampleSeconds.
  for (Member<Real>& m : members) {
    m.arena->execute([&] {
      Record& r = m.r;
      World<Real> world = m.initial;
      const auto t0 = Clock::now();
      advance(world, r.steps);
      const double seconds = seconds_since(t0);
      m.loops = std::clamp(int(std::ceil(kMinSampleSeconds / std::max(seconds, 1e-9))), 1, kMaxLoops);
      r.state_hash = position_hash(world);
      r.errors = errors_of(constraint_violations(world));
      const auto primary = r.errors.find(info.primary_error);
      r.primary_error = finite_or_inf(primary == r.errors.end() ? 0.0 : primary->second.rms);
      r.energy_drift = energy_drift(world, m.e0, info.size_m);
      if (ref) {
        r.trajectory_error_mm = finite_or_inf(1e3 * position_distance(world, ref->positions).rms);
        Rms step_error;  // one step from each sampled reference state, against the reference's step
        for (const ReferenceSample& s : ref->samples) {
          World<Real> w = m.initial;
          load_sample(w, s);
          w.step();
          step_error.add(position_distance(w, s.x_after));
        }
        r.ref_error_mm = finite_or_inf(1e3 * step_error.rms());
        r.ref_error_max_mm = finite_or_inf(1e3 * step_error.max);
      }
    });
    report_progress();
  }
  // The timed rounds, interleaved: A B C ... A B C ...
  for (Member<Real>& m : members) m.first_sample = load.count();
  std::vector<std::vector<double>> load_samples(members.size());
  for (int k = 0; k < repeats; ++k) {
    for (std::size_t i = 0; i < members.size(); ++i) {
      Member<Real>& m = members[i];
      load_samples[i].push_back(load.sample());
      m.arena->execute([&] {
        double seconds = 0.0;
        for (int l = 0; l < m.loops; ++l) {
          World<Real> world = m.initial;  // copied outside the timed region
          const auto t0 = Clock::now();
          advance(world, m.r.steps);
          seconds += seconds_since(t0);
          m.r.repeatable = m.r.repeatable && position_hash(world) == m.r.state_hash;
        }
        m.r.ms.push_back(1e3 * seconds / (double(m.r.steps) * m.loops));
      });
      report_progress();
    }
  }
  std::vector<Record> out;
  for (std::size_t i = 0; i < members.size(); ++i) {
    Record r = std::move(members[i].r);
    const auto [lo, hi] = std::minmax_element(r.ms.begin(), r.ms.end());
    r.ms_per_step = median(r.ms);
    r.ms_per_step_min = *lo;
    r.ms_per_step_max = *hi;
    double mean = 0.0, var = 0.0;
    for (double t : r.ms) mean += t / double(r.ms.size());
    for (double t : r.ms) var += (t - mean) * (t - mean);
    r.ms_per_step_cv = r.ms.size() > 1 && mean > 0.0 ? std::sqrt(var / double(r.ms.size() - 1)) / mean : 0.0;
    double sum = 0.0;
    for (double l : load_samples[i]) sum += l;
    r.load = load_samples[i].empty() ? 0.0 : sum / double(load_samples[i].size());
    r.busy = r.ms_per_step_cv > kBusyCv || r.load > kBusyLoad;
    out.push_back(std::move(r));
  }
  return out;
}

double scene_work(const SceneInfo& info) { return double(info.constraints + info.particles); }

}  // namespace

SceneInfo scene_info(const Scene& scene, int steps) {
  SceneInfo info;
  info.name = scene.name;
  info.steps = steps;
  info.particles = std::size_t(scene.world.num_particles());
  info.constraints = scene.world.num_constraints();
  info.family = is_generated_cloth(scene.name) ? "cloth" : "";
  World<double> world = build_world<double>(scene.world);
  info.size_m = bounding_diagonal(world);
  if (!(info.size_m > 0.0)) info.size_m = 1.0;
  std::vector<std::string> types;
  for (const NamedViolation& v : constraint_violations(world)) {
    types.push_back(v.type);
    info.measures.push_back(measure_of(v.type).first);
  }
  std::string primary = scene.primary_error == "penetration" ? "collision"
                        : scene.primary_error == "overlap"   ? "particle contact"
                                                             : scene.primary_error;
  if (primary.empty()) {
    for (const char* t : {"volume", "stretch"})
      if (primary.empty() && std::find(types.begin(), types.end(), t) != types.end()) primary = t;
    if (primary.empty() && !types.empty()) primary = types.front();
  } else if (std::find(types.begin(), types.end(), primary) == types.end()) {
    throw Error(scene.source + ": primary_error: the scene has no " +
                (primary == "collision"          ? std::string("collider")
                 : primary == "particle contact" ? std::string("contact body with a radius")
                                                 : primary + " constraint") +
                " to measure");
  }
  info.primary_error = primary.empty() ? "" : measure_of(primary).first;
  return info;
}

Reference compute_reference(const Scene& scene, const SceneInfo& info, Split split,
                            const std::function<void(int)>& progress) {
  const auto t0 = Clock::now();
  Reference ref;
  ref.scene = info.name;
  ref.substeps = split.substeps;
  ref.iterations = split.iterations;
  ref.steps = info.steps;
  World<double> world = prepared_world<double>(scene, Solver::serial, split);
  const std::vector<int> samples = sample_steps(info.steps);
  const int first_checked = samples[samples.size() - std::min<std::size_t>(kConvergenceSamples, samples.size())];
  Rms iteration_error, time_error;
  for (int s = 0; s < info.steps; ++s) {
    if (progress && s > 0) progress(s);
    if (std::find(samples.begin(), samples.end(), s) == samples.end()) {
      world.step();
      continue;
    }
    ReferenceSample sample{s, world.time(), world.positions(), world.velocities(), {}};
    // At the last samples, the same state stepped at half the iterations and at half the substeps: how far the
    // reference is from converged in each.
    const bool check = s >= first_checked;
    auto coarse_step = [&](Split coarse) {
      World<double> w = world;
      StepParams<double> params = w.params();
      params.substeps = coarse.substeps;
      params.iterations = coarse.iterations;
      w.set_params(params);
      w.step();
      return Matrix3X<double>(w.positions());
    };
    const Matrix3X<double> half_iterations = check ? coarse_step({split.substeps, split.iterations / 2}) : Matrix3X<double>();
    const Matrix3X<double> half_substeps = check ? coarse_step({split.substeps / 2, split.iterations}) : Matrix3X<double>();
    world.step();
    sample.x_after = world.positions();
    if (check) {
      iteration_error.add(distance(half_iterations, sample.x_after));
      time_error.add(distance(half_substeps, sample.x_after));
    }
    ref.samples.push_back(std::move(sample));
  }
  ref.positions = world.positions();
  ref.iteration_convergence_mm = 1e3 * iteration_error.rms();
  ref.time_convergence_mm = 1e3 * time_error.rms();
  ref.errors = errors_of(constraint_violations(world));
  ref.seconds = seconds_since(t0);
  return ref;
}

std::vector<Record> run_group(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                              const Reference* ref, int repeats, LoadMonitor& load,
                              const std::function<void(int, int)>& progress) {
  if (group.empty()) return {};
  return group.front().double_precision ? run_group_typed<double>(scene, info, group, ref, repeats, load, progress)
                                        : run_group_typed<float>(scene, info, group, ref, repeats, load, progress);
}

std::vector<double> shared_nothing_speedups(const Scene& part, int steps, Split split, int threads, int rounds) {
  const World<float> initial = prepared_world<float>(part, Solver::serial, split);
  int loops = 1;
  // Wall time of `copies` runs at once: the threads start, copy the world and wait; the clock runs from their
  // release to the last one's end (thread start-up and the first copy are not timed).
  auto run_copies = [&](int copies) {
    std::atomic<int> ready{0};
    std::atomic<bool> go{false};
    std::vector<Clock::time_point> ends(static_cast<std::size_t>(copies));
    std::vector<std::thread> team;
    for (int k = 0; k < copies; ++k)
      team.emplace_back([&, k] {
        tbb::task_arena arena(1);
        arena.execute([&] {
          World<float> world = initial;
          ready.fetch_add(1);
          while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
          for (int l = 0; l < loops; ++l) {
            if (l > 0) world = initial;
            advance(world, steps);
          }
          ends[std::size_t(k)] = Clock::now();
        });
      });
    while (ready.load() < copies) std::this_thread::yield();
    const auto t0 = Clock::now();
    go.store(true, std::memory_order_release);
    for (std::thread& t : team) t.join();
    return std::chrono::duration<double>(*std::max_element(ends.begin(), ends.end()) - t0).count();
  };
  // Warm-up, which also sets how many runs each copy makes so that one lasts kMinSampleSeconds.
  const double once = run_copies(1);
  loops = std::clamp(int(std::ceil(kMinSampleSeconds / std::max(once, 1e-9))), 1, kMaxLoops);
  std::vector<double> out;
  for (int k = 0; k < rounds; ++k) {
    const double alone = run_copies(1);
    const double together = run_copies(threads);
    out.push_back(threads * alone / together);
  }
  return out;
}

double estimated_group_cost(const SceneInfo& info, const std::vector<Combination>& group, int repeats) {
  double cost = 0.0;
  for (const Combination& c : group) {
    const double sweeps = double(repeats + 1) * c.steps * c.split.substeps * c.split.iterations + 1.0 * kSamples;
    cost += sweeps / (c.solver.threaded ? std::sqrt(double(c.threads)) : 1.0) * scene_work(info);
  }
  return cost;
}

double estimated_reference_cost(const SceneInfo& info, Split split) {
  const double steps = info.steps + 1.5 * std::min(kConvergenceSamples, info.steps);
  return 1.5 * steps * split.substeps * split.iterations * scene_work(info);  // double, serial
}

}  // namespace pbd::cli
