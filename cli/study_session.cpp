#include "study_session.hpp"

#include "pbd/error.hpp"

#include "load_monitor.hpp"
#include "study_environment.hpp"
#include "study_runner.hpp"
#include "study_scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>

namespace pbd::cli {
namespace {

using Clock = std::chrono::steady_clock;

std::string clock_text(double seconds) {
  const long s = long(seconds + 0.5);
  char out[32];
  if (s >= 3600) std::snprintf(out, sizeof out, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(out, sizeof out, "%ld:%02ld", s / 60, s % 60);
  return out;
}

// Scenes above this many particles get fewer splits per budget (1 × N, the middle one and N × 1) and, with the
// default solvers, the colored solver alone (the others cost as much again each, and the headline is colored's).
constexpr std::size_t kLargeScene = 50000;
// With the default solvers, the solvers that cost about 5× the colored solver per sweep (serial, Jacobi, block) run
// where particles × steps × sweeps per step stay below this (the 100² cloth's 60 steps up to 16 sweeps): above it
// one run of theirs costs minutes. Variants other than plain run the colored solver alone (the headline's).
constexpr double kCostlyWork = 10000.0 * 60 * 16;
// With the default budgets, scenes above kLargeScene particles start at this budget: below it the 300² cloth
// stretches by tens of % and each group costs a few seconds of timing.
constexpr int kLargeSceneFirstBudget = 16;
// ... and their variants other than plain stop at this budget: above it a step of the 300² cloth takes over 10× the
// 33 ms the target allows, so a variant that needs more has missed it anyway.
constexpr int kLargeVariantLastBudget = 64;

// The engine estimates Chebyshev's ρ only from 4 iterations on (StepParams::chebyshev).
constexpr int kChebyshevMinIterations = 4;

// One scene as the study runs it: a variant of a named scene.
struct StudyScene {
  Scene scene;
  SceneInfo info;
};

// One unit of work, in the order they run.
struct Task {
  enum Kind { reference, group, shared_nothing } kind = group;
  std::size_t scene = 0;  // index into the study's scenes (for a reference: its plain variant's, or the first)
  Split split;
  std::vector<Combination> combinations;  // group
  int threads = 0;                         // shared_nothing
  double cost = 0.0;
};

std::vector<Split> splits_for(const SceneInfo& info, int budget) {
  std::vector<Split> all = study_splits(budget);
  // The chain's target is at one substep: its high budgets run as 1 × N too (it is tiny).
  if (info.known_answer == "chain" && all.size() == 1 && budget > 1) all.insert(all.begin(), Split{1, budget});
  if (info.particles <= kLargeScene || all.size() <= 3) return all;
  return {all.front(), all[all.size() / 2], all.back()};
}

std::vector<Combination> combinations(const StudyPlan& plan, const SceneInfo& info, Split split) {
  std::vector<Combination> out;
  const int budget = split.substeps * split.iterations;
  for (const StudySolver& solver : plan.solvers) {
    if (plan.default_solvers && !plan.scaling) {
      const bool costly = solver.solver != Solver::colored && solver.solver != Solver::serial_colored;
      if (costly && double(info.particles) * info.steps * budget > kCostlyWork) continue;
      if ((info.particles > kLargeScene || info.variant != "plain") && solver.name != "colored") continue;
    }
    for (int t : plan.threads) {
      if (!solver.threaded && t != plan.threads.front()) continue;  // one-thread solvers: once
      if (solver.chebyshev && split.iterations < kChebyshevMinIterations) continue;
      out.push_back({solver, solver.threaded ? t : 1, split, info.steps, plan.double_precision});
    }
  }
  return out;
}

int reference_threads(const StudyPlan& plan) { return plan.threads.back(); }

// Whether the scene gets a reference: main mode, and no closed form to be measured against instead.
bool wants_reference(const StudyPlan& plan, const SceneInfo& info) { return !plan.scaling && info.known_answer.empty(); }

std::vector<Task> plan_tasks(const StudyPlan& plan, const std::vector<StudyScene>& scenes) {
  // Every group of every scene, numbered for the shards.
  std::vector<std::vector<Task>> groups(scenes.size());
  std::vector<std::size_t> first_group(scenes.size());
  std::size_t g = 0;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const SceneInfo& info = scenes[i].info;
    first_group[i] = g;
    std::vector<Split> splits;
    if (plan.scaling) splits = {plan.split};
    else
      for (int b : plan.budgets)
        if (!plan.default_budgets ||
            ((b <= kOtherSceneBudget || is_generated_scene(info.base) || info.known_answer == "curve") &&
             (info.particles <= kLargeScene ||
              (b >= kLargeSceneFirstBudget && (info.variant == "plain" || b <= kLargeVariantLastBudget)))))
          for (Split s : splits_for(info, b)) splits.push_back(s);
    for (Split s : splits) {
      std::vector<Combination> group = combinations(plan, info, s);
      if (group.empty()) continue;
      if (int(g++ % std::size_t(plan.shards)) != plan.shard - 1) continue;
      Task t{Task::group, i, s, std::move(group), 0, 0.0};
      t.cost = estimated_group_cost(info, t.combinations, plan.repeats);
      groups[i].push_back(t);
    }
  }
  std::vector<Task> tasks;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const SceneInfo& info = scenes[i].info;
    for (Task& t : groups[i]) tasks.push_back(std::move(t));
    // The reference follows the last variant of its scene that this shard ran a group of: it is checked against
    // every record of the scene.
    const bool last_variant = i + 1 == scenes.size() || scenes[i + 1].info.base != info.base;
    bool any = false;
    for (std::size_t j = i + 1; j-- > 0 && scenes[j].info.base == info.base;) any = any || !groups[j].empty();
    if (last_variant && any && wants_reference(plan, info))
      tasks.push_back({Task::reference, i, plan.reference, {}, 0,
                       estimated_reference_cost(info, plan.reference, reference_threads(plan))});
    // The shared-nothing reference of the plain variant runs in the shard that has its first group.
    const bool first = int(first_group[i] % std::size_t(plan.shards)) == plan.shard - 1;
    const Split sn = plan.scaling ? plan.split : Split{1, 4};
    if (first && info.variant == "plain" && !groups[i].empty())
      for (int t : plan.threads)
        if (t > 1) {
          Task task{Task::shared_nothing, i, sn, {}, t, 0.0};
          task.cost = 2.0 * (std::max(plan.repeats, 3) + 1) * info.steps * sn.substeps * sn.iterations *
                      double(info.constraints + info.particles);
          tasks.push_back(task);
        }
  }
  return tasks;
}

// The scenes of the plan, each as every variant it runs, variants of one scene next to each other.
// With `stand_in`, a variant this build does not parse is planned with the plain scene in its place (--estimate).
std::vector<StudyScene> load_scenes(const StudyPlan& plan, bool stand_in = false) {
  std::vector<StudyScene> out;
  for (const std::string& name : plan.scenes) {
    const std::vector<std::string> variants = plan.scaling ? std::vector<std::string>{"plain"}
                                                           : study_variants(name, plan.variants, stand_in);
    for (const std::string& v : variants) {
      Scene scene;
      try {
        scene = load_study_scene(name, v);
      } catch (const Error&) {
        if (!stand_in) throw;
        scene = load_study_scene(name);
      }
      const int steps = plan.steps > 0                       ? plan.steps
                        : plan.max_steps > 0 ? std::min(scene.steps, plan.max_steps)
                                             : scene.steps;
      SceneInfo info = scene_info(scene, steps, scene.name, v);
      out.push_back({std::move(scene), std::move(info)});
    }
  }
  return out;
}

// The reference of the scene `scenes[last]` is a variant of: a run at plan.reference and one at half of it, then,
// while the check against the scene's records fails, twice the substeps (the old run is the new half), until
// plan.reference_max sweeps or plan.reference_seconds. Fills in the records' distances from it.
Reference converged_reference(const StudyPlan& plan, const std::vector<StudyScene>& scenes, std::size_t last,
                              std::vector<Record>& records, const std::function<void(const std::string&)>& say) {
  const SceneInfo& info = scenes[last].info;
  std::size_t plain = last;  // the scene's first variant (plain, when it runs)
  while (plain > 0 && scenes[plain - 1].info.base == info.base) --plain;
  Scene plain_scene = scenes[plain].info.variant == "plain" ? scenes[plain].scene : load_study_scene(info.base);
  const SceneInfo plain_info = scene_info(plain_scene, info.steps, info.base);
  const int threads = reference_threads(plan);
  const StudySolver& solver = plan.reference_solver;
  double spent = 0.0;
  auto run = [&](Split split, bool sampled) {
    char line[256];
    std::snprintf(line, sizeof line, "%s reference: %s, double, %dx%d, %d steps ...", info.base.c_str(),
                  solver.name.c_str(), split.substeps, split.iterations, info.steps);
    say(line);
    ReferenceRun r = reference_run(plain_scene, plain_info, solver, threads, split, sampled);
    spent += r.seconds;
    return r;
  };
  ReferenceRun half = run(half_of(plan.reference), false);
  ReferenceRun full = run(plan.reference, true);
  std::vector<std::string> tried;
  for (;;) {
    Reference ref = make_reference(plain_info, solver, threads, full, half);
    for (std::size_t i = plain; i <= last; ++i) {
      std::vector<Record*> mine;
      for (Record& r : records)
        if (r.scene == scenes[i].info.name) mine.push_back(&r);
      compare_with_reference(scenes[i].scene, plan.solvers, ref, mine);
    }
    check_reference(ref, records, plain_info.primary_error == kReferenceMeasure);
    ref.tried = tried;
    ref.seconds = spent;
    if (ref.converged) return ref;
    const Split next{full.split.substeps * 2, full.split.iterations};
    const double estimate = 2.0 * full.seconds;
    char line[512];
    // A shard sees only its part of the records: raising the reference there would give each part its own, so a
    // sharded run keeps --reference and `pbd study merge` checks it over every record.
    const bool over_budget = next.substeps * next.iterations > plan.reference_max || plan.shards > 1;
    const bool over_time = spent + estimate > plan.reference_seconds;
    std::snprintf(line, sizeof line, "%s reference at %dx%d is not converged (%s); %s %dx%d (about %.0f s)",
                  info.base.c_str(), full.split.substeps, full.split.iterations,
                  ref.failures.empty() ? "?" : ref.failures.front().c_str(),
                  over_budget || over_time ? "cannot raise it to" : "raising it to", next.substeps, next.iterations,
                  estimate);
    say(line);
    if (over_budget || over_time) {
      ref.capped = true;
      return ref;
    }
    tried.push_back(std::to_string(full.split.substeps) + "x" + std::to_string(full.split.iterations));
    half = std::move(full);
    full = run(next, true);
  }
}

}  // namespace

