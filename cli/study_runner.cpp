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
#include <map>
#include <memory>
#include <set>
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
// A timed run covers the whole run when one thread would do it in this long; a longer run is timed over its first
// steps (at least 2, lasting about this long): the step of a cloth costs the same all through its run, and its
// errors come from the one whole run made untimed.
constexpr double kWholeRunSeconds = 0.5;
// Timed runs longer than this get at most 2 rounds: their own length already averages out the clock's noise.
constexpr double kLongSampleSeconds = 0.25;

// The errors of a state: each type's measure, and a quasi-static scene's error against its closed form.
template <class Real> Errors state_errors(const World<Real>& world, const KnownAnswer& known) {
  Errors e = errors_of(constraint_violations(world));
  if (known.kind == "curve")
    for (const auto& [key, value] : curve_errors(world)) e[key] = value;
  if (!known.kind.empty())
    for (const auto& [key, value] : known_answer_errors(known, world.positions().template cast<double>()))
      e[key] = value;
  return e;
}

// Mean over steps of each measure's RMS and maximum.
struct ErrorMean {
  Errors sum;
  int count = 0;
  void add(const Errors& e) {
    for (const auto& [key, v] : e) {
      sum[key].rms += v.rms;
      sum[key].max += v.max;
    }
    ++count;
  }
  Errors mean() const {
    Errors out = sum;
    for (auto& [key, v] : out) v = {finite_or_inf(v.rms / std::max(count, 1)), finite_or_inf(v.max / std::max(count, 1))};
    return out;
  }
};

// What one whole untimed run gives: its errors, averaged over the steps from info.average_from on and at the end.
struct RunResult {
  Errors mean, final;
  Matrix3X<double> positions;
  std::uint64_t hash = 0;
  double step_seconds = 0.0;  // wall time of the steps alone (not of the error measures)
  double motion = 0.0;        // RMS displacement over the averaged steps, m
  std::optional<double> drift;
};

// Runs `world` over info.steps steps, measuring its errors after each; `before_step(s, world)` runs first at step s.
template <class Real, class BeforeStep>
RunResult error_run(World<Real> world, const SceneInfo& info, const KnownAnswer& known, BeforeStep&& before_step) {
  RunResult out;
  const Energy e0 = energy(world);
  ErrorMean mean;
  Matrix3X<double> window_start;
  for (int s = 0; s < info.steps; ++s) {
    if (s + 1 == info.average_from) window_start = world.positions().template cast<double>();
    before_step(s, world);
    const auto t0 = Clock::now();
    world.step();
    out.step_seconds += seconds_since(t0);
    if (s + 1 >= info.average_from) mean.add(state_errors(world, known));
  }
  out.mean = mean.mean();
  out.final = state_errors(world, known);
  // A type whose constraints all broke has no violation left to measure: 0, as for the steps it was gone in (the
  // mean counts them so), and so that every record has each of the scene's measures.
  for (const std::string& key : info.measures) {
    out.mean.try_emplace(key, ErrorValue{0.0, 0.0});
    out.final.try_emplace(key, ErrorValue{0.0, 0.0});
  }
  out.positions = world.positions().template cast<double>();
  out.hash = position_hash(world);
  if (window_start.cols() == out.positions.cols()) out.motion = distance(window_start, out.positions).rms;
  out.drift = energy_drift(world, e0, info.size_m);
  return out;
}

double primary_of(const Errors& e, const std::string& primary) {
  const auto it = e.find(primary);
  // Not among the state's errors (the reference's distance, measured later): NaN, not measured.
  return it == e.end() ? std::numeric_limits<double>::quiet_NaN() : finite_or_inf(it->second.rms);
}

// One combination of a group while the group runs.
template <class Real> struct Member {
  Combination c;
  std::unique_ptr<tbb::task_arena> arena;
  World<Real> initial;
  Record r;
  int loops = 1;               // runs per timed sample
  int rounds = 1;              // timed samples
  std::uint64_t timing_hash = 0;  // state after timing_steps steps
};

