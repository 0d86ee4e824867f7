// ns per constraint projection per sweep: serial reference, colored Gauss-Seidel and Jacobi on 1 and 2 threads,
// over the stretch constraints of an N×N hanging cloth (float). Positions are perturbed so every projection works.
// One benchmark iteration is one sub-step's solve as World::step runs it: λ reset (begin_substep), kSweeps sweeps,
// and end_substep (which may copy positions back from the solver's padded copy). Counter ns_per_projection = wall
// time of one iteration / (constraints × kSweeps) (medians: use --benchmark_repetitions).
#include "cloth_fixture.hpp"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <vector>

namespace {

using pbd::bench::ClothFixture;
using pbd::bench::kSweeps;
using pbd::bench::Real;

void set_counters(benchmark::State& state, const ClothFixture& f, std::size_t colors) {
  state.counters["ns_per_projection"] = benchmark::Counter(
      double(f.constraints()) * kSweeps * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["constraints"] = double(f.constraints());
  state.counters["colors"] = double(colors);
}

void BM_SerialSweep(benchmark::State& state) {
  ClothFixture f(int(state.range(0)));
  pbd::Multipliers<Real> lambda;
  for (auto _ : state) {
    pbd::bench::serial_substep(f, lambda);
    benchmark::ClobberMemory();
  }
  set_counters(state, f, 0);
}

// Colored Gauss-Seidel (jacobi = false) or Jacobi (true) in an arena of `threads` threads; `config` decides which
// colors fork (default: those of at least 1024 constraints).
void colored_sweep(benchmark::State& state, bool jacobi, const pbd::ParallelConfig& config = {}) {
  ClothFixture f(int(state.range(0)));
  const int threads = int(state.range(1));
  pbd::ColoredSolver<Real> solver;
  pbd::CustomTypes<Real> custom;
  solver.build(f.world.constraints(), pbd::VectorX<Real>(f.world.inverse_masses()), {}, custom);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto _ : state) {
      pbd::bench::colored_substep(f, solver, custom, jacobi, config);
      benchmark::ClobberMemory();
    }
  });
  set_counters(state, f, solver.constraints().num_colors());
  state.counters["threads"] = threads;
}

void BM_ColoredSweep(benchmark::State& state) { colored_sweep(state, false); }
void BM_JacobiSweep(benchmark::State& state) { colored_sweep(state, true); }
// Every color forks, however small: shows what the fork/join per color costs on small cloths (compare with
// BM_ColoredSweep at the same size, where small colors run inline).
void BM_ColoredSweepAlwaysFork(benchmark::State& state) { colored_sweep(state, false, pbd::ParallelConfig{0, 16}); }

// The machine's memory ceiling for the largest cloth: a[i] = 0.999·a[i] + b[i] over two 64 MB arrays (larger than
// L2, like the 1000² cloth's ~90 MB), split evenly over 1 or 2 threads. bytes_per_second counts reads + writes; its 2T/1T
// ratio bounds what any sweep that streams through memory can gain from the second core.
void BM_StreamTriad(benchmark::State& state) {
  const std::size_t n = std::size_t(16) << 20;
  std::vector<float> a(n, 1.0f), b(n, 2.0f);
  const int threads = int(state.range(0));
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto _ : state) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, n / std::size_t(threads)),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) a[i] = 0.999f * a[i] + b[i];
                        }, tbb::static_partitioner());
      benchmark::ClobberMemory();
    }
  });
  state.SetBytesProcessed(std::int64_t(state.iterations()) * 3 * std::int64_t(n * sizeof(float)));
  state.counters["threads"] = threads;
}

}  // namespace

BENCHMARK(BM_SerialSweep)->ArgName("n")->Arg(30)->Arg(100)->Arg(300)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSweep)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100, 300, 1000}, {1, 2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSweepAlwaysFork)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100}, {2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_JacobiSweep)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100, 300, 1000}, {1, 2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StreamTriad)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