void estimate_study(const StudyPlan& plan) {
  const std::vector<StudyScene> scenes = load_scenes(plan, true);
  const std::vector<Task> tasks = plan_tasks(plan, scenes);
  double total = 0.0;
  std::printf("# pbd study --estimate: %zu tasks; seconds from the cost model (%.3g s per sweep over one constraint "
              "or particle on one thread), before anything is timed; a variant this build does not parse is "
              "costed as the plain scene\n", tasks.size(), seconds_per_unit());
  std::printf("%-28s %7s %7s %10s %12s\n", "scene", "groups", "points", "reference", "estimate_s");
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    int groups = 0, points = 0;
    double cost = 0.0, reference = 0.0;
    for (const Task& t : tasks) {
      if (t.scene != i) continue;
      cost += t.cost;
      if (t.kind == Task::group) ++groups, points += int(t.combinations.size());
      if (t.kind == Task::reference) reference += t.cost;
    }
    total += cost;
    std::printf("%-28s %7d %7d %10.0f %12.0f\n", scenes[i].info.name.c_str(), groups, points,
                reference * seconds_per_unit(), cost * seconds_per_unit());
  }
  std::printf("%-28s %7s %7s %10s %12.0f  (%s)\n", "total", "", "", "", total * seconds_per_unit(),
              clock_text(total * seconds_per_unit()).c_str());
  if (!plan.scaling)
    std::printf("# raising a reference that fails its check adds at most %.0f s per scene (--reference-seconds)\n",
                plan.reference_seconds);
}

