// ns per constraint projection per sweep: serial reference, colored Gauss-Seidel and Jacobi on 1 and 2 threads,
// over the stretch constraints of an N×N hanging cloth (float). Positions are perturbed so every projection works.
// One benchmark iteration is one sub-step's solve as World::step runs it: λ reset , kSweeps sweeps,
// and the end of the sub-step (which may copy positions back from the padded copy). Counter ns_per_projection = wall
// time of one iteration / (constraints × kSweeps) (medians: use --benchmark_repetitions). BM_ColoredScaling,
// BM_SharedNothingScaling, BM_SharedNothingHalvesScaling and BM_ComputeScaling measure 2T vs 1T paired, sub-step
// by sub-step (see paired_scaling).
#include "cloth_fixture.hpp"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
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
  ClothFixture f(int(state.range(0)), pbd::Solver::serial);
  for (auto _ : state) {
    f.substep();
    benchmark::ClobberMemory();
  }
  set_counters(state, f, 0);
}

// Colored Gauss-Seidel (jacobi = false) or Jacobi (true) in an arena of `threads` threads; `config` decides which
// colors fork (default: those of at least 1024 constraints).
void colored_sweep(benchmark::State& state, bool jacobi, const pbd::ParallelConfig& config = {},
                   bool bending = false) {
  ClothFixture f(int(state.range(0)), jacobi ? pbd::Solver::jacobi : pbd::Solver::colored, bending);
  const int threads = int(state.range(1));
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto _ : state) {
      f.substep(config);
      benchmark::ClobberMemory();
    }
  });
  set_counters(state, f, f.colors());
  state.counters["threads"] = threads;
}

void BM_ColoredSweep(benchmark::State& state) { colored_sweep(state, false); }
// The same on the cloth with dihedral bending (range(2) = 1).
void BM_ColoredSweepBending(benchmark::State& state) { colored_sweep(state, false, {}, true); }

// Block Gauss-Seidel (BlockOptions' default blocks) in an arena of `threads` threads; range(2) = 1: with bending.
void BM_BlockSweep(benchmark::State& state) {
  ClothFixture f(int(state.range(0)), pbd::Solver::block, state.range(2) != 0);
  tbb::task_arena arena(int(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      f.substep();
      benchmark::ClobberMemory();
    }
  });
  set_counters(state, f, f.colors());
  state.counters["threads"] = double(state.range(1));
  state.counters["blocks"] = double(f.blocks());
}
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

