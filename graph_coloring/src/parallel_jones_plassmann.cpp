// Jones & Plassmann 1993, "A parallel graph coloring heuristic".
//
// Every item gets a random priority; item j precedes item i when (priority, index) of j is smaller.
// In each round, an uncolored item all of whose conflicting predecessors are colored takes the
// smallest color none of them has. Two items colored in one round never conflict (one would precede
// the other), and an item's color depends only on its predecessors' colors, so the result is exactly
// sequential first-fit in priority order: the same on any number of threads, and equal to
// greedy_random with the same seed.
//
// A round reads colors only (into per-item buffers) and the serial compaction after it writes them,
// so no location is written while another thread reads it. The number of rounds is the longest
// chain of conflicting items with increasing priority: small for meshes, large for a node shared by
// very many items (there, use a greedy algorithm).
#include "parallel_jones_plassmann.hpp"

#include <algorithm>
#include <bit>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "common.hpp"

#if defined(__SANITIZE_THREAD__)
#include <sanitizer/tsan_interface.h>
// Debian's libtbb is not instrumented, so ThreadSanitizer cannot see the fork/join edges of
// parallel_for. Declaring them (release before the fork, acquire in each body; release at the end
// of each body, acquire after the join) lets it check this file's own accesses: bodies stay
// unordered with respect to each other, so a race between two of them is still reported.
#define PBD_TSAN_RELEASE(p) __tsan_release(p)
#define PBD_TSAN_ACQUIRE(p) __tsan_acquire(p)
#else
#define PBD_TSAN_RELEASE(p) ((void)(p))
#define PBD_TSAN_ACQUIRE(p) ((void)(p))
#endif

namespace pbd::coloring::detail {

namespace {

constexpr std::uint32_t kNotReady = kUncolored;
// Ranges split down to kGrain items. simple_partitioner: any partition gives the same result here,
// and unlike auto_partitioner its splitting has no benign race for ThreadSanitizer to report.
constexpr std::size_t kGrain = 1024;

// Smallest color not in used (bits for 0..63) nor in high (colors >= 64, unsorted).
std::uint32_t first_free(std::uint64_t used, std::vector<std::uint32_t>& high) {
  if (used != ~std::uint64_t{0}) return static_cast<std::uint32_t>(std::countr_one(used));
  std::sort(high.begin(), high.end());
  std::uint32_t c = 64;
  for (std::uint32_t h : high) {
    if (h == c) ++c;
    else if (h > c) break;
  }
  return c;
}

}  // namespace

std::uint32_t jones_plassmann(const Hypergraph& g, std::uint32_t wide_threshold, std::uint64_t seed,
                              const NodeItems& adj, std::span<std::uint32_t> color, std::uint32_t& num_wide) {
  const std::uint32_t n = g.num_items();
  std::vector<std::uint32_t> prio(n);
  int fork = 0, join = 0;  // addresses for the ThreadSanitizer annotations only
  PBD_TSAN_RELEASE(&fork);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& r) {
    PBD_TSAN_ACQUIRE(&fork);
    for (std::uint32_t i = r.begin(); i != r.end(); ++i) {
      prio[i] = priority(seed, i);
      color[i] = kUncolored;
    }
    PBD_TSAN_RELEASE(&join);
  }, tbb::simple_partitioner{});
  PBD_TSAN_ACQUIRE(&join);
  std::vector<std::uint32_t> remaining;
  remaining.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!is_wide(g, i, wide_threshold)) remaining.push_back(i);
  num_wide = n - static_cast<std::uint32_t>(remaining.size());

  std::vector<std::uint32_t> chosen(remaining.size());
  std::uint32_t num_colors = 0;
  while (!remaining.empty()) {
    PBD_TSAN_RELEASE(&fork);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, remaining.size(), kGrain), [&](const auto& r) {
      PBD_TSAN_ACQUIRE(&fork);
      std::vector<std::uint32_t> high;
      for (std::size_t k = r.begin(); k != r.end(); ++k) {
        const std::uint32_t i = remaining[k];
        const std::uint32_t pi = prio[i];
        std::uint64_t used = 0;
        high.clear();
        bool ready = true;
        for (std::uint32_t node : g.item(i)) {
          if (g.is_fixed(node)) continue;
          for (std::uint32_t j : adj.at(node)) {
            if (!(prio[j] < pi || (prio[j] == pi && j < i))) continue;  // j does not precede i
            const std::uint32_t cj = color[j];
            if (cj == kUncolored) {
              ready = false;
              break;
            }
            if (cj < 64) used |= std::uint64_t{1} << cj;
            else high.push_back(cj);
          }
          if (!ready) break;
        }
        chosen[k] = ready ? first_free(used, high) : kNotReady;
      }
      PBD_TSAN_RELEASE(&join);
    }, tbb::simple_partitioner{});
    PBD_TSAN_ACQUIRE(&join);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < remaining.size(); ++k) {
      if (chosen[k] == kNotReady) {
        remaining[kept++] = remaining[k];
      } else {
        color[remaining[k]] = chosen[k];
        num_colors = std::max(num_colors, chosen[k] + 1);
      }
    }
    remaining.resize(kept);
  }
  return num_colors;
}

}  // namespace pbd::coloring::detail
