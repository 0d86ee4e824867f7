// Cost of keeping the colors up to date when a host adds constraints between steps: coloring every constraint
// from scratch vs coloring only 1% newly added ones (first fit against the colors already at their particles,
// then laying the arrays out again). Stretch constraints of an N×N cloth plus 1% random extra pairs (double).
#include "pbd/io/generators.hpp"
#include "pbd/world.hpp"

#include <benchmark/benchmark.h>

#include <random>

namespace {

pbd::World<double> cloth(int n) {
  pbd::World<double> w;
  pbd::ClothOptions o;
  o.resolution = n;
  pbd::add_cloth(w, o, w.add_constraint_set(pbd::Stiffness::pbd_k(1.0)));
  return w;
}

void add_one_percent(pbd::World<double>& w, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<pbd::Index> pick(0, w.num_particles() - 1);
  const std::size_t extra = w.constraints<pbd::StretchConstraint<double>>().size() / 100;
  for (std::size_t k = 0; k < extra;) {
    const pbd::Index a = pick(rng), b = pick(rng);
    if (a != b) {
      w.add_stretch(a, b, 0);
      ++k;
    }
  }
}

// Full coloring of the cloth plus 1% extra constraints.
void BM_ColorEverything(benchmark::State& state) {
  pbd::World<double> base = cloth(int(state.range(0)));
  add_one_percent(base, 1);
  for (auto _ : state) {
    state.PauseTiming();
    pbd::World<double> w = base;  // a copy has no coloring yet
    state.ResumeTiming();
    benchmark::DoNotOptimize(w.num_colors());
  }
  state.counters["constraints"] = double(base.constraints<pbd::StretchConstraint<double>>().size());
}

// The cloth already colored; then 1% constraints added: only those are colored.
void BM_ColorOnePercentAdded(benchmark::State& state) {
  std::size_t constraints = 0;
  for (auto _ : state) {
    state.PauseTiming();
    pbd::World<double> w = cloth(int(state.range(0)));  // built in place, as a host would (not timed)
    w.num_colors();
    add_one_percent(w, 1);
    constraints = w.constraints<pbd::StretchConstraint<double>>().size();
    state.ResumeTiming();
    benchmark::DoNotOptimize(w.num_colors());
  }
  state.counters["constraints"] = double(constraints);
}

}  // namespace

BENCHMARK(BM_ColorEverything)->ArgName("n")->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ColorOnePercentAdded)->ArgName("n")->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