// The error run of each solver of the group, on its most threads (the parallel solvers end in the same bits on
// any count, which the timed runs check); the others take its errors. Returns each member's estimated seconds per
// step on one thread.
template <class Real>
std::vector<double> error_runs(std::vector<Member<Real>>& members, const SceneInfo& info,
                               const std::function<void()>& progress) {
  const KnownAnswer known = known_answer(info);
  std::map<std::string, std::size_t> runner;  // solver → the member that runs its errors
  for (std::size_t i = 0; i < members.size(); ++i) {
    const auto it = runner.find(members[i].c.solver.name);
    if (it == runner.end() || members[it->second].c.threads < members[i].c.threads)
      runner[members[i].c.solver.name] = i;
  }
  std::map<std::string, double> one_thread_step;  // solver → estimated seconds per step on one thread
  for (const auto& [name, i] : runner) {
    Member<Real>& m = members[i];
    Record& r = m.r;
    const RunResult run = m.arena->execute([&] { return error_run(m.initial, info, known, [](int, World<Real>&) {}); });
    r.state_hash = run.hash;
    r.errors = run.mean;
    r.errors_final = run.final;
    r.primary_error = primary_of(run.mean, info.primary_error);
    r.primary_error_final = primary_of(run.final, info.primary_error);
    r.energy_drift = run.drift;
    r.final_positions = run.positions;
    if (known.settled_motion > 0.0) {  // a quasi-static scene: it must have settled
      r.settle_motion_mm = 1e3 * run.motion;
      r.settled = run.motion < known.settled_motion;
    }
    one_thread_step[name] = run.step_seconds / std::max(info.steps, 1) * (m.c.solver.threaded ? m.c.threads : 1);
    if (progress) progress();
  }
  std::vector<double> out;
  for (Member<Real>& m : members) {
    const Record& from = members[runner[m.c.solver.name]].r;
    if (&from != &m.r) {
      m.r.state_hash = from.state_hash;
      m.r.errors = from.errors;
      m.r.errors_final = from.errors_final;
      m.r.primary_error = from.primary_error;
      m.r.primary_error_final = from.primary_error_final;
      m.r.energy_drift = from.energy_drift;
      m.r.final_positions = from.final_positions;
      m.r.settle_motion_mm = from.settle_motion_mm;
      m.r.settled = from.settled;
    }
    out.push_back(one_thread_step[m.c.solver.name]);
  }
  return out;
}

