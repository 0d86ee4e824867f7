#include "study_session.hpp"

#include "load_monitor.hpp"
#include "study_environment.hpp"
#include "study_runner.hpp"
#include "study_scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

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

// Scenes above this many particles get fewer splits per budget: 1 × N, the middle one and N × 1.
constexpr std::size_t kLargeScene = 50000;

// The engine estimates Chebyshev's ρ only from 4 iterations on (StepParams::chebyshev).
constexpr int kChebyshevMinIterations = 4;

// One unit of work, in the order they run.
struct Task {
  enum Kind { reference, group, shared_nothing } kind = group;
  std::size_t scene = 0;
  Split split;
  std::vector<Combination> combinations;  // group
  int threads = 0;                         // shared_nothing
  double cost = 0.0;
};

std::vector<Split> splits_for(const SceneInfo& info, int budget) {
  std::vector<Split> all = splits_of(budget);
  if (info.particles <= kLargeScene || all.size() <= 3) return all;
  return {all.front(), all[all.size() / 2], all.back()};
}

std::vector<Combination> combinations(const StudyPlan& plan, Split split, int steps) {
  std::vector<Combination> out;
  for (const StudySolver& solver : plan.solvers)
    for (int t : plan.threads) {
      if (!solver.threaded && t != plan.threads.front()) continue;  // one-thread solvers: once
      if (solver.chebyshev && split.iterations < kChebyshevMinIterations) continue;
      out.push_back({solver, solver.threaded ? t : 1, split, steps, plan.double_precision});
    }
  return out;
}

std::vector<Task> plan_tasks(const StudyPlan& plan, const std::vector<SceneInfo>& infos) {
  // Every group of every scene, numbered for the shards.
  std::vector<std::vector<Task>> groups(infos.size());
  std::vector<std::size_t> first_group(infos.size());
  std::size_t g = 0;
  for (std::size_t i = 0; i < infos.size(); ++i) {
    first_group[i] = g;
    std::vector<Split> splits;
    if (plan.scaling) splits = {plan.split};
    else
      for (int b : plan.budgets)
        for (Split s : splits_for(infos[i], b)) splits.push_back(s);
    for (Split s : splits) {
      if (int(g++ % std::size_t(plan.shards)) != plan.shard - 1) continue;
      Task t{Task::group, i, s, combinations(plan, s, infos[i].steps), 0, 0.0};
      t.cost = estimated_group_cost(infos[i], t.combinations, plan.repeats);
      groups[i].push_back(t);
    }
  }
  std::vector<Task> tasks;
  for (std::size_t i = 0; i < infos.size(); ++i) {
    if (groups[i].empty()) continue;
    if (!plan.scaling)
      tasks.push_back({Task::reference, i, plan.reference, {}, 0, estimated_reference_cost(infos[i], plan.reference)});
    for (Task& t : groups[i]) tasks.push_back(std::move(t));
    // The shared-nothing reference runs in the shard that has the scene's first group.
    const bool first = int(first_group[i] % std::size_t(plan.shards)) == plan.shard - 1;
    const Split sn = plan.scaling ? plan.split : Split{1, 4};
    if (first)
      for (int t : plan.threads)
        if (t > 1) {
          Task task{Task::shared_nothing, i, sn, {}, t, 0.0};
          task.cost = 2.0 * (std::max(plan.repeats, 3) + 1) * infos[i].steps * sn.substeps * sn.iterations *
                      double(infos[i].constraints + infos[i].particles);
          tasks.push_back(task);
        }
  }
  return tasks;
}

}  // namespace

