#pragma once
// The phases of generate_particle_contacts (private to contact/), in the order it runs them (particle_contacts.hpp's
// design note says what each does and why), and what they share: the call's inputs, the fixed chunks every loop runs
// in, and a level's grid as the walk reads it.
//   exclusions.cpp  1. the particles joined by a constraint (self-colliding bodies), when the model changed
//   boxes.cpp       2. the frame, the movers and swept boxes, level 0's cells
//   grid.cpp        3. per level: cells of the boxes, entries, buckets, the entries sorted
//   walk.cpp        4. per level: each entry's candidates gathered and tested (pair_test.hpp, near_avx2.hpp)
//   order.cpp       5. the contacts in the order of their pairs
#include "cells.hpp"
#include "particle_contacts.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

namespace pbd::detail::contact {

constexpr Index kChunks = 64;              // fixed, so the output never depends on the thread count
constexpr std::uint64_t kMaxRows = 4096;   // a larger box whose query spans more rows is paired with every small box
constexpr Index kBruteForce = 64;          // at most this many boxes left: paired with one another
// Cells as wide as the boxes are on average along each axis (chosen by measurement on bench_contacts' draped cloth
// and grain lattice: wider cells hold more boxes to pair, narrower ones leave more boxes large). The boxes alone
// decide which pairs are tested, and the test alone which are kept, so the cells change only the cost.
constexpr double kCellScale = 1.0;

// Calls f(chunk, begin, end) for `count` items in min(kChunks, count) fixed chunks, in parallel when `fork`. Whatever
// a chunk computes depends on its items only, and chunk results are joined in chunk order, so nothing depends on
// threads.
template <class F> void over_chunks(Index count, bool fork, const F& f) {
  const Index chunks = std::min<Index>(kChunks, count);
  auto one = [&](Index ch) {
    f(ch, Index(std::uint64_t(ch) * count / chunks), Index(std::uint64_t(ch + 1) * count / chunks));
  };
  if (fork && chunks > 1)
    tbb::parallel_for(tbb::blocked_range<Index>(0, chunks, 1), [&](const tbb::blocked_range<Index>& r) {
      for (Index ch = r.begin(); ch < r.end(); ++ch) one(ch);
    });
  else
    for (Index ch = 0; ch < chunks; ++ch) one(ch);
}

// One call of generate_particle_contacts: its inputs, what the first phases found for the later ones, and the
// contact lists the pair phases fill (g.lists, in the order they are taken).
template <class Real> struct Call {
  const Model<Real>& m;
  const Matrix3X<Real>& x;  // positions at the start of the sub-step
  const Matrix3X<Real>& p;  // predicted
  const Matrix3X<Real>& v;  // velocities after forces (restitution)
  Real margin;
  bool parallel;
  ParticleGrid<Real>& g;
  bool any_self = false;  // a body collides with itself: pairs joined by a constraint are masked out
  bool known = false;     // g's frame and cell widths are the last sub-step's, of as many particles
  Vec3<Real> frame = Vec3<Real>::Zero();  // the frame the boxes are swept in (a mean path)
  bool avx2 = false;      // the AVX2 builds may run (simd/cpu.hpp)
  bool repeats = false;   // a box was entered in pieces: a pair may have been found more than once
  std::size_t lists = 0;  // contact lists used so far
  std::size_t limit = 0;  // the most pairs the call may find (budget.hpp)
  mutable std::atomic<std::size_t> found{0};  // pairs the lists have found so far, in whole kCountEvery (budget.hpp)

  bool fork(Index items) const { return parallel && items >= kParallelContactsFrom; }
  // k more contact lists, emptied: the index of the first
  std::size_t take_lists(std::size_t k) {
    if (g.lists.size() < lists + k) g.lists.resize(lists + k);
    for (std::size_t l = lists; l < lists + k; ++l) g.lists[l].clear();
    lists += k;
    return lists - k;
  }
};

// Entry order within a bucket: cell (z, y, x), then particle.
template <class Slot> inline bool before(const Slot& a, const Slot& b) {
  if (a.cell[2] != b.cell[2]) return a.cell[2] < b.cell[2];
  if (a.cell[1] != b.cell[1]) return a.cell[1] < b.cell[1];
  if (a.cell[0] != b.cell[0]) return a.cell[0] < b.cell[0];
  return a.particle < b.particle;
}

// One level's grid as the walk and the queries read it (grid.cpp builds it; particle_contacts.hpp, phase 3).
template <class Real> struct LevelGrid {
  using Slot = typename ParticleGrid<Real>::Slot;
  Index small = 0;                          // entries: small boxes and pieces of larger ones
  Index small_chunks = 1;                   // the walk's chunks (buckets lv.cut[ch] to lv.cut[ch + 1])
  Cell base{0, 0, 0};                       // dense: the rows' lowest cell (x: of the lower corners)
  std::array<std::int64_t, 3> dims{0, 0, 0};  // dense: cells along each axis
  bool dense = false;                       // a bucket per row of the bounding grid (else a hash table of rows)
  std::uint32_t buckets = 1, mask = 0;      // buckets; the hash table's mask
  const Slot* E = nullptr;                  // the entries, bucket by bucket, sorted by before()
  const Index* start = nullptr;             // per bucket + 1: its first entry
  const std::int32_t* cx = nullptr;         // per entry (+ 8 past the end): its cell along x
  const Index* pid = nullptr;               // per entry (+ 8 past the end): its particle

  // The bucket of row (y, z).
  std::uint32_t bucket_of(std::int32_t y, std::int32_t z) const {
    if (dense) return std::uint32_t((std::int64_t(z) - base[2]) * dims[1] + (std::int64_t(y) - base[1]));
    return hash_cell(0, y, z, mask);
  }
  // The boxes of row (y, z) in bucket `nb` from cell x0 on: [from, end of the row)
  Index row_from(std::uint32_t nb, std::int32_t y, std::int32_t z, std::int32_t x0) const {
    Slot probe;
    probe.cell = {x0, y, z};
    probe.particle = 0;
    return Index(std::lower_bound(E + start[nb], E + start[nb + 1], probe,
                                  [](const Slot& a, const Slot& b) { return before(a, b); }) - E);
  }
  static bool in_row(const Slot& e, std::int32_t y, std::int32_t z) { return e.cell[1] == y && e.cell[2] == z; }
};

// Entries [from, end) whose cells along x (cx) are at most `top`: counted eight at a time without a branch (the
// arrays run eight past the last entry), as the rows hold one or two boxes per cell, so that one probe nearly always
// ends the count. With `below` < `top`, also those whose cells are at most `below` (a prefix: the row is sorted).
// Returns (those at most `below`, those at most `top`).
inline std::pair<Index, Index> upto(const std::int32_t* cx, Index from, Index end, std::int32_t below, std::int32_t top) {
  Index n = 0, under = 0;
  for (;;) {
    Index k8 = 0;
#if defined(__SSE2__)
    using namespace wide;
    const Index at = from + n;  // indices and cells fit in 31 bits: signed compares
    const IntW last = splat_int(std::int32_t(end)), high = splat_int(top + 1);
    const IntW low_end = splat_int(below + 1);
    const IntW index = splat_int(std::int32_t(at)) + lanes_int(0, 1, 2, 3);
    const IntW c0 = loadu(cx + at);
    const IntW c1 = loadu(cx + at + 4);
    const MaskIW in0 = (index < last) & (c0 < high);
    const MaskIW in1 = ((index + splat_int(4)) < last) & (c1 < high);
    const MaskIW lo0 = in0 & (c0 < low_end);
    const MaskIW lo1 = in1 & (c1 < low_end);
    const unsigned inside = unsigned(bits(in0)) | unsigned(bits(in1)) << 4;
    const unsigned lower = unsigned(bits(lo0)) | unsigned(bits(lo1)) << 4;
    k8 = Index(__builtin_ctz(~inside));  // prefixes: a row is sorted
    under += Index(__builtin_ctz(~lower));
#else
    for (Index k = 0; k < 8; ++k) {
      const Index at = from + n + k;
      const bool in = (at < end) & (cx[at] <= top);
      k8 += Index(in);
      under += Index(in & (cx[at] <= below));
    }
#endif
    n += k8;
    if (k8 < 8) return std::pair<Index, Index>(under, n);
  }
}

template <class Real> using Level = typename ParticleGrid<Real>::Level;

// 1. exclusions.cpp: g's rows of the particles joined to each particle (self-colliding bodies only).
template <class Real> void build_exclusions(const Model<Real>& m, const Matrix3X<Real>& x, ParticleGrid<Real>& g);
// 2. boxes.cpp: this sub-step's mean path (the frame when the last sub-step's is not known).
template <class Real> Vec3<Real> mean_path(Call<Real>& call);
// 2. boxes.cpp: the movers, the boxes' sums (the next sub-step's frame and cells) and, when known, level 0's cells.
template <class Real> void sweep_boxes(Call<Real>& call);
// 3. grid.cpp: the cells of each member's box (level 0's when the boxes' pass could not find them).
template <class Real> void find_cells(Call<Real>& call, Level<Real>& lv, const Vec3<Real>& inv);
// 3. grid.cpp: the level's entries in buckets, sorted; its large members in lv.large.
template <class Real> LevelGrid<Real> build_grid(Call<Real>& call, Level<Real>& lv);
// 4. walk.cpp: each member with each (a few left).
template <class Real> void pair_each_with_each(Call<Real>& call, const Level<Real>& lv);
// 4. walk.cpp: entries with entries in the same or the next cells.
template <class Real> void walk_entries(Call<Real>& call, const Level<Real>& lv, const LevelGrid<Real>& grid);
// 4. walk.cpp: each large box with the entries in its cells.
template <class Real>
void query_large(Call<Real>& call, const Level<Real>& lv, const LevelGrid<Real>& grid, const Vec3<Real>& inv);
// 5. order.cpp: the lists' contacts appended to `out` in the order of their pairs, each once.
template <class Real> void order_contacts(Call<Real>& call, std::vector<ParticleContact<Real>>& out);

}  // namespace pbd::detail::contact