template <class Real>
std::vector<Record> run_group_typed(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                                    int repeats, LoadMonitor& load, const std::function<void(int, int)>& progress) {
  std::set<std::string> solvers;
  for (const Combination& c : group) solvers.insert(c.solver.name);
  const int total = int(solvers.size() + group.size()) + int(group.size()) * repeats;
  int done = 0;
  auto report_progress = [&] {
    ++done;
    if (progress) progress(std::min(done, total), total);
  };
  std::vector<Member<Real>> members;
  members.reserve(group.size());
  for (const Combination& c : group) {
    auto arena = std::make_unique<tbb::task_arena>(c.threads);
    World<Real> initial =
        arena->execute([&] { return prepared_world<Real>(scene, c.solver.solver, c.split, c.solver.chebyshev); });
    Member<Real> m{c, std::move(arena), std::move(initial), {}, 1, repeats, 0};
    Record& r = m.r;
    r.scene = info.name;
    r.variant = info.variant;
    r.solver = c.solver.name;
    r.threads = c.threads;
    r.substeps = c.split.substeps;
    r.iterations = c.split.iterations;
    r.steps = c.steps;
    r.precision = std::is_same_v<Real, float> ? "float" : "double";
    r.particles = m.initial.num_particles();
    r.constraints = m.initial.num_constraints();
    r.colors = c.solver.solver == Solver::serial ? 0 : std::size_t(m.initial.num_colors());
    members.push_back(std::move(m));
  }
  const std::vector<double> one_thread_step = error_runs(members, info, report_progress);
  // The timed runs' length (the same for every thread count of a solver, so their end states compare), and an
  // untimed warm-up of it that also sets how many runs one timed sample needs to last kMinSampleSeconds.
  for (std::size_t i = 0; i < members.size(); ++i) {
    Member<Real>& m = members[i];
    const double per_step = std::max(one_thread_step[i], 1e-9);
    m.r.timing_steps = per_step * m.r.steps <= kWholeRunSeconds
                           ? m.r.steps
                           : std::clamp(int(std::ceil(kWholeRunSeconds / per_step)), 2, m.r.steps);
    m.arena->execute([&] {
      World<Real> world = m.initial;
      const auto t0 = Clock::now();
      advance(world, m.r.timing_steps);
      const double seconds = seconds_since(t0);
      m.loops = std::clamp(int(std::ceil(kMinSampleSeconds / std::max(seconds, 1e-9))), 1, kMaxLoops);
      m.rounds = seconds > kLongSampleSeconds ? std::min(repeats, 2) : repeats;
      m.timing_hash = position_hash(world);
    });
    // A member that ran the whole run ends as its solver's error run did, on whatever thread count.
    if (m.r.timing_steps == m.r.steps && m.timing_hash != m.r.state_hash) m.r.repeatable = false;
    if (m.r.timing_steps == m.r.steps) m.r.state_hash = m.timing_hash;
    m.r.repeats = m.rounds;
    report_progress();
  }
  // The timed rounds, interleaved: A B C ... A B C ...
  std::vector<std::vector<double>> load_samples(members.size());
  for (int k = 0; k < repeats; ++k) {
    for (std::size_t i = 0; i < members.size(); ++i) {
      Member<Real>& m = members[i];
      if (k >= m.rounds) continue;
      load_samples[i].push_back(load.sample());
      m.arena->execute([&] {
        double seconds = 0.0;
        for (int l = 0; l < m.loops; ++l) {
          World<Real> world = m.initial;  // copied outside the timed region
          const auto t0 = Clock::now();
          advance(world, m.r.timing_steps);
          seconds += seconds_since(t0);
          m.r.repeatable = m.r.repeatable && position_hash(world) == m.timing_hash;
        }
        m.r.ms.push_back(1e3 * seconds / (double(m.r.timing_steps) * m.loops));
      });
      report_progress();
    }
  }
  // Every thread count of a solver ends its timed runs in the same bits.
  for (Member<Real>& m : members)
    for (const Member<Real>& o : members)
      if (o.c.solver.name == m.c.solver.name && o.timing_hash != m.timing_hash) m.r.repeatable = false;
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

// Seconds per work unit (one sweep over one constraint or particle on one thread) assumed by the estimates before
// the study has timed anything; the estimate of the time left is then rescaled by what has been measured.
// Calibrated against the idle default run at 6bb0c5e (293 s; its groups estimated 1.3–1.7× too cheap at 5 ns).
constexpr double kSecondsPerUnit = 7e-9;
// The serial reference solver's sweep costs several times a colored one's (it has no lanes).
// Serial, Jacobi and block cost about 5× the colored solver's per sweep (no lanes; the report at 6bb0c5e: 24–28
// against 4.6–5.4 ns per constraint on one thread on the generated cloths).
double solver_factor(const StudySolver& s) { return s.solver == Solver::colored || s.solver == Solver::serial_colored ? 1.0 : 5.0; }

}  // namespace

