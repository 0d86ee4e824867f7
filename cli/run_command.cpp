// `pbd run SCENE`: steps a scene and writes its frames as OBJ or VTU files; prints the time per step, each
// constraint type's RMS error at the final frame and averaged over the run's steps (a moving scene's final frame is
// a noisy measure: runs are compared by the average), for every volume constraint the volume reached against its
// target, and the final state hash (a determinism check with --expect-hash); --stats writes each step's phase times
// as CSV, --breaks the fibers that broke (step, fiber, strain, force) as CSV.
//
// Outputs are complete whatever stops a run: the CSV files are written step by step (streamed_file.hpp), each frame
// whole (atomic_file.hpp), and on an error, a non-finite state (World::step fails at the step that made one, and
// undoes it, so nothing of it is written) or SIGINT/SIGTERM (stop_signals.hpp) the .pvd is rewritten to list every
// frame written before the run ends.
#include "commands.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/frame_series.hpp"
#include "pbd/io/streamed_file.hpp"
#include "option_rules.hpp"
#include "pbd/metrics.hpp"
#include "scene_dir.hpp"
#include "stop_signals.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
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
  std::string expect_hash;  // empty: no check
  std::string stats;        // --stats FILE: per-step phase times as CSV
  std::string breaks;       // --breaks FILE: the fibers that broke, as CSV
  std::string precision = "float";
  std::optional<double> chebyshev_rho;  // --chebyshev: accelerate with this ρ (0: estimated)
  bool hierarchy = false;               // --hierarchy: the coarse-to-fine pass (StepParams::hierarchy)
  std::optional<int> hierarchy_levels;  // --hierarchy-levels L (implies --hierarchy)
};

// The state hash as `pbd run` prints it and --expect-hash takes it: 16 lowercase hex digits.
std::string hex(std::uint64_t h) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

// One CSV row of a step's statistics (the header is kStatsHeader).
constexpr const char* kStatsHeader =
    "step,time_s,seconds,seconds_integrate,seconds_collisions,seconds_coloring,seconds_solve,seconds_waiting,"
    "seconds_hierarchy,solve_threads,substeps,sweeps,colors,collisions\n";
std::string stats_row(int step, double time, const StepStats& s) {
  char line[320];
  std::snprintf(line, sizeof line, "%d,%.9g,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%d,%d,%d,%u,%zu\n", step, time, s.seconds,
                s.seconds_integrate, s.seconds_collisions, s.seconds_coloring, s.seconds_solve, s.seconds_waiting,
                s.seconds_hierarchy, s.solve_threads, s.substeps, s.sweeps, unsigned(s.colors), s.collisions);
  return line;
}

// One CSV row per fiber a step broke (the header is kBreaksHeader): World::last_breaks.
// A fiber's row leaves particle_c and particle_d empty; its force is in N, a tet fiber's (a stress) in Pa.
constexpr const char* kBreaksHeader =
    "step,time_s,type,index,set,particle_a,particle_b,particle_c,particle_d,strain,force,force_unit\n";
std::string break_rows(std::span<const FiberBreak> breaks) {
  std::string csv;
  for (const FiberBreak& b : breaks) {
    char line[300];
    int n = std::snprintf(line, sizeof line, "%lld,%.9g,%s,%u,%u", static_cast<long long>(b.step), b.time, b.type,
                          unsigned(b.fiber), unsigned(b.set));
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t room = sizeof line - std::size_t(n);
      n += i < std::size_t(b.arity) ? std::snprintf(line + n, room, ",%u", unsigned(b.particles[i]))
                                    : std::snprintf(line + n, room, ",");
    }
    const char* unit = b.arity == 2 ? "N" : "Pa";
    std::snprintf(line + n, sizeof line - std::size_t(n), ",%.9g,%.9g,%s\n", b.strain, b.force, unit);
    csv += line;
  }
  return csv;
}

