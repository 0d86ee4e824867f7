#pragma once
// What both bench/peer bar drivers share (standard library only: the peer's driver includes it too): the bar file of
// make_bar.py, the command line, the tip's trajectory and its error against a reference trajectory, and the one line
// of JSON they print. bench/peer/README.md, "The bar".
#include "cloth_common.hpp"  // number(), Clock, ms_since(), cpu_ms(): standard library only as well

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace peer_bench {

/// The bar as make_bar.py writes it (the peer's BarDemo mesh, in the peer's order).
struct Bar {
  int width = 0, height = 0, depth = 0;         ///< vertices along x, y, z
  std::array<double, 3> size{}, translation{};  ///< the demo's scale and translation
  std::vector<std::array<double, 3>> x;         ///< vertex positions, m
  double mass = 1;                              ///< every vertex's mass before the pins, kg
  std::vector<unsigned> pinned;                 ///< vertices of mass 0 (the clamped end, i = 0)
  std::vector<unsigned> tip;                    ///< the far end's vertices (i = width − 1)
  std::vector<std::array<unsigned, 4>> tets;    ///< tets, corners in the peer's order
};

inline Bar read_bar(const std::string& path) {
  KeywordFile f(path, "pbd_peer_bar");
  std::stringstream& text = f.text;
  auto expect = [&](const char* word) { f.expect(word); };
  auto count = [&](const char* word) { return f.count(word); };
  Bar b;
  expect("width");
  text >> b.width;
  expect("height");
  text >> b.height;
  expect("depth");
  text >> b.depth;
  expect("size");
  text >> b.size[0] >> b.size[1] >> b.size[2];
  expect("translation");
  text >> b.translation[0] >> b.translation[1] >> b.translation[2];
  b.x.resize(count("vertices"));
  for (auto& p : b.x) text >> p[0] >> p[1] >> p[2];
  expect("mass");
  text >> b.mass;
  b.pinned.resize(count("pinned"));
  for (auto& i : b.pinned) text >> i;
  b.tip.resize(count("tip"));
  for (auto& i : b.tip) text >> i;
  b.tets.resize(count("tets"));
  for (auto& t : b.tets) text >> t[0] >> t[1] >> t[2] >> t[3];
  if (!text) throw std::runtime_error(path + ": truncated or malformed");
  if (b.width < 2 || b.height < 2 || b.depth < 2 || b.x.size() != std::size_t(b.width) * b.height * b.depth)
    throw std::runtime_error(path + ": the vertex count is not width × height × depth");
  if (!(b.mass > 0)) throw std::runtime_error(path + ": the mass must be > 0");
  if (b.tip.empty()) throw std::runtime_error(path + ": no tip vertices");
  const std::size_t nv = b.x.size();
  auto check = [&](unsigned i) {
    if (i >= nv) throw std::runtime_error(path + ": vertex index " + std::to_string(i) + " out of range");
  };
  for (unsigned i : b.pinned) check(i);
  for (unsigned i : b.tip) check(i);
  for (auto& t : b.tets) for (unsigned i : t) check(i);
  return b;
}

/// The bar drivers' command line (the same for both engines).
struct BarOptions {
  std::string mesh;               ///< make_bar.py's file (required)
  int steps = 400;                ///< steps timed (400 × 5 ms = 2 s: the bar falls and swings back once)
  int substeps = 5;               ///< sub-steps per step (the peer's TimeStepController default)
  int iterations = 1;             ///< sweeps per sub-step (the peer's default)
  int threads = 0;                ///< 0: the engine's default
  bool use_double = false;        ///< pbd: World<double> (the peer is always double)
  std::string solver;             ///< pbd only; empty: the driver's default
  int inline_below = 0;           ///< pbd only: ParallelConfig::inline_below (0: pbd's default)
  std::string method;             ///< the solid model; empty: the driver's default (pbd: neo-hookean; peer: fem)
  double dt = 0.005;              ///< step, s (the demo's setTimeStepSize(0.005))
  double young = 1e6;             ///< Young's modulus E, Pa (the demo's solid stiffness for its FEM XPBD method)
  double poisson = 0.3;           ///< Poisson's ratio ν (the peer's default solid Poisson ratio)
  double stiffness = 1.0;         ///< PBD stiffness k of the peer's shape matching (the demo's solid stiffness 1)
  double damping = 0.0;           ///< velocity damping rate, 1/s (0: none, as the demo; only for static sags)
  std::string reference;          ///< tip trajectory to measure the error against (empty: none)
  std::string write_reference;    ///< write this run's tip trajectory there
};

inline void bar_usage(const char* prog, const char* extra) {
  std::fprintf(stderr,
               "usage: %s --mesh FILE [--steps 400] [--substeps 5] [--iterations 1] [--threads T] [--double]\n"
               "          [--solver NAME] [--method NAME] [--dt 0.005] [--young 1e6] [--poisson 0.3] [--stiffness 1]\n"
               "          [--damping 0] [--reference FILE] [--write-reference FILE] [--inline-below N]\n%s",
               prog, extra);
}

inline BarOptions parse_bar(int argc, char** argv, const char* extra_help) {
  BarOptions o;
  ArgReader r(argc, argv, [&] { bar_usage(argv[0], extra_help); });
  while (r.next()) {
    const std::string& a = r.option();
    if (read_run_option(r, o)) continue;
    if (a == "--inline-below") o.inline_below = r.integer(1);
    else if (a == "--method") o.method = r.value();
    else if (a == "--young") o.young = r.real();
    else if (a == "--poisson") o.poisson = r.real();
    else if (a == "--stiffness") o.stiffness = r.real();
    else if (a == "--damping") o.damping = r.real();
    else if (a == "--reference") o.reference = r.value();
    else if (a == "--write-reference") o.write_reference = r.value();
    else if (a == "-h" || a == "--help") r.help();
    else r.unknown();
  }
  if (o.mesh.empty()) r.fail("--mesh is required (bench/peer/make_bar.py writes it)");
  if (!(o.dt > 0)) r.fail("--dt must be > 0");
  if (!(o.young > 0)) r.fail("--young must be > 0");
  if (!(o.poisson < 0.5)) r.fail("--poisson must be in [0, 0.5)");
  return o;
}

using Point = std::array<double, 3>;

/// The mean of the tip vertices' positions; position(i) gives particle i's (in double).
inline Point tip_of(const Bar& b, const std::function<Point(unsigned)>& position) {
  Point m{0, 0, 0};
  for (unsigned i : b.tip) {
    const Point p = position(i);
    for (int d = 0; d < 3; ++d) m[d] += p[d];
  }
  for (double& v : m) v /= double(b.tip.size());
  return m;
}

/// A tip trajectory: where the tip starts and where it is after each step.
struct Trajectory {
  double dt = 0;
  Point start{};
  std::vector<Point> tip;  ///< after step 1, 2, …
  std::string made_by;     ///< a comment: engine, precision, split
};

inline void write_trajectory(const std::string& path, const Trajectory& t) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write");
  std::fprintf(f, "# the bar's tip (mean of the far end's vertices) after each step: %s\n", t.made_by.c_str());
  std::fprintf(f, "pbd_peer_bar_tip 1\ndt %.17g\nstart %.17g %.17g %.17g\nsteps %zu\n", t.dt, t.start[0], t.start[1],
               t.start[2], t.tip.size());
  for (const Point& p : t.tip) std::fprintf(f, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  if (std::fclose(f) != 0) throw std::runtime_error(path + ": write failed");
}

inline Trajectory read_trajectory(const std::string& path) {
  KeywordFile f(path, "pbd_peer_bar_tip");
  std::stringstream& text = f.text;
  auto expect = [&](const char* word) { f.expect(word); };
  Trajectory t;
  expect("dt");
  text >> t.dt;
  expect("start");
  text >> t.start[0] >> t.start[1] >> t.start[2];
  expect("steps");
  long long n = -1;
  text >> n;
  if (n < 0) throw std::runtime_error(path + ": bad step count");
  t.tip.resize(std::size_t(n));
  for (Point& p : t.tip) text >> p[0] >> p[1] >> p[2];
  if (!text) throw std::runtime_error(path + ": truncated or malformed");
  return t;
}

/// The tip's distance from the reference's, in mm: RMS over the run's steps, at its last step, and the largest.
struct TipError {
  double rms_mm = -1, final_mm = -1, max_mm = -1;  ///< -1: no reference
};

inline TipError tip_error(const Trajectory& run, const Trajectory& ref) {
  if (std::abs(run.dt - ref.dt) > 1e-12 * ref.dt)
    throw std::runtime_error("the reference's dt (" + number(ref.dt) + " s) is not this run's (" + number(run.dt) + ")");
  if (ref.tip.size() < run.tip.size())
    throw std::runtime_error("the reference has " + std::to_string(ref.tip.size()) + " steps, the run " +
                             std::to_string(run.tip.size()));
  for (int d = 0; d < 3; ++d)
    if (std::abs(run.start[d] - ref.start[d]) > 1e-9)
      throw std::runtime_error("the reference's tip starts elsewhere (another bar?)");
  TipError e{0, 0, 0};
  double sum = 0;
  for (std::size_t s = 0; s < run.tip.size(); ++s) {
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += (run.tip[s][d] - ref.tip[s][d]) * (run.tip[s][d] - ref.tip[s][d]);
    const double mm = 1e3 * std::sqrt(d2);
    sum += mm * mm;
    if (!(mm <= e.max_mm)) e.max_mm = mm;  // a NaN sticks
    e.final_mm = mm;
  }
  e.rms_mm = run.tip.empty() ? 0.0 : std::sqrt(sum / double(run.tip.size()));
  return e;
}

/// The result line.
struct BarResult {
  std::string engine, precision, method, solver;
  int threads = 0;
  std::size_t particles = 0, tets = 0, constraints = 0;
  long long colors = -1;                   ///< -1: unknown
  double setup_ms = 0, ms_per_step = 0;    ///< set-up; wall clock per step
  double cpu_ms_per_step = 0;              ///< the process's CPU time per step, all threads
  double integrate_ms = -1, solve_ms = -1;  ///< per step, from the engine's own phase timers (-1: not measured)
  Point tip{};                             ///< after the last step
  double sag_mm = 0;                       ///< the tip's drop after the last step (start y − y), mm
  double mean_sag_mm = 0;                  ///< the tip's drop averaged over the steps, mm
  TipError error;                          ///< against --reference
};

inline void print_bar(const BarOptions& o, const Bar& b, const BarResult& r) {
  auto opt = [](double v) { return v < 0 ? std::string("null") : number(v); };
  std::printf(
      "{\"engine\": \"%s\", \"precision\": \"%s\", \"method\": \"%s\", \"solver\": \"%s\", \"vertices\": [%d, %d, %d], "
      "\"particles\": %zu, \"tets\": %zu, \"constraints\": %zu, \"colors\": %s, \"threads\": %d, \"steps\": %d, "
      "\"substeps\": %d, \"iterations\": %d, \"dt\": %s, \"young\": %s, \"poisson\": %s, \"stiffness\": %s, "
      "\"damping\": %s, \"setup_ms\": %s, \"ms_per_step\": %s, \"cpu_ms_per_step\": %s, \"integrate_ms\": %s, "
      "\"solve_ms\": %s, \"tip\": [%s, %s, %s], \"sag_mm\": %s, \"mean_sag_mm\": %s, \"tip_rms_mm\": %s, "
      "\"tip_final_mm\": %s, \"tip_max_mm\": %s}\n",
      r.engine.c_str(), r.precision.c_str(), r.method.c_str(), r.solver.c_str(), b.width, b.height, b.depth,
      r.particles, r.tets, r.constraints, r.colors < 0 ? "null" : std::to_string(r.colors).c_str(), r.threads,
      o.steps, o.substeps, o.iterations, number(o.dt).c_str(), number(o.young).c_str(), number(o.poisson).c_str(),
      number(o.stiffness).c_str(), number(o.damping).c_str(), number(r.setup_ms).c_str(),
      number(r.ms_per_step).c_str(), number(r.cpu_ms_per_step).c_str(), opt(r.integrate_ms).c_str(),
      opt(r.solve_ms).c_str(), number(r.tip[0]).c_str(), number(r.tip[1]).c_str(), number(r.tip[2]).c_str(),
      number(r.sag_mm).c_str(), number(r.mean_sag_mm).c_str(), opt(r.error.rms_mm).c_str(),
      opt(r.error.final_mm).c_str(), opt(r.error.max_mm).c_str());
  std::fflush(stdout);
}

/// Runs o.steps steps (step()), each timed alone; after each, outside the timed part, records the tip (tip()).
/// Fills r's timings, tip, sags and, with --reference, error; with --write-reference writes the trajectory.
inline void run_bar(const BarOptions& o, const Bar& b, BarResult& r, const std::function<void()>& step,
                    const std::function<Point()>& tip, const std::string& made_by) {
  Trajectory traj;
  traj.dt = o.dt;
  traj.start = tip();
  traj.made_by = made_by;
  traj.tip.reserve(std::size_t(o.steps));
  Trajectory ref;
  if (!o.reference.empty()) ref = read_trajectory(o.reference);  // before the run: a bad file fails at once
  double ms = 0, cpu = 0, sag = 0;
  for (int s = 0; s < o.steps; ++s) {
    const Clock::time_point t = Clock::now();
    const double c = cpu_ms();
    step();
    cpu += cpu_ms() - c;
    ms += ms_since(t);
    traj.tip.push_back(tip());
    sag += traj.start[1] - traj.tip.back()[1];
  }
  r.ms_per_step = ms / o.steps;
  r.cpu_ms_per_step = cpu / o.steps;
  r.tip = traj.tip.back();
  r.sag_mm = 1e3 * (traj.start[1] - r.tip[1]);
  r.mean_sag_mm = 1e3 * sag / o.steps;
  if (!o.reference.empty()) r.error = tip_error(traj, ref);
  if (!o.write_reference.empty()) write_trajectory(o.write_reference, traj);
  (void)b;
}

}  // namespace peer_bench
