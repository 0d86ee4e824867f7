#pragma once
// What both bench/peer drivers share (standard library only: the peer's driver includes it too): the cloth file of
// make_cloth.py, the command line, the stretch error and the one line of JSON they print.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <time.h>

namespace peer_bench {

/// The cloth as make_cloth.py writes it (the peer's ClothDemo mesh, in the peer's order).
struct Cloth {
  int n = 0;
  double width = 0, height = 0;
  std::vector<std::array<double, 3>> x;         ///< vertex positions, m
  double mass = 1;                              ///< every vertex's mass before the pins, kg
  std::vector<unsigned> pinned;                 ///< vertices of mass 0
  std::vector<std::array<unsigned, 3>> tris;    ///< triangles
  std::vector<std::array<unsigned, 2>> edges;   ///< distance constraints, in the peer's order
  std::vector<std::array<unsigned, 4>> quads;   ///< dihedral constraints (opposite p0, opposite p1, edge e0, e1)
};

/// A keyword-tagged text file of this directory's formats ("<magic> 1", then "keyword value ..." and counted lists),
/// with its '#' comment lines dropped; every error names the file.
struct KeywordFile {
  std::string path;       ///< the file, for messages
  std::stringstream text;  ///< its content without comment lines: read the values with >>
  /// Opens `file` and checks its first words are "<magic> 1".
  KeywordFile(const std::string& file, const char* magic) : path(file) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    for (std::string line; std::getline(in, line);)
      if (line.empty() || line[0] != '#') text << line << '\n';
    expect(magic);
    int version = 0;
    text >> version;
    if (version != 1) throw std::runtime_error(path + ": unknown version");
  }
  /// The next word must be `word`.
  void expect(const char* word) {
    std::string w;
    if (!(text >> w) || w != word) throw std::runtime_error(path + ": expected '" + word + "', found '" + w + "'");
  }
  /// `word`, then a count ≥ 0.
  std::size_t count(const char* word) {
    expect(word);
    long long k = -1;
    if (!(text >> k) || k < 0) throw std::runtime_error(path + ": bad count after '" + word + "'");
    return std::size_t(k);
  }
};

inline Cloth read_cloth(const std::string& path) {
  KeywordFile f(path, "pbd_peer_cloth");
  std::stringstream& text = f.text;
  auto expect = [&](const char* word) { f.expect(word); };
  auto count = [&](const char* word) { return f.count(word); };
  Cloth c;
  expect("n");
  text >> c.n;
  expect("width");
  text >> c.width;
  expect("height");
  text >> c.height;
  c.x.resize(count("vertices"));
  for (auto& p : c.x) text >> p[0] >> p[1] >> p[2];
  expect("mass");
  text >> c.mass;
  c.pinned.resize(count("pinned"));
  for (auto& i : c.pinned) text >> i;
  c.tris.resize(count("triangles"));
  for (auto& t : c.tris) text >> t[0] >> t[1] >> t[2];
  c.edges.resize(count("edges"));
  for (auto& e : c.edges) text >> e[0] >> e[1];
  c.quads.resize(count("bending"));
  for (auto& q : c.quads) text >> q[0] >> q[1] >> q[2] >> q[3];
  if (!text) throw std::runtime_error(path + ": truncated or malformed");
  const std::size_t nv = c.x.size();
  auto check = [&](unsigned i) {
    if (i >= nv) throw std::runtime_error(path + ": vertex index " + std::to_string(i) + " out of range");
  };
  for (unsigned i : c.pinned) check(i);
  for (auto& t : c.tris) for (unsigned i : t) check(i);
  for (auto& e : c.edges) for (unsigned i : e) check(i);
  for (auto& q : c.quads) for (unsigned i : q) check(i);
  return c;
}

/// The drivers' command line (the same for both engines).
struct Options {
  std::string mesh;             ///< make_cloth.py's file (required)
  int steps = 200;              ///< steps timed
  int substeps = 1;             ///< sub-steps per step
  int iterations = 10;          ///< sweeps per sub-step
  int threads = 0;              ///< 0: the engine's default
  bool use_double = false;      ///< pbd: World<double> (the peer is always double)
  std::string solver;           ///< pbd only; empty: the driver's default
  double dt = 1.0 / 60.0;       ///< step, s
  double k_distance = 1.0;      ///< PBD stiffness of the distance constraints
  double k_bending = 0.01;      ///< PBD stiffness of the dihedral constraints
  bool average = false;         ///< also measure the stretch after every step (untimed) and report its mean
  bool tethers = false;         ///< pbd only: long-range attachments to the pins (World::add_tethers, defaults)
  bool hierarchy = false;       ///< pbd only: hierarchical PBD (StepParams::hierarchy, defaults)
};

