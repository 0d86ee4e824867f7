// Whole steps of an N×N cloth with self-collision draped over a sphere onto the ground (stretch k = 1, bending
// k = 0.2, 10 iterations, one sub-step of 1/60 s, particles of radius half the rest edge, margin a fifth of an
// edge): the step's time and the share of it spent in the broad phase and contact generation
// (StepStats::seconds_collisions), per size, so that the cost per particle can be compared across sizes.
// The cloth is first stepped 45 times (it reaches the sphere and folds); each benchmark iteration is one step.
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/world.hpp"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/task_arena.h>

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

void BM_SelfCollidingClothStep(benchmark::State& state) {
  const int n = int(state.range(0)), threads = int(state.range(1));
  tbb::task_arena arena(threads);
  World<Real> w = arena.execute([&] { return draped_cloth(n); });
  double total = 0, broad = 0;
  std::size_t contacts = 0;
  for (auto _ : state) {
    arena.execute([&] { w.step(); });
    total += w.last_step_stats().seconds;
    broad += w.last_step_stats().seconds_collisions;
    contacts += w.last_step_stats().collisions;
  }
  const double steps = double(state.iterations());
  state.counters["broad_phase_share"] = broad / total;
  state.counters["broad_phase_ns_per_particle"] = 1e9 * broad / steps / double(w.num_particles());
  state.counters["step_ns_per_particle"] = 1e9 * total / steps / double(w.num_particles());
  state.counters["contacts"] = double(contacts) / steps;
}

}  // namespace

BENCHMARK(BM_SelfCollidingClothStep)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100, 300}, {1, 2}})
    ->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_MAIN();
