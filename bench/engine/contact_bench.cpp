// Whole steps of an N×N cloth with self-collision draped over a sphere onto the ground (stretch k = 1, bending
// k = 0.2, 10 iterations, one sub-step of 1/60 s, particles of radius half the rest edge, margin a fifth of an
// edge): the step's time and the share of it spent in the broad phase and contact generation
// (StepStats::seconds_collisions), per size, so that the cost per particle can be compared across sizes.
// The cloth is first stepped 45 times (it reaches the sphere and folds); each benchmark iteration is one step.
// The finer cloths fold into more layers (more particle contacts per particle), so their cost per particle is not a
// test of linearity; BM_GrainLatticeStep is: a lattice of side × side × 4 grains (radius 5 mm, 2.1 radii apart,
// jittered by 0.02 radii) resting on a floor inside four walls, one self-colliding body, stepped the same way and
// first 5 times; every grain has the same neighbourhood at every size (4 layers deep at each), so a broad phase
// linear in the particle count costs the same per grain.
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/world.hpp"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

namespace {

using Real = float;
using namespace pbd;

World<Real> draped_cloth(int n) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.2));
  MeshBodyOptions o;
  o.origin = {-0.5, -0.35, 0.9};
  add_mesh(w, grid_mesh(n, 1.0), o, sets);
  const double edge = 1.0 / (n - 1);
  const ContactMaterial<Real> cloth{Real(0.3), Real(0.2), Real(0)};
  w.add_contact_body({0, w.num_particles(), Real(0.5 * edge), cloth, true});
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0), cloth);
  w.add_sphere(Vec3<Real>(0, 0, Real(0.3)), Real(0.3), cloth);
  StepParams<Real> p;
  p.solver = Solver::colored;
  p.iterations = 10;
  p.substeps = 1;
  p.collision_margin = Real(0.2 * edge);
  w.set_params(p);
  for (int i = 0; i < 45; ++i) w.step();
  return w;
}

// Steps w once per benchmark iteration; counters: the share of the step and the ns per particle spent in the broad
// phase and contact generation, the step's ns per particle, and the particle and collider contacts per particle.
void measure(benchmark::State& state, tbb::task_arena& arena, World<Real>& w) {
  double total = 0, broad = 0;
  std::size_t contacts = 0, colls = 0;
  for (auto _ : state) {
    arena.execute([&] { w.step(); });
    total += w.last_step_stats().seconds;
    broad += w.last_step_stats().seconds_collisions;
    contacts += w.last_particle_contacts().size();
    colls += w.last_collisions().size();
  }
  const double steps = double(state.iterations()), n = double(w.num_particles());
  state.counters["broad_phase_share"] = broad / total;
  state.counters["broad_phase_ns_per_particle"] = 1e9 * broad / steps / n;
  state.counters["step_ns_per_particle"] = 1e9 * total / steps / n;
  state.counters["particle_contacts_per_particle"] = double(contacts) / steps / n;
  state.counters["collider_contacts_per_particle"] = double(colls) / steps / n;
}

void BM_SelfCollidingClothStep(benchmark::State& state) {
  const int n = int(state.range(0)), threads = int(state.range(1));
  tbb::task_arena arena(threads);
  World<Real> w = arena.execute([&] { return draped_cloth(n); });
  measure(state, arena, w);
}