// "12 stretch, 0 bending, 0 area, 1 volume, 2 anchor": the constraints of every type, from the list: the types a
// body's mesh makes (SceneForm::mesh) in the list's order, then volume, then the types a scene lists by particle.
template <class Real> std::string constraint_counts(const World<Real>& world) {
  std::string text;
  auto count = [&](std::size_t n, const char* name) {
    if (!text.empty()) text += ", ";
    text += std::to_string(n);
    text += ' ';
    text += name;
  };
  auto types = [&](SceneForm form) {
    for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
      using C = typename decltype(type)::type;
      if (C::kSceneForm == form) count(world.template constraints<C>().size(), C::kName);
    });
  };
  types(SceneForm::mesh);
  count(world.volumes().size(), VolumeConstraint<Real>::kName);
  types(SceneForm::listed);
  return text;
}

// Each violation type's RMS and maximum after every step, summed, for the run's average (untimed).
struct RunErrors {
  std::vector<std::string> types;      // in constraint_violations' order
  std::vector<double> rms_sum, max_sum;
  std::vector<NamedViolation> last;
  int steps = 0;
  template <class Real> void add(const World<Real>& world) {
    last = constraint_violations(world);
    for (const NamedViolation& v : last) {
      auto it = std::find(types.begin(), types.end(), v.type);
      if (it == types.end()) {
        types.push_back(v.type);
        rms_sum.push_back(0.0);
        max_sum.push_back(0.0);
        it = types.end() - 1;
      }
      const std::size_t k = std::size_t(it - types.begin());
      rms_sum[k] += v.value.rms;
      max_sum[k] += v.value.max;
    }
    ++steps;
  }
  // "errors (RMS; final frame | averaged over N steps):" and one line per type in its measure's unit.
  void print() const {
    if (last.empty() || steps == 0) return;
    std::printf("errors (RMS at the final frame | averaged over the %d steps; max likewise):\n", steps);
    for (const NamedViolation& v : last) {
      const std::size_t k = std::size_t(std::find(types.begin(), types.end(), v.type) - types.begin());
      const Measure* m = v.measure.key[0] ? &v.measure : find_measure(v.type);
      const double scale = m ? m->scale : 1.0;
      std::printf("  %-16s %-4s rms %10.4g | %10.4g   max %10.4g | %10.4g\n", m ? m->key : v.type.c_str(),
                  m ? m->unit : "", scale * v.value.rms, scale * rms_sum[k] / steps, scale * v.value.max,
                  scale * max_sum[k] / steps);
    }
  }
};

// What a run writes as it goes: the frames (with the .pvd), the per-step statistics and the breaks.
struct RunOutputs {
  std::optional<FrameSeries> series;
  std::optional<StreamedFile> stats, breaks;

  // Completes what was written so far: the .pvd lists every frame written, the CSV files are closed.
  void finish() {
    if (series) series->finish();
    if (stats) stats->close();
    if (breaks) breaks->close();
  }
  // The same after the run failed: a failure here is printed, and the run's own error is the one reported.
  void finish_after_failure() noexcept {
    try {
      finish();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pbd run: also: %s\n", e.what());
    }
  }
};

// The outputs of a run, opened and checked before its first step: a folder, a full device or a read-only file
// system is refused now rather than after the run.
template <class Real> RunOutputs open_outputs(const Scene& scene, const RunOptions& o, const World<Real>& world) {
  RunOutputs out;
  if (!o.stats.empty()) out.stats.emplace(o.stats, kStatsHeader);
  if (!o.breaks.empty()) out.breaks.emplace(o.breaks, kBreaksHeader);
  if (!o.frames.empty()) {
    const std::filesystem::path dir = o.frames;
    check_frame_stem(scene.name);  // before the folder is made
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error(dir.string() + ": cannot create the frame directory (" + ec.message() + ")");
    // The scene's dt in double: frame times are step × dt, and a float world's dt is 1/60 rounded (90 steps:
    // 1.5000000782).
    out.series.emplace(dir, scene.name, parse_frame_format(o.format), frame_topology(world, scene.bodies),
                       scene.world.params.dt);
    out.series->prepare();
  }
  return out;
}

