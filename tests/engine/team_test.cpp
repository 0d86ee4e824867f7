// The sweeps' thread team (engine/src/solve/team.hpp): every part of a loop runs once whichever threads joined,
// member 0's work alone is seen by the next shared loop, and a team whose workers never come runs on its own.
#include "solve/team.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <vector>

namespace {

using pbd::detail::Team;

// Rounds of: a shared loop that adds 1 to every element, a loop on member 0 alone that checks the sum (every
// member's writes must be visible) and writes a marker, a shared loop that checks the marker. Counts must come out
// exact: no element twice, none missed.
// Returns the largest team that formed over `attempts` runs, workers waited for `wait_ms`.
int exercise(int arena_threads, int team_threads, int attempts = 1, int wait_ms = 0) {
  constexpr std::size_t n = 1000;
  constexpr int rounds = 50;
  std::vector<int> a(n, 0);
  std::atomic<int> largest{0}, bad{0};
  int marker = -1;
  tbb::task_arena arena(arena_threads);
  for (int attempt = 0; attempt < attempts; ++attempt) {
  std::fill(a.begin(), a.end(), 0);
  arena.execute([&] {
    Team::run(team_threads, std::chrono::milliseconds(wait_ms), [&](Team::Member& m) {
      if (m.rank == 0) largest = std::max(largest.load(), m.size());
      for (int r = 0; r < rounds; ++r) {
        m.loop(0, n, true, [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) ++a[i];
        });
        m.loop(0, 1, false, [&](std::size_t, std::size_t) {
          long sum = 0;
          for (int v : a) sum += v;
          if (sum != long(n) * (r + 1)) ++bad;
          marker = r;
        });
        m.loop(0, n, true, [&](std::size_t, std::size_t) {
          if (marker != r) ++bad;
        });
      }
    });
  });
  EXPECT_EQ(bad.load(), 0) << arena_threads << " threads";
  for (int v : a) EXPECT_EQ(v, rounds);
  }
  EXPECT_LE(largest.load(), std::min(arena_threads, team_threads));
  return largest.load();
}

TEST(Team, EveryPartRunsOnceAndMemberZerosWorkIsSeen) {
  EXPECT_EQ(exercise(1, 1), 1);
  // Workers join when they come within the wait (here 50 ms, ample): over 10 runs, at least once (else the test
  // would show nothing). (This machine may give fewer workers than the arena asks for, so at least 2.)
  for (int threads : {2, 3, 4}) EXPECT_GE(exercise(threads, threads, 10, 50), 2) << threads << " threads";
}

// More members asked for than the arena has threads: the tasks nobody picks up in time return at once, and the
// team runs with those that joined (with one thread: member 0 alone, no deadlock).
TEST(Team, RunsWithTheThreadsThatJoin) {
  EXPECT_EQ(exercise(1, 4), 1);
  EXPECT_LE(exercise(2, 8, 10), 2);
}

// loop_parts: member r runs [start(r), start(r + 1)); starts out of order or out of range are clamped, so the
// parts still cover the range exactly once.
TEST(Team, ChosenPartsCoverTheRangeOnceWhateverTheStarts) {
  for (int threads : {2, 3, 4}) {
    std::vector<std::atomic<int>> hits(100);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      Team::run(threads, std::chrono::milliseconds(50), [&](Team::Member& m) {
        m.loop_parts(10, 90, true, [](int r) -> std::size_t { return r == 1 ? 70 : r == 2 ? 40 : 1000; },
                     [&](std::size_t b, std::size_t e) {
                       for (std::size_t i = b; i < e; ++i) ++hits[i];
                     });
      });
    });
    for (std::size_t i = 0; i < hits.size(); ++i) EXPECT_EQ(hits[i].load(), i >= 10 && i < 90 ? 1 : 0) << i;
  }
}

// Team::Outcome: the members and the share of their time spent in barriers. One member never waits. Of two, both
// first meet at a barrier (so a worker that starts late makes member 0 wait, and that wait is counted); then member 0
// works 5 ms alone in a shared loop (its part is the whole range) while member 1 waits for it. The share is then
// strictly between 0 and 1, and at least about one half: member 1 waits through member 0's whole loop, member 0
// through the worker's late start. A member's thread descheduled between the two barriers counts as working, so on
// a loaded machine one run may come out lower: the test asks for one run of at most 50 to reach 0.45.
TEST(Team, ReportsTheShareOfTheirTimeMembersWaited) {
  auto spin = [](std::chrono::microseconds d) {
    const auto until = std::chrono::steady_clock::now() + d;
    while (std::chrono::steady_clock::now() < until) {
    }
  };
  tbb::task_arena arena(2);
  arena.execute([&] {
    const Team::Outcome one = Team::run(1, std::chrono::milliseconds(0), [&](Team::Member& m) {
      m.loop(0, 10, true, [&](std::size_t, std::size_t) { spin(std::chrono::microseconds(100)); });
    });
    EXPECT_EQ(one.members, 1);
    EXPECT_EQ(one.wait_fraction, 0.0);
    int two = 0;
    bool half = false;
    for (int attempt = 0; attempt < 50 && !half; ++attempt) {
      const Team::Outcome out = Team::run(2, std::chrono::milliseconds(50), [&](Team::Member& m) {
        m.wait();
        m.loop_parts(0, 2, true, [](int) -> std::size_t { return 2; },  // member 0: [0, 2); member 1: nothing
                     [&](std::size_t, std::size_t) { spin(std::chrono::milliseconds(5)); });
      });
      if (out.members < 2) {
        EXPECT_EQ(out.wait_fraction, 0.0);
        continue;
      }
      ++two;
      EXPECT_GT(out.wait_fraction, 0.0);
      EXPECT_LT(out.wait_fraction, 1.0);
      half = out.wait_fraction >= 0.45;
    }
    EXPECT_GT(two, 0) << "no team of two formed in 50 runs that waited 50 ms for the worker";
    EXPECT_TRUE(half) << "of " << two << " teams of two, none waited at least about half of its time";
  });
}

}  // namespace