Report run_study(const StudyPlan& plan) {
  Report report;
  LoadMonitor load;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const nlohmann::json env = study_environment(plan.commit);
  nlohmann::json context = study_context(env);
  context["load_before"] = load.settle(10, 50);
  std::vector<Scene> scenes;
  for (const std::string& name : plan.scenes) {
    scenes.push_back(load_study_scene(name));
    const Scene& s = scenes.back();
    const int steps = plan.steps > 0 ? plan.steps : plan.max_steps > 0 ? std::min(s.steps, plan.max_steps) : s.steps;
    report.scenes.push_back(scene_info(s, steps));
  }
  const std::vector<Task> tasks = plan_tasks(plan, report.scenes);
  double total_cost = 0.0, done_cost = 0.0;
  for (const Task& t : tasks) total_cost += t.cost;
  auto left = [&](double extra_done) {
    const double done = done_cost + extra_done;
    return done > 0.0 ? elapsed() * (total_cost - done) / done : 0.0;
  };
  std::size_t index = 0;
  std::vector<Reference> references(scenes.size());
  for (const Task& task : tasks) {
    ++index;
    const Scene& scene = scenes[task.scene];
    const SceneInfo& info = report.scenes[task.scene];
    char what[512];
    if (task.kind == Task::reference) {
      std::fprintf(stderr, "pbd study: [%zu/%zu] %s: converged reference (serial, double, %dx%d, %d steps) ...\n",
                   index, tasks.size(), info.name.c_str(), task.split.substeps, task.split.iterations, info.steps);
      auto last = Clock::now();
      references[task.scene] = compute_reference(scene, info, task.split, [&](int step) {
        if (std::chrono::duration<double>(Clock::now() - last).count() < 5.0) return;
        last = Clock::now();
        std::fprintf(stderr, "pbd study:   reference of %s: step %d of %d (elapsed %s, about %s left)\n",
                     info.name.c_str(), step, info.steps, clock_text(elapsed()).c_str(),
                     clock_text(left(task.cost * step / info.steps)).c_str());
      });
      const Reference& r = references[task.scene];
      report.references.push_back(r);
      report.references.back().samples.clear();
      std::snprintf(what, sizeof what, "%s reference done in %.1f s; one step at half its iterations moves %.2g mm, "
                    "at half its substeps %.2g mm", info.name.c_str(), r.seconds, r.iteration_convergence_mm,
                    r.time_convergence_mm);
    } else if (task.kind == Task::group) {
      const Reference* ref = plan.scaling ? nullptr : &references[task.scene];
      auto last = Clock::now();
      std::vector<Record> records =
          run_group(scene, info, task.combinations, ref, plan.repeats, load, [&](int done, int total) {
            if (std::chrono::duration<double>(Clock::now() - last).count() < 5.0) return;
            last = Clock::now();
            std::fprintf(stderr, "pbd study:   %s %dx%d: run %d of %d (elapsed %s, about %s left)\n",
                         info.name.c_str(), task.split.substeps, task.split.iterations, done, total,
                         clock_text(elapsed()).c_str(), clock_text(left(task.cost * done / total)).c_str());
          });
      std::string summary;
      for (const Record& r : records) {
        char s[128];
        std::snprintf(s, sizeof s, "%s%s %dT %.3g ms", summary.empty() ? "" : ", ", r.solver.c_str(), r.threads,
                      r.ms_per_step);
        summary += s;
      }
      double lo = records.front().primary_error, hi = lo;
      for (const Record& r : records) lo = std::min(lo, r.primary_error), hi = std::max(hi, r.primary_error);
      std::snprintf(what, sizeof what, "%s %dx%d: %s; %s %.3g to %.3g", info.name.c_str(), task.split.substeps,
                    task.split.iterations, summary.c_str(), info.primary_error.c_str(), lo, hi);
      for (Record& r : records) report.records.push_back(std::move(r));
    } else {
      // The parts: for a generated N×N cloth, T cloths of N/√T on a side (the same data split T ways); for any
      // other scene, T copies of it.
      const int rounds = std::max(plan.repeats, 3);
      Scene part_scene;
      const Scene* part = &scene;
      if (info.family == "cloth") {
        const int n = std::stoi(info.name.substr(5));
        part_scene = load_study_scene("cloth" + std::to_string(std::max(2, int(std::lround(n / std::sqrt(double(task.threads)))))));
        part = &part_scene;
      }
      report.shared_nothing.push_back(
          {info.name, task.threads, shared_nothing_speedups(*part, info.steps, task.split, task.threads, rounds)});
      std::vector<double> s = report.shared_nothing.back().speedups;
      std::sort(s.begin(), s.end());
      std::snprintf(what, sizeof what, "%s shared-nothing split on %d threads: %.2fx (%.2f-%.2f)", info.name.c_str(),
                    task.threads, s[s.size() / 2], s.front(), s.back());
    }
    done_cost += task.cost;
    std::fprintf(stderr, "pbd study: [%zu/%zu] %s (elapsed %s, about %s left)\n", index, tasks.size(), what,
                 clock_text(elapsed()).c_str(), clock_text(left(0.0)).c_str());
  }
  context["load_during"] = load.mean();
  context["load_during_max"] = load.max();
  context["loadavg_end"] = load_average();
  nlohmann::json solvers = nlohmann::json::array();
  for (const auto& s : plan.solvers) solvers.push_back(s.name);
  nlohmann::json options = {
      {"scenes", plan.scenes}, {"solvers", solvers}, {"threads", plan.threads},
      {"precision", plan.double_precision ? "double" : "float"}, {"repeats", plan.repeats},
      {"steps", plan.steps > 0 ? nlohmann::json(plan.steps) : nlohmann::json("scene")},
      {"quick", plan.quick},
      {"shard", plan.shards > 1 ? nlohmann::json(std::to_string(plan.shard) + "/" + std::to_string(plan.shards))
                                : nlohmann::json(nullptr)}};
  if (plan.scaling) options["split"] = {{"substeps", plan.split.substeps}, {"iterations", plan.split.iterations}};
  else {
    options["budgets"] = plan.budgets;
    options["reference"] = {{"substeps", plan.reference.substeps}, {"iterations", plan.reference.iterations}};
  }
  report.study = {{"command", env["command"]}, {"date", env["date"]}, {"git_commit", env["git_commit"]},
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