SceneInfo scene_info(const Scene& scene, int steps, const std::string& base, const std::string& variant) {
  SceneInfo info;
  info.base = base;
  info.variant = variant;
  info.name = variant == "plain" ? base : base + "+" + variant;
  info.steps = steps;
  info.particles = std::size_t(scene.world.num_particles());
  info.constraints = scene.world.num_constraints();
  info.family = is_generated_cloth(base) && known_answer(base).kind.empty() ? "cloth" : "";
  const KnownAnswer known = known_answer(base);
  info.known_answer = known.kind;
  // A quasi-static scene's error is that of the state it settles in: averaged over the last quarter of its run.
  info.average_from = known.kind.empty() ? 1 : std::max(1, steps - steps / 4);
  World<double> world = build_world<double>(scene.world);
  info.size_m = bounding_diagonal(world);
  if (!(info.size_m > 0.0)) info.size_m = 1.0;
  std::vector<std::string> types;
  for (const NamedViolation& v : constraint_violations(world)) {
    types.push_back(v.type);
    info.measures.push_back(measure_of(v.type).first);
  }
  for (const auto& [key, value] : known_answer_errors(known, world.positions())) info.measures.push_back(key);
  if (known.kind.empty() && has_curve(world)) {  // fibers on a curve: judged by their forces on it, no reference
    info.known_answer = "curve";
    info.average_from = 1;
    info.measures.push_back("curve_pct");
    info.primary_error = "curve_pct";
    return info;
  }
  std::string primary = scene.primary_error == "penetration" ? "collision"
                        : scene.primary_error == "overlap"   ? "particle contact"
                                                             : scene.primary_error;
  if (primary == "reference") {
    info.primary_error = kReferenceMeasure;  // set from the reference (study_report.cpp's finish)
    return info;
  }
  // A primary_error the scene has no measure for is refused where the scene is read (parse_scene), for every command.
  if (primary.empty()) {
    for (const char* t : {"volume", "stretch"})
      if (primary.empty() && std::find(types.begin(), types.end(), t) != types.end()) primary = t;
    if (primary.empty() && !types.empty()) primary = types.front();
  }
  info.primary_error = primary.empty() ? "" : measure_of(primary).first;
  if (known.kind == "chain") info.primary_error = "extension_pct";  // against α·T, not the constraints' own C
  return info;
}

Split half_of(Split split) {
  return split.substeps >= 2 ? Split{split.substeps / 2, split.iterations} : Split{1, split.iterations / 2};
}

ReferenceRun reference_run(const Scene& scene, const SceneInfo& info, const StudySolver& solver, int threads,
                           Split split, bool sampled, const std::function<void(int)>& progress) {
  const auto t0 = Clock::now();
  ReferenceRun out;
  out.split = split;
  tbb::task_arena arena(solver.threaded ? threads : 1);
  arena.execute([&] {
    const World<double> initial = prepared_world<double>(scene, solver.solver, split, solver.chebyshev);
    const std::vector<int> samples = sampled ? sample_steps(info.steps) : std::vector<int>();
    Rms step_change;
    std::optional<ReferenceSample> pending;  // a sample waiting for the positions after its step
    const RunResult run = error_run(initial, info, known_answer(info), [&](int s, World<double>& world) {
      if (progress && s > 0) progress(s);
      if (pending) {
        pending->x_after = world.positions();
        step_change.add(distance(pending->x_after, pending->x_half));
        out.samples.push_back(std::move(*pending));
        pending.reset();
      }
      if (std::find(samples.begin(), samples.end(), s) == samples.end()) return;
      // The same state stepped at half the budget: how far one step of the reference is from converged.
      World<double> half = world;
      StepParams<double> params = half.params();
      const Split h = half_of(split);
      params.substeps = h.substeps;
      params.iterations = h.iterations;
      half.set_params(params);
      half.step();
      pending = ReferenceSample{s, world.time(), world.positions(), world.velocities(), {}, half.positions()};
    });
    if (pending) {
      pending->x_after = run.positions;
      step_change.add(distance(pending->x_after, pending->x_half));
      out.samples.push_back(std::move(*pending));
    }
    out.mean = run.mean;
    out.final = run.final;
    out.positions = run.positions;
    out.step_change_mm = 1e3 * step_change.rms();
  });
  out.seconds = seconds_since(t0);
  return out;
}