// What a run prints at its end: time per step, the errors (final and averaged over the steps taken), the volumes,
// the files written, the fibers broken and the state hash (returned).
template <class Real>
std::string print_summary(const World<Real>& world, const RunOptions& o, const std::vector<double>& ms,
                          const RunErrors& errors, const RunOutputs& out, std::size_t broken) {
  const VolumeConstraints<Real>& volumes = world.volumes();
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / double(std::max<std::size_t>(1, ms.size()));
  std::printf("time per step: median %.4f ms, mean %.4f ms, min %.4f ms\n", sorted.empty() ? 0.0 : sorted[sorted.size() / 2],
              mean, sorted.empty() ? 0.0 : sorted.front());
  const Violation v = stretch_violation(world);
  if (v.count) std::printf("stretch error: rms %.3e, max %.3e (relative)\n", v.rms, v.max);
  errors.print();
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
  const std::optional<FrameSeries>& series = out.series;
  if (series && series->frames_written())
    std::printf("wrote %zu frames to %s%s\n", series->frames_written(), o.frames.c_str(),
                series->format() == FrameFormat::vtu ? (" (series: " + series->pvd_file().string() + ")").c_str() : "");
  if (!o.stats.empty()) std::printf("wrote per-step statistics to %s\n", o.stats.c_str());
  if (broken) {  // of the fibers and tet fibers there were
    std::size_t left = 0;
    for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
      using C = typename decltype(type)::type;
      if constexpr (takes_material<C>()) left += world.template constraints<C>().size();
    });
    std::printf("fibers broken: %zu of %zu\n", broken, broken + left);
  }
  if (!o.breaks.empty()) std::printf("wrote the %zu breaks to %s\n", broken, o.breaks.c_str());
  const std::string hash = hex(position_hash(world));
  std::printf("state hash: %s\n", hash.c_str());
  return hash;
}

template <class Real> void run(const Scene& scene, const RunOptions& o, int steps, int threads) {
  const StopSignals signals;
  World<Real> world = build_world<Real>(scene.world);
  StepParams<Real> params = world.params();
  params.solver = *parse_solver(o.solver);
  if (!o.sweep_order.empty()) params.sweep_order = *parse_sweep_order(o.sweep_order);
  if (o.chebyshev_rho) {
    params.chebyshev.enabled = true;
    params.chebyshev.rho = Real(*o.chebyshev_rho);
  }
  if (o.hierarchy || o.hierarchy_levels) params.hierarchy.enabled = true;
  if (o.hierarchy_levels) params.hierarchy.levels = *o.hierarchy_levels;
  world.set_params(params);
  RunOutputs out = open_outputs(scene, o, world);
  bool torn = false;  // fibers broke since the last frame: its topology is made anew (the broken ones not drawn)
  auto frame = [&](int step) {
    torn = torn || !world.last_breaks().empty();
    if (!out.series || step % o.every != 0) return;
    if (torn) out.series->set_topology(frame_topology(world, scene.bodies));
    torn = false;
    out.series->write(world, step);
  };
  std::printf("# scene %s: %u particles; constraints: %s\n", scene.name.c_str(), world.num_particles(),
              constraint_counts(world).c_str());
  std::printf("# solver %s on %d threads, %s, dt %.6g s, %d substeps x %d iterations, %d steps\n", o.solver.c_str(),
              is_parallel(params.solver) ? threads : 1, sizeof(Real) == 4 ? "float" : "double", double(params.dt),
              params.substeps, params.iterations, steps);
  std::size_t broken = 0;
  std::vector<double> ms;
  RunErrors errors;
  auto last_report = std::chrono::steady_clock::now();
  int done = 0;  // the steps whose outputs are written
  try {
    frame(0);
    for (int s = 1; s <= steps && !signals.received(); ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      world.step();
      const auto t1 = std::chrono::steady_clock::now();
      ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      if (out.stats) out.stats->append(stats_row(s, world.time(), world.last_step_stats()));
      broken += world.last_breaks().size();
      if (out.breaks && !world.last_breaks().empty()) out.breaks->append(break_rows(world.last_breaks()));
      errors.add(world);
      frame(s);
      done = s;
      if (std::chrono::duration<double>(t1 - last_report).count() > 1.0) {
        std::fprintf(stderr, "pbd run: step %d of %d\n", s, steps);
        last_report = t1;
      }
    }
  } catch (...) {
    out.finish_after_failure();
    std::fflush(stdout);
    std::fprintf(stderr, "pbd run: the run stopped after step %d of %d; the outputs written before are complete\n",
                 done, steps);
    throw;
  }
  out.finish();  // the .pvd lists every frame
  // A run stopped by a signal reports the steps it took, as a whole run does, then exits 130 or 143 (main.cpp).
  const std::string hash = print_summary(world, o, ms, errors, out, broken);
  const int number = signals.received();
  if (number)
    throw Interrupted(number, "stopped by " + std::string(number == SIGINT ? "SIGINT" : "SIGTERM") + " after step " +
                                  std::to_string(done) + " of " + std::to_string(steps) +
                                  "; the outputs written are complete, and the summary above is of those steps");
  if (!o.expect_hash.empty() && hash != o.expect_hash)
    throw Error("--expect-hash: the final state hash is " + hash + ", expected " + o.expect_hash);
}

