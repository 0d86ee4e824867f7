// `pbd study`: for now, runs one scene with the serial reference solver and prints, per step, the wall time and
// the stretch error reached (the full speed-vs-error study is issue 6).
#include "commands.hpp"
#include "pbd/metrics.hpp"
#include "pbd/scene.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

namespace pbd::cli {
namespace {

struct StudyOptions {
  std::string scene = "cloth";
  int steps = 0;  // 0: the scene's own
  std::string precision = "float";
  std::string solver = "serial";
  int threads = 0;  // 0: the arena's default
};

template <class Real> void run(const Scene& scene, int steps, Solver solver) {
  World<Real> world(scene.world);
  StepParams<Real> params = world.params();
  params.solver = solver;
  world.set_params(params);
  std::printf("# scene %s (%s), %u particles, %zu stretch constraints, precision %s\n", scene.name.c_str(),
              scene.source.c_str(), world.num_particles(), world.constraints().stretch.size(),
              sizeof(Real) == 4 ? "float" : "double");
  std::printf("# solver %s on %d threads, dt %.6g s, %d substeps, %d iterations\n", std::string(name(solver)).c_str(),
              tbb::this_task_arena::max_concurrency(), double(world.params().dt), world.params().substeps,
              world.params().iterations);
  std::printf("%6s %12s %14s %14s\n", "step", "ms", "rms_stretch", "max_stretch");
  std::vector<double> ms;
  for (int s = 1; s <= steps; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step();
    const auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    const Violation v = stretch_violation(world);
    std::printf("%6d %12.4f %14.6e %14.6e\n", s, ms.back(), v.rms, v.max);
  }
  std::sort(ms.begin(), ms.end());
  const Violation v = stretch_violation(world);
  std::printf("# median %.4f ms/step, min %.4f ms/step over %d steps; final stretch rms %.6e max %.6e\n",
              ms[ms.size() / 2], ms.front(), steps, v.rms, v.max);
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto opts = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand("study", "Run a scene and report time per step with the stretch error reached");
  cmd->add_option("--scene", opts->scene, "Built-in scene name or scene JSON file")->capture_default_str();
  cmd->add_option("--steps", opts->steps, "Number of steps (default: the scene's own)")->check(CLI::Range(1, 100000000));
  cmd->add_option("--precision", opts->precision, "float or double")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str();
  cmd->add_option("--solver", opts->solver, "serial, serial-colored, colored or jacobi")
      ->check(CLI::IsMember({"serial", "serial-colored", "colored", "jacobi"}))
      ->capture_default_str();
  cmd->add_option("--threads", opts->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->callback([opts] {
    const Scene scene = load_scene_by_name(opts->scene);
    const int steps = opts->steps > 0 ? opts->steps : scene.steps;
    const Solver solver = *parse_solver(opts->solver);
    tbb::task_arena arena(opts->threads > 0 ? opts->threads : tbb::task_arena::automatic);
    arena.execute([&] {
      if (opts->precision == "double") run<double>(scene, steps, solver);
      else run<float>(scene, steps, solver);
    });
  });
}

}  // namespace pbd::cli