// One world stepped on 1 thread against an equal one on 2, paired step by step (the order alternating), beside the
// same run's ceiling: two more pairs of cloths, each pair stepped one after the other on one thread, or at once, one
// cloth per thread, each in an arena of its own (shared nothing). Counters: the broad phase's share at 1 and 2
// threads, the 2T/1T speed-ups of the broad phase and of the step (medians of the paired ratios), and the ceiling's.
// The solver's bits do not depend on the thread count, so the two worlds must stay bitwise equal; checked at the end.
void BM_SelfCollidingClothScaling(benchmark::State& state) {
  const int n = int(state.range(0));
  tbb::task_arena one(1), two(2), own[2] = {tbb::task_arena(1), tbb::task_arena(1)};
  World<Real> w[2] = {one.execute([&] { return draped_cloth(n); }), two.execute([&] { return draped_cloth(n); })};
  World<Real> apart[4] = {draped_cloth(n), draped_cloth(n), draped_cloth(n), draped_cloth(n)};
  using clock = std::chrono::steady_clock;
  auto seconds = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  std::vector<double> broad_speedup, step_speedup, ceiling;
  double total[2] = {0, 0}, broad[2] = {0, 0};
  int turn = 0;
  for (auto _ : state) {
    double step[2], collide[2];
    for (int k = 0; k < 2; ++k) {
      const int t = (k + turn) & 1;  // 1 then 2 threads, then 2 then 1
      (t == 0 ? one : two).execute([&] { w[t].step(); });
      step[t] = w[t].last_step_stats().seconds;
      collide[t] = w[t].last_step_stats().seconds_collisions;
      total[t] += step[t];
      broad[t] += collide[t];
    }
    double serial = 0, both = 0;
    for (int k = 0; k < 2; ++k) {
      if (((k + turn) & 1) == 0) {
        const auto a = clock::now();
        own[0].execute([&] {
          apart[0].step();
          apart[1].step();
        });
        serial = seconds(a, clock::now());
      } else {
        const auto a = clock::now();
        std::thread other([&] { own[1].execute([&] { apart[3].step(); }); });
        own[0].execute([&] { apart[2].step(); });
        other.join();
        both = seconds(a, clock::now());
      }
    }
    turn ^= 1;
    broad_speedup.push_back(collide[0] / collide[1]);
    step_speedup.push_back(step[0] / step[1]);
    ceiling.push_back(serial / both);
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  if (w[0].positions() != w[1].positions()) state.SkipWithError("1-thread and 2-thread positions differ");
  state.counters["broad_phase_share_1T"] = broad[0] / total[0];
  state.counters["broad_phase_share_2T"] = broad[1] / total[1];
  state.counters["broad_phase_speedup"] = median(broad_speedup);
  state.counters["step_speedup"] = median(step_speedup);
  state.counters["shared_nothing_speedup"] = median(ceiling);
}

World<Real> grain_lattice(int side) {
  World<Real> w;
  const double r = 0.005, spacing = 2.1 * r, half = 0.5 * side * spacing + 0.05 * r;
  std::uint64_t state = 1;
  auto jitter = [&] {  // splitmix64, in [-0.01, 0.01] r
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double((z ^ (z >> 31)) >> 11) / double(1ull << 53) - 0.5) * 0.02 * r;
  };
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        w.add_particle(Vec3<Real>(Real((i + 0.5) * spacing - 0.5 * side * spacing + jitter()),
                                  Real((j + 0.5) * spacing - 0.5 * side * spacing + jitter()),
                                  Real(r + k * spacing + 0.02 * r + jitter())),
                       Real(0.001));
  const ContactMaterial<Real> rough{Real(0.4), Real(0.3), Real(0)};
  w.add_contact_body({0, w.num_particles(), Real(r), rough, true});
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0), rough);
  w.add_plane(Vec3<Real>(1, 0, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(-1, 0, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(0, 1, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(0, -1, 0), Real(-half), rough);
  StepParams<Real> p;
  p.solver = Solver::colored;
  p.iterations = 10;
  p.substeps = 1;
  p.collision_margin = Real(0.2 * r);
  w.set_params(p);
  for (int i = 0; i < 5; ++i) w.step();
  return w;
}

void BM_GrainLatticeStep(benchmark::State& state) {
  const int side = int(state.range(0)), threads = int(state.range(1));
  tbb::task_arena arena(threads);
  World<Real> w = arena.execute([&] { return grain_lattice(side); });
  measure(state, arena, w);
}

}  // namespace

// A fixed number of steps per run (about a second on this machine), so that two builds compared see the same states.
BENCHMARK(BM_GrainLatticeStep)->ArgNames({"side", "threads"})->ArgsProduct({{32}, {1, 2}})->Iterations(160)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GrainLatticeStep)->ArgNames({"side", "threads"})->ArgsProduct({{64}, {1, 2}})->Iterations(80)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GrainLatticeStep)->ArgNames({"side", "threads"})->ArgsProduct({{128}, {1, 2}})->Iterations(20)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelfCollidingClothStep)->ArgNames({"n", "threads"})->ArgsProduct({{30}, {1, 2}})->Iterations(1000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelfCollidingClothStep)->ArgNames({"n", "threads"})->ArgsProduct({{100}, {1, 2}})->Iterations(120)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelfCollidingClothStep)->ArgNames({"n", "threads"})->ArgsProduct({{300}, {1, 2}})->Iterations(8)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelfCollidingClothScaling)->ArgNames({"n"})->Arg(100)->Iterations(120)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