// The threads an arena of `requested` threads really runs: oneTBB runs at most its max_allowed_parallelism (the
// machine's cores unless a host lowered it).
int actual_threads(int requested) {
  const int allowed = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return requested > 0 ? std::min(requested, allowed) : allowed;
}

// Options that do nothing without, or next to, another one are refused (option_rules.hpp).
void check_option_rules(const CLI::App& cmd, const RunOptions& o) {
  refuse_without(cmd, "--format", "--frames", "only the frames have a format");
  refuse_without(cmd, "--every", "--frames", "it chooses the steps whose frames are written");
  const Solver solver = *parse_solver(o.solver);
  refuse_with(cmd, "--sweep-order", solver == Solver::jacobi, "--solver jacobi",
              "every Jacobi sweep reads the same positions: it has no order");
  refuse_with(cmd, "--threads", !is_parallel(solver) && o.threads > 1, "--solver " + o.solver,
              "it runs on one thread; the parallel solvers are colored, jacobi and block");
  refuse_with(cmd, "--chebyshev", solver == Solver::serial, "--solver serial",
              "the serial reference is never accelerated; serial-colored can be");
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scene and write its frames as OBJ or VTU files");
  cmd->add_option("scene", o->scene, "Scene name (pbd list: built-in or generated) or scene JSON file")->required();
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
  cmd->add_flag("--hierarchy", o->hierarchy, "Hierarchical PBD: a coarse-to-fine pass over the stretch constraints before each sub-step's sweeps");
  cmd->add_option("--hierarchy-levels", o->hierarchy_levels, "Coarse levels of --hierarchy (implies it; default 4)")
      ->check(CLI::Range(1, 16));
  cmd->add_option("--sweep-order", o->sweep_order, "forward or symmetric (default: the scene's own)")
      ->check(CLI::IsMember({"forward", "symmetric"}));
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores; at most what the machine gives)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--expect-hash", o->expect_hash,
                  "Exit with an error unless the final state hash (printed last) equals this one (16 hex digits)")
      ->check([](const std::string& h) {
        return h.size() == 16 && h.find_first_not_of("0123456789abcdef") == std::string::npos
                   ? std::string()
                   : "a state hash is 16 lowercase hex digits, as `pbd run` prints it";
      });
  cmd->add_option("--stats", o->stats,
                  "Write each step's phase times (s) and counts to this CSV file, a row as each step ends");
  cmd->add_option("--breaks", o->breaks,
                  "Write the fibers that broke (step, time, fiber, set, particles, strain, force in N) to this CSV file");
  cmd->add_option("--precision", o->precision, "float or double")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str();
  cmd->callback([o, cmd] {
    check_option_rules(*cmd, *o);
    for (const auto& [flag, file] : {std::pair{"--stats", &o->stats}, std::pair{"--breaks", &o->breaks}}) {
      if (file->empty()) continue;  // refused before the run, not after it
      const std::filesystem::path folder = std::filesystem::absolute(*file).parent_path();
      std::error_code ec;
      if (!std::filesystem::is_directory(folder, ec))
        throw Error(std::string(flag) + ": " + *file + ": the folder " + folder.string() + " does not exist");
    }
    const Scene scene = load_builtin_scene(o->scene);
    const int steps = o->steps > 0 ? o->steps : scene.steps;
    const int threads = actual_threads(o->threads);
    if (o->threads > threads)
      std::fprintf(stderr, "pbd run: --threads %d: this machine runs at most %d threads; running on %d\n", o->threads,
                   threads, threads);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      if (o->precision == "double") run<double>(scene, *o, steps, threads);
      else run<float>(scene, *o, steps, threads);
    });
  });
}

}  // namespace pbd::cli
