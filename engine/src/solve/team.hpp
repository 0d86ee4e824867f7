#pragma once
// A team of threads held for all of a sub-step's sweeps (private): one fork/join per sub-step instead of one per
// parallel loop (a cloth with bending has 20–27 colors a sweep, and a fork/join costs about as much as projecting a
// thousand constraints; the block solver has its interiors and then its boundary colors).
//
// Every member runs the same sweep code (SPMD: the sweeps' control flow depends on the model alone, so every member
// takes the same path). A loop shared by the team is cut into one contiguous part per member, the same part every
// sweep (so each thread keeps its own particles in its cache), and ends at a barrier. A loop too small to share runs
// on member 0 alone; the others go on to the next shared loop, which first waits at a barrier for member 0's
// writes. Every loop the sweeps run gives the same bits however it is cut (sweep.hpp), so which threads joined, and
// how many, never changes a bit.
//
// Joining: the calling thread is member 0; up to threads − 1 tasks are spawned in the caller's arena, and a worker
// that picks one up within the wait becomes a member (the solver waits at most a tenth of its last solve's time: a
// worker asleep in the arena takes long to wake, and on a small model the wait would cost more than it brings).
// Then the team closes: a task that starts later returns at once. Nothing ever waits on a thread that has not
// joined, so a busy arena (a host's, or one whose workers are asleep) costs at most the wait, never a deadlock.
// Barriers spin (with a pause, then yielding): the team exists only while the sweeps run.
// Waiting is measured: each member counts the processor's ticks it spends in barriers (and so waiting for member
// 0's loops run alone), and run() reports that share of the members' time: StepStats::seconds_waiting, the scaling
// diagnostic (two reads of the time-stamp counter per barrier: cheap against the barrier itself).
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#if defined(__SSE2__)
#include <immintrin.h>
#endif
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace pbd::detail {

class Team {
public:
  /// What run() reports: how many members the team had, and the share of their time they spent waiting.
  struct Outcome {
    int members = 1;
    double wait_fraction = 0.0;  ///< ticks spent in barriers over all members' ticks in f (0 with one member)
  };

  /// The member's view: its rank and whether member 0 ran work alone since the last barrier.
  struct Member {
    Team* team = nullptr;
    int rank = 0;
    bool behind = false;  ///< member 0 wrote alone since the last barrier: wait before the next shared loop
    std::uint64_t waited = 0;  ///< ticks this member spent in barriers

    int size() const { return team->size_; }
    /// The team's barrier, its ticks counted in `waited`.
    void wait() {
      const std::uint64_t start = ticks();
      team->barrier();
      waited += ticks() - start;
    }
    /// Runs body(b, e) over [begin, end): shared (each member its contiguous part, then a barrier), or on member 0
    /// alone (share = false; no barrier: the next shared loop waits for it).
    template <class Body> void loop(std::size_t begin, std::size_t end, bool share, const Body& body) {
      const int n = size();
      if (n == 1) {
        body(begin, end);
        return;
      }
      if (!share) {
        if (rank == 0) body(begin, end);
        behind = true;
        return;
      }
      if (behind) {
        wait();
        behind = false;
      }
      const std::size_t count = end - begin;
      const std::size_t b = begin + count * std::size_t(rank) / std::size_t(n);
      const std::size_t e = begin + count * std::size_t(rank + 1) / std::size_t(n);
      if (b < e) body(b, e);
      wait();
    }
    /// loop() with the parts chosen by the caller: member r runs [start(r), start(r + 1)), start(0) = begin and
    /// start(size()) = end, each start clamped into [the one before, end] so the parts always cover the range once.
    template <class Start, class Body>
    void loop_parts(std::size_t begin, std::size_t end, bool share, const Start& start, const Body& body) {
      if (size() == 1 || !share) return loop(begin, end, share, body);
      if (behind) {
        wait();
        behind = false;
      }
      std::size_t b = begin;
      for (int r = 1; r <= rank; ++r) b = std::clamp<std::size_t>(start(r), b, end);
      const std::size_t e = rank + 1 == size() ? end : std::clamp<std::size_t>(start(rank + 1), b, end);
      if (b < e) body(b, e);
      wait();
    }
  };

  /// Runs f(member) on the calling thread and on the workers that join within `wait` (at most `threads` in all);
  /// returns how many members the team had and how much of their time they waited.
  template <class F> static Outcome run(int threads, std::chrono::microseconds wait, const F& f) {
    Team team;
    if (threads <= 1) {
      Member m{&team, 0};
      f(m);
      return {};
    }
    auto member = [&team, &f](int rank) {
      Member m{&team, rank};
      const std::uint64_t start = ticks();
      f(m);
      team.ticks_.fetch_add(ticks() - start, std::memory_order_relaxed);
      team.waited_.fetch_add(m.waited, std::memory_order_relaxed);
    };
    tbb::task_group workers;
    for (int i = 1; i < threads; ++i)
      workers.run([&team, &member] {
        const int rank = team.join();
        if (rank < 0) return;
        while (!team.closed_.load(std::memory_order_acquire)) pause();
        member(rank);
      });
    team.close(threads, wait);
    member(0);
    workers.wait();
    const std::uint64_t all = team.ticks_.load(std::memory_order_relaxed);
    const double waited = all ? double(team.waited_.load(std::memory_order_relaxed)) / double(all) : 0.0;
    return {team.size_, team.size_ > 1 ? std::min(1.0, waited) : 0.0};
  }

  /// A monotonic tick count: the time-stamp counter where there is one (cheap), else steady_clock's nanoseconds.
  static std::uint64_t ticks() {
#if defined(__x86_64__) || defined(__i386__)
    return __rdtsc();
#else
    return std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
  }

private:
  static constexpr int kClosed = 1 << 30;

  static void pause() {
#if defined(__SSE2__)
    _mm_pause();
#else
    std::this_thread::yield();
#endif
  }

  // A worker's rank, or −1 when the team has closed.
  int join() {
    int v = state_.load(std::memory_order_relaxed);
    while (!(v & kClosed))
      if (state_.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel)) return v;
    return -1;
  }

  // Member 0: waits (at most `wait`) for threads − 1 workers, then closes the team.
  void close(int threads, std::chrono::microseconds wait) {
    const auto until = std::chrono::steady_clock::now() + wait;
    while (state_.load(std::memory_order_acquire) < threads && std::chrono::steady_clock::now() < until) pause();
    const int joined = state_.fetch_or(kClosed, std::memory_order_acq_rel);
    size_ = joined;
    closed_.store(true, std::memory_order_release);
  }

  // Sense-reversing central barrier: the last to arrive resets the count and starts the next generation.
  void barrier() {
    const unsigned gen = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) == size_ - 1) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.store(gen + 1, std::memory_order_release);
      return;
    }
    for (int spins = 0; generation_.load(std::memory_order_acquire) == gen; ++spins)
      if (spins < 4096) pause();
      else std::this_thread::yield();  // the other member's thread is not running (a busy machine)
  }

  alignas(64) std::atomic<int> state_{1};  // members joined (member 0 counts), | kClosed once closed
  std::atomic<bool> closed_{false};
  int size_ = 1;                           // members, fixed when closed_ is set
  std::atomic<std::uint64_t> ticks_{0};   // members' ticks in f, summed as each member leaves
  std::atomic<std::uint64_t> waited_{0};  // members' ticks in barriers, summed likewise
  alignas(64) std::atomic<int> arrived_{0};
  alignas(64) std::atomic<unsigned> generation_{0};
};

}  // namespace pbd::detail
