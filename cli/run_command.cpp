// `pbd run SCENE`: steps a scene and writes its frames as OBJ or VTU files; prints the time per step and, for every
// volume constraint, the volume reached against its target.
#include "commands.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/frame_series.hpp"
#include "pbd/metrics.hpp"
#include "scene_dir.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <numeric>
#include <optional>
#include <vector>

namespace pbd::cli {
namespace {

struct RunOptions {
  std::string scene;
  int steps = 0;  // 0: the scene's own
  std::string frames;
  std::string format = "obj";  // frame format: obj or vtu
  int every = 1;
  std::string solver = "colored";
  std::string sweep_order;  // empty: the scene's own
  int threads = 0;  // 0: the arena's default
  std::string precision = "float";
  std::optional<double> chebyshev_rho;  // --chebyshev: accelerate with this ρ (0: estimated)
};

template <class Real> void run(const Scene& scene, const RunOptions& o, int steps) {
  World<Real> world = build_world<Real>(scene.world);
  StepParams<Real> params = world.params();
  params.solver = *parse_solver(o.solver);
  if (!o.sweep_order.empty()) params.sweep_order = *parse_sweep_order(o.sweep_order);
  if (o.chebyshev_rho) {
    params.chebyshev.enabled = true;
    params.chebyshev.rho = Real(*o.chebyshev_rho);
  }
  world.set_params(params);
  std::optional<FrameSeries> series;
  if (!o.frames.empty()) {
    const std::filesystem::path dir = o.frames;
    check_frame_stem(scene.name);  // before the folder is made
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error(dir.string() + ": cannot create the frame directory (" + ec.message() + ")");
    series.emplace(dir, scene.name, parse_frame_format(o.format), frame_topology(world, scene.bodies));
  }
  auto frame = [&](int step) {
    if (series && step % o.every == 0) series->write(world, step);
  };
  const VolumeConstraints<Real>& volumes = world.volumes();
  std::printf("# scene %s: %u particles; constraints: %zu stretch, %zu bending, %zu area, %zu volume, %zu anchor\n",
              scene.name.c_str(), world.num_particles(), world.template constraints<StretchConstraint<Real>>().size(),
              world.template constraints<BendingConstraint<Real>>().size(),
              world.template constraints<AreaConstraint<Real>>().size(), volumes.size(),
              world.template constraints<AnchorConstraint<Real>>().size());
  std::printf("# solver %s on %d threads, %s, dt %.6g s, %d substeps x %d iterations, %d steps\n", o.solver.c_str(),
              tbb::this_task_arena::max_concurrency(), sizeof(Real) == 4 ? "float" : "double", double(params.dt),
              params.substeps, params.iterations, steps);
  frame(0);
  std::vector<double> ms;
  auto last_report = std::chrono::steady_clock::now();
  for (int s = 1; s <= steps; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step();
    const auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    frame(s);
    if (std::chrono::duration<double>(t1 - last_report).count() > 1.0) {
      std::fprintf(stderr, "pbd run: step %d of %d\n", s, steps);
      last_report = t1;
    }
  }
  if (!world.positions().allFinite()) throw Error("the simulation produced non-finite positions");
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / double(std::max<std::size_t>(1, ms.size()));
  std::printf("time per step: median %.4f ms, mean %.4f ms, min %.4f ms\n", sorted.empty() ? 0.0 : sorted[sorted.size() / 2],
              mean, sorted.empty() ? 0.0 : sorted.front());
  const Violation v = stretch_violation(world);
  if (v.count) std::printf("stretch error: rms %.3e, max %.3e (relative)\n", v.rms, v.max);
  const Matrix3X<Real> x = world.positions();
  for (std::size_t i = 0; i < volumes.size(); ++i) {
    const auto& vc = volumes.items[i];
    const std::span<const std::array<Index, 3>> tris(volumes.triangles.data() + vc.triangle_begin,
                                                     vc.triangle_end - vc.triangle_begin);
    const double target = double(vc.rest) * vc.pressure.at(world.time());
    const double now = double(six_volume<Real>(tris, x));
    std::printf("volume %zu: %.6g m^3, target %.6g m^3 (%.2fx rest), error %+.3f%%\n", i, now / 6, target / 6,
                vc.pressure.at(world.time()), 100.0 * (now / target - 1.0));
  }
  if (series && series->frames_written())
    std::printf("wrote %zu frames to %s%s\n", series->frames_written(), o.frames.c_str(),
                series->format() == FrameFormat::vtu ? (" (series: " + series->pvd_file().string() + ")").c_str() : "");
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scene and write its frames as OBJ or VTU files");
  cmd->add_option("scene", o->scene, "Built-in scene name or scene JSON file")->required();
  cmd->add_option("--steps", o->steps, "Number of steps (default: the scene's own)")->check(CLI::Range(1, 100000000));
  cmd->add_option("--frames", o->frames, "Write frames as DIR/<scene>_<step>.obj or .vtu (step 0 included)");
  cmd->add_option("--format", o->format, "Frame format: obj (Blender) or vtu (ParaView, with DIR/<scene>.pvd)")
      ->check(CLI::IsMember({"obj", "vtu"}))
      ->capture_default_str();
  cmd->add_option("--every", o->every, "Write every K-th step's frame")->check(CLI::Range(1, 100000000))->capture_default_str();
  std::vector<std::string> solvers;
  for (Solver s : kSolvers) solvers.emplace_back(name(s));
  cmd->add_option("--solver", o->solver, solver_names())->check(CLI::IsMember(solvers))->capture_default_str();
  cmd->add_option("--chebyshev", o->chebyshev_rho,
                  "Chebyshev acceleration of the sweeps with this spectral radius in [0, 1) (0: estimated)")
      ->check(CLI::Range(0.0, 0.999999));
  cmd->add_option("--sweep-order", o->sweep_order, "forward or symmetric (default: the scene's own)")
      ->check(CLI::IsMember({"forward", "symmetric"}));
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->add_option("--precision", o->precision, "float or double")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str();
  cmd->callback([o] {
    const Scene scene = load_builtin_scene(o->scene);
    const int steps = o->steps > 0 ? o->steps : scene.steps;
    tbb::task_arena arena(o->threads > 0 ? o->threads : tbb::task_arena::automatic);
    arena.execute([&] {
      if (o->precision == "double") run<double>(scene, *o, steps);
      else run<float>(scene, *o, steps);
    });
  });
}

}  // namespace pbd::cli