/// Reads a driver's command line one option at a time (both drivers of the cloth and of the bar): the option, then
/// its value as text, an integer ≥ lo or a finite real ≥ 0. A missing value prints the usage and says so, a bad one
/// says so; both exit with status 2, as fail() and an unknown option do.
class ArgReader {
public:
  ArgReader(int argc, char** argv, std::function<void()> usage) : argc_(argc), argv_(argv), usage_(std::move(usage)) {}

  /// Moves to the next option; false when there is none.
  bool next() {
    if (++i_ >= argc_) return false;
    option_ = argv_[i_];
    return true;
  }
  const std::string& option() const { return option_; }

  std::string value() {
    if (i_ + 1 >= argc_) fail(option_ + " needs a value");
    return argv_[++i_];
  }
  int integer(int lo) {
    const std::string v = value();
    char* end = nullptr;
    const long r = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end || r < lo || r > 100000000) bad(v);
    return int(r);
  }
  double real() {
    const std::string v = value();
    char* end = nullptr;
    const double r = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(r >= 0) || !std::isfinite(r)) bad(v);
    return r;
  }

  /// Prints the usage and `what`, and exits with status 2.
  [[noreturn]] void fail(const std::string& what) {
    usage_();
    std::fprintf(stderr, "%s: %s\n", argv_[0], what.c_str());
    std::exit(2);
  }
  [[noreturn]] void unknown() { fail("unknown option '" + option_ + "'"); }
  [[noreturn]] void help() {
    usage_();
    std::exit(0);
  }

private:
  [[noreturn]] void bad(const std::string& v) {
    std::fprintf(stderr, "%s: %s: bad value '%s'\n", argv_[0], option_.c_str(), v.c_str());
    std::exit(2);
  }
  int argc_;
  char** argv_;
  std::function<void()> usage_;
  int i_ = 0;
  std::string option_;
};

/// The options every driver takes (--mesh, --steps, --substeps, --iterations, --threads, --double, --solver, --dt),
/// into any options struct with those members; false when r.option() is none of them.
template <class O> bool read_run_option(ArgReader& r, O& o) {
  const std::string& a = r.option();
  if (a == "--mesh") o.mesh = r.value();
  else if (a == "--steps") o.steps = r.integer(1);
  else if (a == "--substeps") o.substeps = r.integer(1);
  else if (a == "--iterations") o.iterations = r.integer(1);
  else if (a == "--threads") o.threads = r.integer(1);
  else if (a == "--double") o.use_double = true;
  else if (a == "--solver") o.solver = r.value();
  else if (a == "--dt") o.dt = r.real();
  else return false;
  return true;
}

inline void usage(const char* prog, const char* extra) {
  std::fprintf(stderr,
               "usage: %s --mesh FILE [--steps S=200] [--substeps 1] [--iterations 10] [--threads T] [--double]\n"
               "          [--solver NAME] [--dt 1/60] [--k-distance 1] [--k-bending 0.01] [--average-error]\n"
               "          [--tethers] [--hierarchy]\n%s",
               prog, extra);
}

inline Options parse(int argc, char** argv, const char* extra_help) {
  Options o;
  ArgReader r(argc, argv, [&] { usage(argv[0], extra_help); });
  while (r.next()) {
    const std::string& a = r.option();
    if (read_run_option(r, o)) continue;
    if (a == "--k-distance") o.k_distance = r.real();
    else if (a == "--k-bending") o.k_bending = r.real();
    else if (a == "--average-error") o.average = true;
    else if (a == "--tethers") o.tethers = true;
    else if (a == "--hierarchy") o.hierarchy = true;
    else if (a == "-h" || a == "--help") r.help();
    else r.unknown();
  }
  if (o.mesh.empty()) r.fail("--mesh is required (bench/peer/make_cloth.py writes it)");
  if (!(o.dt > 0)) r.fail("--dt must be > 0");
  return o;
}