// Paired 2T/1T measurement: each benchmark iteration times one unit of work in a 1-thread arena, then the same work
// in a 2-thread arena, so both halves of a pair see the same minute of this shared machine. Counters: median ms of
// each, and `speedup` = median over pairs of t1/t2 (noise slower than a pair cancels; faster noise does not).
template <class Work> void paired_scaling(benchmark::State& state, Work&& work, double projections = 0) {
  tbb::task_arena one(1), two(2);
  std::vector<double> t1, t2, ratio;
  auto timed = [&](tbb::task_arena& arena, int slot) {
    double ms = 0;
    arena.execute([&] {
      std::atomic<int> arrived{0};
      const int expected = arena.max_concurrency();
      // Untimed: wait (≤ 50 ms) until every thread of the arena has arrived, so the timed work starts with them all
      // awake (a worker that went to sleep during the other run can take milliseconds to come back on this VM).
      tbb::parallel_for(0, 2, [&](int) {
        ++arrived;
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
        while (arrived.load() < expected && std::chrono::steady_clock::now() < until) {
        }
      }, tbb::static_partitioner());
      const auto start = std::chrono::steady_clock::now();
      work(slot);
      ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    });
    return ms;
  };
  for (auto _ : state) {
    t1.push_back(timed(one, 0));
    t2.push_back(timed(two, 1));
    ratio.push_back(t1.back() / t2.back());
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  state.counters["ms_1T"] = median(t1);
  state.counters["ms_2T"] = median(t2);
  state.counters["speedup"] = median(ratio);
  if (projections > 0) {  // ns per projection per sweep, `projections` per unit of work
    state.counters["ns_1T"] = median(t1) * 1e6 / projections;
    state.counters["ns_2T"] = median(t2) * 1e6 / projections;
  }
}

// Sub-steps of `solver`, 1 thread against 2, paired: two identical cloths, one per thread count. The solver's bits
// do not depend on the thread count, so the two cloths must stay bitwise equal; checked at the end.
void solver_scaling(benchmark::State& state, pbd::Solver solver, bool bending = false, std::size_t per_block = 0) {
  const int n = int(state.range(0));
  ClothFixture f[2] = {ClothFixture(n, solver, bending, per_block), ClothFixture(n, solver, bending, per_block)};
  paired_scaling(
      state,
      [&](int k) {
        f[k].substep();
        benchmark::ClobberMemory();
      },
      double(f[0].constraints()) * kSweeps);
  if (std::memcmp(f[0].p().data(), f[1].p().data(), sizeof(Real) * std::size_t(f[0].p().size())) != 0)
    state.SkipWithError("1-thread and 2-thread positions differ");
  state.counters["constraints"] = double(f[0].constraints());
  if (solver == pbd::Solver::block) state.counters["blocks"] = double(f[0].blocks());
}

// Colored Gauss-Seidel.
void BM_ColoredScaling(benchmark::State& state) { solver_scaling(state, pbd::Solver::colored); }
// Block Gauss-Seidel; range(1) = 1: with bending; range(2): constraints per block (0: the default).
void BM_BlockScaling(benchmark::State& state) {
  solver_scaling(state, pbd::Solver::block, state.range(1) != 0, std::size_t(state.range(2)));
}

// Two threads that share nothing: a unit of work is one sub-step of each of two independent cloths of side `side`,
// both on one thread, or one per thread at once (every color inline, so no fork, no join, no particle shared).
// Paired like BM_ColoredScaling; what it loses against 2× is what the two cores cost each other (shared cache and
// memory) and how unequal their speeds are at that moment.
void shared_nothing_scaling(benchmark::State& state, int side, pbd::Solver solver = pbd::Solver::colored,
                            bool bending = false) {
  ClothFixture f[4] = {ClothFixture(side, solver, bending), ClothFixture(side, solver, bending),
                       ClothFixture(side, solver, bending), ClothFixture(side, solver, bending)};  // two per half
  const pbd::ParallelConfig inline_all{std::size_t(-1), std::size_t(-1)};
  paired_scaling(
      state,
      [&](int half) {
        tbb::parallel_for(0, 2, [&](int k) {
          f[2 * half + k].substep(inline_all);
        }, tbb::static_partitioner());
        benchmark::ClobberMemory();
      },
      2.0 * double(f[0].constraints()) * kSweeps);
  state.counters["side"] = side;
  state.counters["constraints"] = 2.0 * double(f[0].constraints());
}

// The ceiling at size n for work of the solver's kind that shares nothing: two n² cloths, one per thread (each
// thread holds a whole cloth, twice what each of the colored solver's threads holds).
void BM_SharedNothingScaling(benchmark::State& state) { shared_nothing_scaling(state, int(state.range(0))); }

// The same for the data of one n² cloth: two cloths of side round(n/√2), about n²/2 particles each, so each thread
// holds half of an n² cloth's data, as each of the colored solver's threads does. Compare per thread (ns_1T, ns_2T):
// one thread alone is faster here than on one n² cloth, since each of its cloths is smaller.
void BM_SharedNothingHalvesScaling(benchmark::State& state) {
  shared_nothing_scaling(state, int(std::lround(double(state.range(0)) / std::sqrt(2.0))));
}

// The same split for the block solver's own work (interiors interleaved, scalar projections; bending with range(1)
// = 1): its same-run ceiling, each thread solving a whole half-size cloth with blocks and no fork.
void BM_SharedNothingHalvesBlockScaling(benchmark::State& state) {
  shared_nothing_scaling(state, int(std::lround(double(state.range(0)) / std::sqrt(2.0))), pbd::Solver::block,
                         state.range(1) != 0);
}

// The machine's own 2T/1T ceiling for work that touches no memory: two independent chains of floating-point
// multiply-adds in registers (about 5 ms on one thread), paired like BM_ColoredScaling. No solver can be expected to
// scale better than this in the same run.
void BM_ComputeScaling(benchmark::State& state) {
  double out[2] = {0, 0};
  paired_scaling(state, [&](int) {
    tbb::parallel_for(0, 2, [&](int half) {
      double a = 1.0 + half, b = 2.0 + half, c = 3.0 + half, d = 4.0 + half;
      for (int i = 0; i < 1500000; ++i) {
        a = a * 0.999999 + 1e-7;
        b = b * 0.999999 + 1e-7;
        c = c * 0.999999 + 1e-7;
        d = d * 0.999999 + 1e-7;
      }
      out[half] = a + b + c + d;
    }, tbb::static_partitioner());
    benchmark::DoNotOptimize(out);
  });
}

}  // namespace

BENCHMARK(BM_SerialSweep)->ArgName("n")->Arg(30)->Arg(100)->Arg(300)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSweep)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100, 300, 1000}, {1, 2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSweepAlwaysFork)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100}, {2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_JacobiSweep)->ArgNames({"n", "threads"})->ArgsProduct({{30, 100, 300, 1000}, {1, 2}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BlockSweep)->ArgNames({"n", "threads", "bending"})->ArgsProduct({{30, 100, 300, 1000}, {1, 2}, {0}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BlockSweep)->ArgNames({"n", "threads", "bending"})->ArgsProduct({{30, 300}, {1, 2}, {1}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSweepBending)->ArgNames({"n", "threads"})
    ->ArgsProduct({{30, 300}, {1, 2}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredScaling)->ArgName("n")->Arg(300)->Iterations(40)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BlockScaling)->ArgNames({"n", "bending", "per_block"})->ArgsProduct({{30}, {0, 1}, {0}})
    ->Iterations(400)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BlockScaling)->ArgNames({"n", "bending", "per_block"})->ArgsProduct({{300}, {0, 1}, {0}})
    ->Iterations(40)->Unit(benchmark::kMillisecond);
// Block sizes: what the partition's aim does to 2T/1T (the default is BlockOptions::constraints_per_block).
BENCHMARK(BM_BlockScaling)->ArgNames({"n", "bending", "per_block"})->ArgsProduct({{30}, {0, 1}, {128, 256, 512}})
    ->Iterations(400)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ColoredScaling)->ArgName("n")->Arg(1000)->Iterations(8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharedNothingScaling)->ArgName("n")->Arg(300)->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharedNothingHalvesScaling)->ArgName("n")->Arg(300)->Iterations(40)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharedNothingHalvesScaling)->ArgName("n")->Arg(1000)->Iterations(8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SharedNothingHalvesBlockScaling)->ArgNames({"n", "bending"})->ArgsProduct({{300}, {0, 1}})
    ->Iterations(40)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ComputeScaling)->Iterations(40)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StreamTriad)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