Report run_study(const StudyPlan& plan) {
  Report report;
  LoadMonitor load;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const nlohmann::json env = study_environment(plan.commit);
  nlohmann::json context = study_context(env);
  context["load_before"] = load.settle(10, 50);
  const std::vector<StudyScene> scenes = load_scenes(plan);
  for (const StudyScene& s : scenes) report.scenes.push_back(s.info);
  const std::vector<Task> tasks = plan_tasks(plan, scenes);
  double total_cost = 0.0, done_cost = 0.0;
  for (const Task& t : tasks) total_cost += t.cost;
  std::fprintf(stderr, "pbd study: %zu scenes (with their variants), %zu tasks; estimated %s on this machine before "
               "any timing (the estimate of the time left is then rescaled by what has run)\n", scenes.size(),
               tasks.size(), clock_text(total_cost * seconds_per_unit()).c_str());
  auto left = [&](double extra_done) {
    const double done = done_cost + extra_done;
    return done > 0.0 ? elapsed() * (total_cost - done) / done : total_cost * seconds_per_unit();
  };
  std::size_t index = 0;
  for (const Task& task : tasks) {
    ++index;
    const Scene& scene = scenes[task.scene].scene;
    const SceneInfo& info = scenes[task.scene].info;
    std::string what;
    char line[512];
    if (task.kind == Task::reference) {
      const Reference r = converged_reference(plan, scenes, task.scene, report.records, [&](const std::string& text) {
        std::fprintf(stderr, "pbd study:   %s (elapsed %s)\n", text.c_str(), clock_text(elapsed()).c_str());
      });
      report.references.push_back(r);
      report.references.back().samples.clear();
      report.references.back().positions.resize(3, 0);
      std::snprintf(line, sizeof line, "%s reference %s %dx%d done in %.1f s: %s; at half its budget one step moves "
                    "%.2g mm, the run ends %.2g mm away", info.base.c_str(), r.solver.c_str(), r.substeps,
                    r.iterations, r.seconds, r.converged ? "converged" : "NOT CONVERGED", r.step_change_mm,
                    r.trajectory_change_mm);
      what = line;
    } else if (task.kind == Task::group) {
      auto last = Clock::now();
      std::vector<Record> records =
          run_group(scene, info, task.combinations, plan.repeats, load, [&](int done, int total) {
            if (std::chrono::duration<double>(Clock::now() - last).count() < 5.0) return;
            last = Clock::now();
            std::fprintf(stderr, "pbd study:   %s %dx%d: run %d of %d (elapsed %s, about %s left)\n",
                         info.name.c_str(), task.split.substeps, task.split.iterations, done, total,
                         clock_text(elapsed()).c_str(), clock_text(left(task.cost * done / total)).c_str());
          });
      for (const Record& r : records) {
        std::snprintf(line, sizeof line, "%s%s %dT %.3g ms", what.empty() ? "" : ", ", r.solver.c_str(), r.threads,
                      r.ms_per_step);
        what += line;
      }
      double lo = records.front().primary_error, hi = lo;
      for (const Record& r : records) lo = std::min(lo, r.primary_error), hi = std::max(hi, r.primary_error);
      std::snprintf(line, sizeof line, "%s %dx%d: ", info.name.c_str(), task.split.substeps, task.split.iterations);
      what = line + what;
      std::snprintf(line, sizeof line, "; %s (run average) %.3g to %.3g", info.primary_error.c_str(), lo, hi);
      if (info.primary_error != kReferenceMeasure) what += line;  // that one is measured with the reference
      for (Record& r : records) report.records.push_back(std::move(r));
    } else {
      // The parts: for a generated N×N cloth, T cloths of N/√T on a side (the same data split T ways); for any
      // other scene, T copies of it.
      const int rounds = std::max(plan.repeats, 3);
      Scene part_scene;
      const Scene* part = &scene;
      if (info.family == "cloth") {
        const int n = std::stoi(info.base.substr(5));
        part_scene = load_study_scene("cloth" + std::to_string(std::max(2, int(std::lround(n / std::sqrt(double(task.threads)))))));
        part = &part_scene;
      }
      report.shared_nothing.push_back(
          {info.name, task.threads, shared_nothing_speedups(*part, info.steps, task.split, task.threads, rounds)});
      std::vector<double> s = report.shared_nothing.back().speedups;
      std::sort(s.begin(), s.end());
      std::snprintf(line, sizeof line, "%s shared-nothing split on %d threads: %.2fx (%.2f-%.2f)", info.name.c_str(),
                    task.threads, s[s.size() / 2], s.front(), s.back());
      what = line;
    }
    done_cost += task.cost;
    std::fprintf(stderr, "pbd study: [%zu/%zu] %s (elapsed %s, about %s left)\n", index, tasks.size(), what.c_str(),
                 clock_text(elapsed()).c_str(), clock_text(left(0.0)).c_str());
  }
  for (Record& r : report.records) r.final_positions.resize(3, 0);
  context["load_during"] = load.mean();
  context["load_during_max"] = load.max();
  context["loadavg_end"] = load_average();
  nlohmann::json solvers = nlohmann::json::array();
  for (const auto& s : plan.solvers) solvers.push_back(s.name);
  nlohmann::json options = {
      {"scenes", plan.scenes}, {"solvers", solvers}, {"threads", plan.threads},
      {"precision", plan.double_precision ? "double" : "float"}, {"repeats", plan.repeats},
      {"steps", plan.steps > 0 ? nlohmann::json(plan.steps) : nlohmann::json("scene")},
      {"quick", plan.quick}, {"variants", plan.variants}, {"target_pct", plan.target},
      {"default_solvers", plan.default_solvers},
      {"shard", plan.shards > 1 ? nlohmann::json(std::to_string(plan.shard) + "/" + std::to_string(plan.shards))
                                : nlohmann::json(nullptr)}};
  if (plan.scaling) options["split"] = {{"substeps", plan.split.substeps}, {"iterations", plan.split.iterations}};
  else {
    options["budgets"] = plan.budgets;
    options["reference"] = {{"solver", plan.reference_solver.name}, {"substeps", plan.reference.substeps},
                            {"iterations", plan.reference.iterations}, {"max_budget", plan.reference_max},
                            {"max_seconds", plan.reference_seconds}};
  }
  report.study = {{"pbd_version", env["pbd_version"]}, {"command", env["command"]}, {"date", env["date"]},
                  {"git_commit", env["git_commit"]},
                  {"seconds", elapsed()}, {"mode", plan.scaling ? "scaling" : "study"}, {"context", context},
                  {"options", options}};
  // Scenes no group of this shard touched are left out of its report.
  std::vector<SceneInfo> touched;
  for (const SceneInfo& s : report.scenes)
    if (std::any_of(report.records.begin(), report.records.end(), [&](const Record& r) { return r.scene == s.name; }))
      touched.push_back(s);
  report.scenes = touched;
  finish(report);
  return report;
}

}  // namespace pbd::cli