Reference make_reference(const SceneInfo& info, const StudySolver& solver, int threads, const ReferenceRun& full,
                         const ReferenceRun& half) {
  Reference ref;
  ref.scene = info.base;
  ref.solver = solver.name;
  ref.threads = solver.threaded ? threads : 1;
  ref.substeps = full.split.substeps;
  ref.iterations = full.split.iterations;
  ref.steps = info.steps;
  ref.positions = full.positions;
  ref.samples = full.samples;
  ref.errors = full.mean;
  ref.errors_final = full.final;
  ref.step_change_mm = finite_or_inf(full.step_change_mm);
  ref.trajectory_change_mm = finite_or_inf(1e3 * distance(half.positions, full.positions).rms);
  for (const auto& [key, v] : full.mean) {
    const auto it = half.mean.find(key);
    if (it == half.mean.end()) continue;
    ref.error_change[key] = {finite_or_inf(std::abs(v.rms - it->second.rms)),
                             finite_or_inf(std::abs(v.max - it->second.max))};
  }
  return ref;
}

void compare_with_reference(const Scene& scene, const std::vector<StudySolver>& solvers, const Reference& ref,
                            std::vector<Record*>& records) {
  for (Record* r : records) {
    const auto solver = std::find_if(solvers.begin(), solvers.end(), [&](const StudySolver& s) { return s.name == r->solver; });
    if (solver == solvers.end()) continue;
    tbb::task_arena arena(r->threads);
    auto measure = [&](auto zero) {
      using Real = decltype(zero);
      const World<Real> initial = prepared_world<Real>(scene, solver->solver, {r->substeps, r->iterations}, solver->chebyshev);
      Rms step_error;  // one step from each sampled reference state, against the reference's step
      for (const ReferenceSample& s : ref.samples) {
        World<Real> w = initial;
        load_sample(w, s);
        w.step();
        step_error.add(position_distance(w, s.x_after));
      }
      r->ref_error_mm = finite_or_inf(1e3 * step_error.rms());
      r->ref_error_max_mm = finite_or_inf(1e3 * step_error.max);
      r->trajectory_error_mm = finite_or_inf(1e3 * distance(r->final_positions, ref.positions).rms);
    };
    arena.execute([&] {
      if (r->precision == "double") measure(0.0);
      else measure(0.0f);
    });
  }
}

std::vector<Record> run_group(const Scene& scene, const SceneInfo& info, const std::vector<Combination>& group,
                              int repeats, LoadMonitor& load, const std::function<void(int, int)>& progress) {
  if (group.empty()) return {};
  return group.front().double_precision ? run_group_typed<double>(scene, info, group, repeats, load, progress)
                                        : run_group_typed<float>(scene, info, group, repeats, load, progress);
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
  std::set<std::string> error_run;
  for (const Combination& c : group) {
    const double sweeps = double(c.split.substeps) * c.split.iterations;
    const double threads = (c.solver.threaded ? std::sqrt(double(c.threads)) : 1.0) / solver_factor(c.solver);
    // The error run measures every constraint after every step: about two sweeps more.
    if (error_run.insert(c.solver.name).second) cost += c.steps * (sweeps + 2.0) / threads * scene_work(info);
    // Warm-up and timed runs: whole runs up to kWholeRunSeconds, then a few steps (in work units, about 1 s).
    const double timed =
        std::min(c.steps * sweeps * scene_work(info), kWholeRunSeconds / kSecondsPerUnit / solver_factor(c.solver));
    cost += (1.0 + std::min(repeats, timed * kSecondsPerUnit > kLongSampleSeconds ? 2 : repeats)) * timed / threads;
  }
  return cost;
}

double estimated_reference_cost(const SceneInfo& info, Split split, int threads) {
  // A run at the budget and one at half of it, in double (about 1.3× float's cost), on `threads`.
  return 1.3 * 1.5 * info.steps * (split.substeps * split.iterations + 2.0) * scene_work(info) /
         std::sqrt(double(threads));
}

double seconds_per_unit() { return kSecondsPerUnit; }

}  // namespace pbd::cli
