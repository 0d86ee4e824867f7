// Time to accuracy with and without the hierarchy (docs/performance.md): one scene, several splits, run side by
// side in one process with their steps interleaved (step i of every configuration before step i + 1 of any), so a
// busy machine slows them alike. For each configuration it prints the RMS relative stretch averaged over the run
// (mean of the per-step RMS, every step) and at the last step, and the time per step (median; and the hierarchy's
// share of it).
//   hierarchy_bench SCENE.json [--threads T] [--steps N] [--solver S] [--precision float|double] CONFIG...
// CONFIG is SUBSTEPSxITERATIONS, with "+h" for the hierarchy, then optionally its levels L and options: sK sweeps per
// coarse level, pK parents, eE slack (Hierarchy::slack), c compliant stretch too (e.g. 8x1 8x1+h 16x1+h3 8x1+h6s2p1
// 16x1+he0 1x20+hc).
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

struct Config {
  std::string label;
  int substeps = 1, iterations = 1, levels = 0, sweeps = 1, parents = 2;  // levels 0: no hierarchy
  bool compliant = false;
  double slack = pbd::Hierarchy{}.slack;
};

Config parse_config(const std::string& s) {
  Config c{s};
  const auto x = s.find('x');
  const auto plus = s.find('+');
  if (x == std::string::npos) throw std::runtime_error("config " + s + ": expected SxI[+h[L]]");
  c.substeps = std::stoi(s.substr(0, x));
  c.iterations = std::stoi(s.substr(x + 1, plus == std::string::npos ? std::string::npos : plus - x - 1));
  if (plus != std::string::npos) {
    const std::string h = s.substr(plus + 1);
    if (h.empty() || h[0] != 'h') throw std::runtime_error("config " + s + ": expected +h[L][sK][pK][eSLACK][c]");
    c.levels = pbd::Hierarchy{}.levels;
    std::size_t i = 1;
    auto number = [&] {
      std::size_t used = 0;
      const int v = std::stoi(h.substr(i), &used);
      i += used;
      return v;
    };
    if (i < h.size() && std::isdigit(static_cast<unsigned char>(h[i]))) c.levels = number();
    while (i < h.size()) {
      const char key = h[i++];
      if (key == 's') c.sweeps = number();
      else if (key == 'p') c.parents = number();
      else if (key == 'c') c.compliant = true;
      else if (key == 'e') {
        std::size_t used = 0;
        c.slack = std::stod(h.substr(i), &used);
        i += used;
      }
      else throw std::runtime_error("config " + s + ": unknown hierarchy option " + key);
    }
  }
  return c;
}

template <class Real>
int run(const pbd::Scene& scene, const std::vector<Config>& configs, pbd::Solver solver, int steps, int threads) {
  tbb::task_arena arena(threads);
  std::vector<pbd::World<Real>> worlds;
  for (const Config& c : configs) {
    pbd::World<Real> w = pbd::build_world<Real>(scene.world);
    pbd::StepParams<Real> p = w.params();
    p.solver = solver;
    p.substeps = c.substeps;
    p.iterations = c.iterations;
    p.hierarchy.enabled = c.levels > 0;
    if (c.levels > 0) p.hierarchy.levels = c.levels;
    p.hierarchy.sweeps = c.sweeps;
    p.hierarchy.parents = c.parents;
    p.hierarchy.compliant = c.compliant;
    p.hierarchy.slack = c.slack;
    w.set_params(p);
    worlds.push_back(std::move(w));
  }
  const std::size_t n = configs.size();
  std::vector<std::vector<double>> ms(n), hier_ms(n), solve_ms(n), integrate_ms(n);
  std::vector<double> rms_sum(n, 0.0), last_rms(n, 0.0), max_rms(n, 0.0);
  for (int step = 0; step < steps; ++step)
    for (std::size_t i = 0; i < n; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      arena.execute([&] { worlds[i].step(); });
      const auto t1 = std::chrono::steady_clock::now();
      ms[i].push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      const pbd::StepStats& st = worlds[i].last_step_stats();
      hier_ms[i].push_back(1e3 * st.seconds_hierarchy);
      solve_ms[i].push_back(1e3 * st.seconds_solve);
      integrate_ms[i].push_back(1e3 * st.seconds_integrate);
      const double rms = pbd::stretch_violation(worlds[i]).rms;
      rms_sum[i] += rms;
      last_rms[i] = rms;
      max_rms[i] = std::max(max_rms[i], rms);
    }
  std::printf("config,substeps,iterations,levels,rms_stretch_mean_pct,rms_stretch_last_pct,rms_stretch_max_pct,"
              "ms_per_step_median,ms_per_step_min,hierarchy_ms_median,solve_ms_median,integrate_ms_median,state_hash\n");
  for (std::size_t i = 0; i < n; ++i) {
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    std::printf("%s,%d,%d,%d,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%016llx\n", configs[i].label.c_str(), configs[i].substeps,
                configs[i].iterations, configs[i].levels, 100.0 * rms_sum[i] / steps, 100.0 * last_rms[i],
                100.0 * max_rms[i], median(ms[i]), *std::min_element(ms[i].begin(), ms[i].end()), median(hier_ms[i]),
                median(solve_ms[i]), median(integrate_ms[i]), static_cast<unsigned long long>(pbd::position_hash(worlds[i])));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3) {
      std::fprintf(stderr, "usage: %s SCENE.json [--threads T] [--steps N] [--solver S] [--precision P] SxI[+h[L]]...\n", argv[0]);
      return 2;
    }
    const pbd::Scene scene = pbd::load_scene(argv[1]);
    int threads = 2, steps = scene.steps;
    std::string solver = "colored", precision = "float";
    std::vector<Config> configs;
    for (int a = 2; a < argc; ++a) {
      const std::string arg = argv[a];
      if (arg == "--threads" && a + 1 < argc) threads = std::atoi(argv[++a]);
      else if (arg == "--steps" && a + 1 < argc) steps = std::atoi(argv[++a]);
      else if (arg == "--solver" && a + 1 < argc) solver = argv[++a];
      else if (arg == "--precision" && a + 1 < argc) precision = argv[++a];
      else configs.push_back(parse_config(arg));
    }
    const auto s = pbd::parse_solver(solver);
    if (!s) throw std::runtime_error("unknown solver " + solver);
    return precision == "double" ? run<double>(scene, configs, *s, steps, threads)
                                 : run<float>(scene, configs, *s, steps, threads);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hierarchy_bench: %s\n", e.what());
    return 1;
  }
}
