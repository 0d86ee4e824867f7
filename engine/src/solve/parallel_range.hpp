#pragma once
// The one parallel loop driver of the engine (private): inline when small, serial or single-threaded; otherwise
// tbb::parallel_for with an explicit grain. Bodies must give the same result however the range is cut.
#include "pbd/solver.hpp"
#include "pbd/types.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>

namespace pbd::detail {

template <class Body>
void run_range(Index begin, Index end, bool parallel, const ParallelConfig& cfg, tbb::affinity_partitioner& ap,
               const Body& body) {
  const std::size_t n = end - begin;
  const std::size_t threads = std::size_t(tbb::this_task_arena::max_concurrency());
  if (!parallel || threads <= 1 || n < cfg.inline_below) {
    body(begin, end);
    return;
  }
  const std::size_t grain = std::max(cfg.min_grain, n / (4 * threads));
  tbb::parallel_for(
      tbb::blocked_range<Index>(begin, end, grain), [&](const tbb::blocked_range<Index>& r) { body(r.begin(), r.end()); },
      ap);
}

/// `cfg` for a loop over blocks of `block` items: the inline threshold and grain still count items.
inline ParallelConfig per_block(const ParallelConfig& cfg, std::size_t block) {
  return {std::max<std::size_t>(1, cfg.inline_below / block), std::max<std::size_t>(1, cfg.min_grain / block)};
}

}  // namespace pbd::detail
