// What tearing costs a step: a 300² cloth of fibers torn along one line of about 300 edges per step, against its
// twin whose fibers never break, stepped in turn (A B A B) so that both see the same machine at the same moment.
//
// The cloth (1 m, 1 kg, weightless) is held by its bottom and top rows, grips pulled apart at a constant speed,
// and starts in the motion of that uniform stretch, so that the vertical edges' strain grows by about the same
// amount each step everywhere. Its vertical edges are fibers; those of every other column form one constraint set
// each, whose rupture strain is a little above the previous such column's. Once the first column breaks, about
// one column of vertical edges (a line of N − 1 edges) breaks each step, and the breaks slit the cloth along the
// column (World::add_surface: the particles along a cut are copied). The other edges never break. The twin has
// the same cloth and sets, but no rupture strains.
//
// Prints, over the steps in which the torn cloth broke fibers, the ratio of its step time to the twin's step
// time in the same round (median, min–max), the fibers broken per step and the particles copied. A break's
// aftermath (new colors at the copies, free bodies found again) falls in later steps, all of which break too.
#include "pbd/world.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using World = pbd::World<double>;
using pbd::Index;

struct Options {
  int n = 300;            // particles per side
  int steps = 60;         // steps of each world (the first, which colors both, is left out of the figures)
  int substeps = 10;
  int iterations = 4;
  double speed = 0.3;     // m/s of the top row away from the bottom row
};

// One step's strain growth: the rows' relative speed times dt over the cloth's 1 m height.
double strain_per_step(const Options& o) { return o.speed / 60.0; }

// The first rupture strain, and the rupture strains' spacing from column to column in steps of strain growth: a
// column breaks over a few steps (at 4 sweeps the solve leaves every other fiber of a column more stretched than
// the next), so columns a little closer than one step apart make about one line of edges break per step.
constexpr double kFirstRupture = 0.02;
constexpr double kSpacing = 0.75;

World cloth(const Options& o, bool tears) {
  World w;
  const int n = o.n;
  const double h = 1.0 / (n - 1);
  const double mass = 1.0 / (double(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const bool bottom = i == 0, top = i == n - 1;
      // Every particle starts at the speed of a uniform stretch, which the grips then keep up: no wave runs
      // from the grips, and the strain is the same along each column from the first step on.
      w.add_particle({j * h, i * h, 0.0}, bottom || top ? World::kPinned : mass, {0.0, o.speed * (i * h - 0.5), 0.0});
    }
  // The horizontal edges are stretch constraints, which also push: they keep the cloth's width (its diagonal
  // fibers, pulled, would draw the columns together), so that the columns are pulled alike.
  const Index held = w.add_constraint_set(pbd::Stiffness::pbd_k(1.0));
  pbd::Material strong;
  strong.stiffness = 100.0;
  // One set per breakable column (the odd ones), their rupture strains growing left to right.
  const Index lasting = w.add_constraint_set(pbd::Stiffness::fiber(strong));
  std::vector<Index> column_set(std::size_t(n), lasting);
  int k = 0;
  for (int j = 1; j < n; j += 2, ++k) {
    pbd::Material m = strong;
    if (tears) m.rupture_strain = kFirstRupture + k * kSpacing * strain_per_step(o);
    column_set[std::size_t(j)] = w.add_constraint_set(pbd::Stiffness::fiber(m));
  }
  auto at = [n](int i, int j) { return Index(i * n + j); };
  std::vector<std::array<Index, 3>> triangles;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      triangles.push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (j + 1 < n) w.add_stretch(at(i, j), at(i, j + 1), held);
      if (i + 1 < n) w.add_fiber(at(i, j), at(i + 1, j), column_set[std::size_t(j)]);
      if (i + 1 < n && j + 1 < n) w.add_fiber(at(i, j + 1), at(i + 1, j), lasting);
    }
  w.add_surface(triangles);
  pbd::StepParams<double> p;
  p.substeps = o.substeps;
  p.iterations = o.iterations;
  p.gravity = {0.0, 0.0, 0.0};
  w.set_params(p);
  return w;
}

double seconds_of_step(World& w) {
  const auto t0 = std::chrono::steady_clock::now();
  w.step();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Spread {
  double median, min, max;
};

Spread spread(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  const double median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
  return {median, v.front(), v.back()};
}

int usage(const char* self) {
  std::fprintf(stderr, "usage: %s [--n N] [--steps S] [--substeps K] [--iterations I]\n", self);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string key = argv[a];
    if (a + 1 >= argc) return usage(argv[0]);
    const int value = std::atoi(argv[++a]);
    if (value < 1) return usage(argv[0]);
    if (key == "--n") o.n = std::max(value, 4);
    else if (key == "--steps") o.steps = value;
    else if (key == "--substeps") o.substeps = value;
    else if (key == "--iterations") o.iterations = value;
    else return usage(argv[0]);
  }
  World torn = cloth(o, true), twin = cloth(o, false);
  std::vector<double> ratios, torn_s, twin_s, quiet_ratios;
  std::vector<double> broken;
  std::size_t copies = 0;
  for (int s = 0; s < o.steps; ++s) {
    // Alternate which world goes first, so that neither always follows the other's cache state.
    double a, b;
    if (s % 2) {
      b = seconds_of_step(twin);
      a = seconds_of_step(torn);
    } else {
      a = seconds_of_step(torn);
      b = seconds_of_step(twin);
    }
    const std::size_t breaks = torn.last_breaks().size();
    copies += torn.last_copies().size();
    if (s == 0) continue;  // the first step colors both: not a step a run repeats
    if (breaks == 0) {
      quiet_ratios.push_back(a / b);
      continue;
    }
    ratios.push_back(a / b);
    torn_s.push_back(a);
    twin_s.push_back(b);
    broken.push_back(double(breaks));
    std::fprintf(stderr, "step %d: %zu fibers broke, %.1f ms against %.1f ms\n", s + 1, breaks, 1e3 * a, 1e3 * b);
  }
  std::printf("cloth %d², %d steps of %d sub-steps × %d sweeps, each world stepped in turn\n", o.n, o.steps,
              o.substeps, o.iterations);
  if (ratios.empty()) {
    std::printf("no fibers broke: run more steps\n");
    return 1;
  }
  const Spread r = spread(ratios), q = quiet_ratios.empty() ? Spread{0, 0, 0} : spread(quiet_ratios);
  const Spread f = spread(broken), ta = spread(torn_s), tb = spread(twin_s);
  std::printf("steps with breaks: %zu; fibers broken per step: median %.0f (%.0f–%.0f); particles copied: %zu\n",
              ratios.size(), f.median, f.min, f.max, copies);
  std::printf("step time, tearing / not tearing: median %.3f (%.3f–%.3f)\n", r.median, r.min, r.max);
  std::printf("  tearing %.1f ms (%.1f–%.1f), its twin %.1f ms (%.1f–%.1f)\n", 1e3 * ta.median, 1e3 * ta.min,
              1e3 * ta.max, 1e3 * tb.median, 1e3 * tb.min, 1e3 * tb.max);
  if (!quiet_ratios.empty())
    std::printf("steps before the first break: %zu, ratio median %.3f (%.3f–%.3f)\n", quiet_ratios.size(), q.median,
                q.min, q.max);
  return 0;
}