/// RMS and max over the distance edges of |(|xi − xj| − L) / L|, L the rest length in the file's positions;
/// position(i) gives particle i's final position (in double).
struct Stretch {
  double rms = 0, max = 0;
};
inline Stretch stretch(const Cloth& c, const std::function<std::array<double, 3>(unsigned)>& position) {
  auto dist = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  };
  Stretch s;
  double sum = 0;
  for (const auto& e : c.edges) {
    const double L = dist(c.x[e[0]], c.x[e[1]]);
    const double r = std::abs((dist(position(e[0]), position(e[1])) - L) / L);
    sum += r * r;
    if (!(r <= s.max)) s.max = r;  // a NaN sticks
  }
  s.rms = c.edges.empty() ? 0.0 : std::sqrt(sum / double(c.edges.size()));
  return s;
}

/// A JSON number (null when not finite: the line stays valid JSON and run_ab sees the failure).
inline std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

/// The result line: engine, precision, solver, counts, timings, error.
struct Result {
  std::string engine, precision, solver;
  int threads = 0;
  std::size_t particles = 0, distance = 0, bending = 0;
  long long colors = -1;  ///< -1: unknown
  double setup_ms = 0, ms_per_step = 0;
  double cpu_ms_per_step = 0;  ///< the process's CPU time per step, all threads (robust to other processes on 1 thread)
  double integrate_ms = -1, solve_ms = -1;  ///< per step, from the engine's own phase timers (-1: not measured)
  double wait_ms = -1;     ///< per step: of solve_ms, the sweeps' threads waiting for one another (-1: not measured)
  int shared_steps = -1;   ///< steps whose sweeps ran on more than one thread (-1: not measured)
  Stretch error;           ///< after the last step
  double rms_mean = -1;    ///< --average-error: the RMS stretch after each step, averaged over the steps (-1: not)
};

inline void print(const Options& o, const Cloth& c, const Result& r) {
  std::printf(
      "{\"engine\": \"%s\", \"precision\": \"%s\", \"solver\": \"%s\", \"n\": %d, \"particles\": %zu, "
      "\"distance\": %zu, \"bending\": %zu, \"colors\": %s, \"threads\": %d, \"steps\": %d, \"substeps\": %d, "
      "\"iterations\": %d, \"dt\": %s, \"k_distance\": %s, \"k_bending\": %s, \"setup_ms\": %s, "
      "\"ms_per_step\": %s, \"cpu_ms_per_step\": %s, \"integrate_ms\": %s, \"solve_ms\": %s, \"wait_ms\": %s, \"shared_steps\": %s, "
      "\"stretch_rms\": %s, \"stretch_max\": %s, \"stretch_rms_mean\": %s}\n",
      r.engine.c_str(), r.precision.c_str(), r.solver.c_str(), c.n, r.particles, r.distance, r.bending,
      r.colors < 0 ? "null" : std::to_string(r.colors).c_str(), r.threads, o.steps, o.substeps, o.iterations,
      number(o.dt).c_str(), number(o.k_distance).c_str(), number(o.k_bending).c_str(), number(r.setup_ms).c_str(),
      number(r.ms_per_step).c_str(), number(r.cpu_ms_per_step).c_str(), r.integrate_ms < 0 ? "null" : number(r.integrate_ms).c_str(),
      r.solve_ms < 0 ? "null" : number(r.solve_ms).c_str(), r.wait_ms < 0 ? "null" : number(r.wait_ms).c_str(),
      r.shared_steps < 0 ? "null" : std::to_string(r.shared_steps).c_str(), number(r.error.rms).c_str(),
      number(r.error.max).c_str(), r.rms_mean < 0 ? "null" : number(r.rms_mean).c_str());
  std::fflush(stdout);
}

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The process's CPU time (all its threads), ms.
inline double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

/// Runs o.steps steps (step(s)) and returns the ms per step; r.cpu_ms_per_step gets the CPU time per step. With
/// --average-error, `measure` (the RMS stretch of the current positions) runs after every step, outside the timed
/// part, and r.rms_mean gets its mean: each step is timed alone, so the figures are the steps' time either way.
inline double timed_steps(const Options& o, Result& r, const std::function<void(int)>& step,
                          const std::function<double()>& measure) {
  double ms = 0, cpu = 0, sum = 0;
  for (int s = 0; s < o.steps; ++s) {
    const Clock::time_point t = Clock::now();
    const double c = cpu_ms();
    step(s);
    cpu += cpu_ms() - c;
    ms += ms_since(t);
    if (o.average) sum += measure();
  }
  if (o.average) r.rms_mean = sum / o.steps;
  r.cpu_ms_per_step = cpu / o.steps;
  return ms / o.steps;
}

}  // namespace peer_bench
