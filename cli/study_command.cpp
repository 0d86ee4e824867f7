// `pbd study`: the speed-vs-error study. Runs scenes × substeps × iterations × solvers × threads; for each
// combination measures the wall time per step (median and minimum of repeated runs after a warm-up) and the error
// reached (constraint violations, distance from a converged reference, energy drift), and reports them as a table
// on stdout, a JSON file and plots. Progress, with the estimated time left, goes to stderr.
#include "commands.hpp"
#include "pbd/error.hpp"
#include "study_environment.hpp"
#include "study_options.hpp"
#include "study_report.hpp"
#include "study_runner.hpp"
#include "study_scenes.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace pbd::cli {
namespace {

std::string clock_text(double seconds) {
  const long s = long(seconds + 0.5);
  char out[32];
  if (s >= 3600) std::snprintf(out, sizeof out, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(out, sizeof out, "%ld:%02ld", s / 60, s % 60);
  return out;
}

// One unit of work: a reference or a combination of one scene.
struct Task {
  std::size_t scene = 0;
  bool reference = false;
  Combination combination;
  double cost = 0.0;
};

std::vector<Task> plan_tasks(const StudyPlan& plan, const std::vector<Scene>& scenes) {
  std::vector<Task> tasks;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const Scene& scene = scenes[i];
    const int steps = plan.steps > 0 ? plan.steps : scene.steps;
    for (int sub : plan.substeps) {
      Task ref{i, true, Combination{plan.solvers.front(), 1, plan.reference_iterations, sub, steps, true}, 0.0};
      ref.cost = estimated_reference_cost(scene, sub, steps, plan.reference_iterations);
      tasks.push_back(ref);
      for (int it : plan.iterations)
        for (const StudySolver& solver : plan.solvers)
          for (int t : plan.threads) {
            if (!solver.threaded && t != plan.threads.front()) continue;  // one-thread solvers: once
            Task task{i, false, Combination{solver, t, it, sub, steps, plan.double_precision}, 0.0};
            task.cost = estimated_cost(scene, task.combination, plan.repeats, plan.reference_iterations);
            tasks.push_back(task);
          }
    }
  }
  return tasks;
}

void write_json(const std::filesystem::path& file, const nlohmann::json& doc) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  std::ofstream f(file);
  if (!(f << doc.dump(1) << "\n")) throw Error("--json: cannot write " + file.string());
}

void run_study(const StudyPlan& plan) {
  nlohmann::json environment = study_environment();
  std::vector<Scene> scenes;
  for (const std::string& name : plan.scenes) scenes.push_back(load_study_scene(name));
  const std::vector<Task> tasks = plan_tasks(plan, scenes);
  double total_cost = 0.0, done_cost = 0.0;
  for (const Task& t : tasks) total_cost += t.cost;
  std::vector<Reference> references;
  std::vector<Record> records;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t combinations = tasks.size();
  std::size_t index = 0;
  for (const Task& task : tasks) {
    ++index;
    const Scene& scene = scenes[task.scene];
    const Combination& c = task.combination;
    char what[256];
    if (task.reference) {
      references.push_back(compute_reference(scene, c.substeps, c.steps, c.iterations));
      const Reference& r = references.back();
      std::snprintf(what, sizeof what, "%s reference (serial, double, %d iterations, %d substeps, %d steps): "
                    "%.1f s; N/2 vs N iterations: %.1e per step, %.1e over the run", scene.name.c_str(), r.iterations,
                    r.substeps, r.steps, r.seconds, r.step_convergence, r.trajectory_convergence);
    } else {
      records.push_back(run_combination(scene, c, references.back(), plan.repeats));
      const Record& r = records.back();
      std::snprintf(what, sizeof what, "%s %s %d thr %d it %d sub: %.4f ms/step, ref_error %.2e, rms_violation %.2e",
                    r.scene.c_str(), r.solver.c_str(), r.threads, r.iterations, r.substeps, r.ms_per_step,
                    r.ref_error, r.rms_violation);
    }
    done_cost += task.cost;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double left = done_cost > 0.0 ? elapsed * (total_cost - done_cost) / done_cost : 0.0;
    std::fprintf(stderr, "pbd study: [%zu/%zu] %s (elapsed %s, about %s left)\n", index, combinations, what,
                 clock_text(elapsed).c_str(), clock_text(left).c_str());
  }
  const std::vector<Dominance> dom = dominance(records);
  print_table(std::cout, records, dom);
  std::cout.flush();
  environment["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  environment["machine"]["load_average_at_end"] = study_environment()["machine"]["load_average_at_start"];
  std::filesystem::path json = plan.json;
  if (json.empty() && !plan.plots.empty()) json = std::filesystem::path(plan.plots) / "study.json";
  if (!json.empty()) {
    write_json(json, report_json(plan, environment, references, records, dom));
    std::fprintf(stderr, "pbd study: wrote %s\n", json.string().c_str());
  }
  if (!plan.plots.empty()) run_plot_script(json, plan.plots);
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "The speed-vs-error study: time per step and error reached for scenes x solvers x threads x "
               "iterations x substeps (table on stdout, JSON report, plots)");
  cmd->add_option("--scene", o->scenes,
                  "Built-in scene, cloth100/cloth300/cloth1000 (generated hanging cloth, for scaling) or a scene "
                  "JSON file; repeatable or comma-separated (default: every built-in scene)");
  cmd->add_option("--solvers", o->solvers, "Comma-separated: serial, serial-colored, colored, jacobi")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "Comma-separated thread counts (serial solvers run once, at the fewest)")
      ->capture_default_str();
  cmd->add_option("--iterations", o->iterations, "Comma-separated iterations per substep")->capture_default_str();
  cmd->add_option("--substeps", o->substeps, "Comma-separated substeps per step")->capture_default_str();
  cmd->add_option("--steps", o->steps, "Steps per run (default: each scene's own)")->check(CLI::Range(1, 100000000));
  cmd->add_option("--precision", o->precision, "float or double")->capture_default_str();
  cmd->add_option("--repeats", o->repeats, "Timed runs per combination after the warm-up (default 5; --quick 1)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--reference-iterations", o->reference_iterations,
                  "Iterations per substep of the converged reference (serial, double; default 200; --quick 50)")
      ->check(CLI::Range(2, 1000000));
  cmd->add_option("--json", o->json, "Write the JSON report to FILE");
  cmd->add_option("--plots", o->plots,
                  "Write plots (PNG) to DIR with scripts/plot_study.py (and the JSON to DIR/study.json if no --json)");
  cmd->add_flag("--quick", o->quick,
                "Smoke test: iterations 1,4, 20 steps, 1 timed run, 50-iteration reference (explicit options win)");
  cmd->callback([o, cmd] {
    o->given_iterations = cmd->count("--iterations") > 0;
    run_study(make_plan(*o));
  });
}

}  // namespace pbd::cli
