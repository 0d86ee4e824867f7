// Phase 4 of the particle contacts (particle_contacts.hpp), per level: each entry's candidates are gathered from its
// own and the neighbouring cells and tested together (pair_test.hpp); each large box is tested against the entries in
// its cells; when few boxes are left, each against each. Each part fills contact lists of its own, in chunk order.
#include "pair_test.hpp"
#include "phases.hpp"

#include <array>
#include <cstring>
#include <type_traits>

namespace pbd::detail::contact {

namespace {

// The rows (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1) a row is walked along with.
constexpr std::array<std::array<std::int32_t, 2>, 4> kRows = {{{1, 0}, {-1, 1}, {0, 1}, {1, 1}}};

// The walk over buckets [first_bucket, last_bucket): each entry with those after it in its cell and the next cell
// along x, and with those in the neighbouring cells x − 1 to x + 1 of the rows kRows.
template <class Real>
void walk_buckets(const PairTest<Real>& test, const LevelGrid<Real>& grid, Index first_bucket, Index last_bucket,
                  std::vector<ParticleContact<Real>>& mine) {
  const auto* E = grid.E;
  const Index* start = grid.start;
  const std::int32_t* cx = grid.cx;
  const Index* pid = grid.pid;
  const bool dense = grid.dense;
  Others o;
  // b's candidates from row entries [from, from + count), counted in `size` (o.size once they are all taken:
  // a local count stays in a register)
  auto take = [&](Index from, Index count, std::uint32_t& size) {
    if (size + count > Others::kSize) {  // a crowded cell: one at a time
      o.size = size;
      for (Index k = 0; k < count; ++k) test.candidate(pid[from + k], o, mine);
      size = o.size;
      return;
    }
    Index* to = o.of.data() + size;
    std::memcpy(to, pid + from, 8 * sizeof(Index));  // eight at once; `count` of them kept
    for (Index k = 8; k < count; ++k) to[k] = pid[from + k];
    size += count;
  };
  for (Index b = first_bucket; b < last_bucket; ++b) {
    const Index s1 = start[b + 1];
    for (Index r0 = start[b], r1; r0 < s1; r0 = r1) {  // one row at a time: [r0, r1)
      const std::int32_t y = E[r0].cell[1], z = E[r0].cell[2];
      if (dense) r1 = s1;  // the bucket is the row
      else for (r1 = r0 + 1; r1 < s1 && grid.in_row(E[r1], y, z); ++r1) {}
      std::array<Index, 4> w, w1;  // each neighbouring row that holds boxes, walked along with this one: [w, w1)
      std::size_t rows = 0;
      for (std::size_t q = 0; q < kRows.size(); ++q) {
        const std::int32_t ny = y + kRows[q][0], nz = z + kRows[q][1];
        const std::uint32_t nb = grid.bucket_of(ny, nz);
        w[rows] = start[nb];  // dense: the bucket is the row
        w1[rows] = start[nb + 1];
        if (!dense) {
          w[rows] = grid.row_from(nb, ny, nz, E[r0].cell[0] - 1);
          for (w1[rows] = w[rows]; w1[rows] < start[nb + 1] && grid.in_row(E[w1[rows]], ny, nz); ++w1[rows]) {}
        }
        rows += w[rows] < w1[rows] ? 1 : 0;  // an empty row (a flat cloth's rows above it) is not walked
      }
      for (Index s = r0; s < r1; ++s) {
        const std::int32_t x = cx[s];
        o.a = pid[s];
        if (test.any_self) __builtin_prefetch(test.g.joined.data() + test.g.joined_offsets[pid[s + 2]]);  // pid runs 8 past
        std::uint32_t size = 0;
        take(s + 1, upto(cx, s + 1, r1, x, x + 1).second, size);  // its own cell (after s) and the next along x
        for (std::size_t q = 0; q < rows; ++q) {  // the neighbouring rows' cells x − 1, x, x + 1
          const auto [skip, n] = upto(cx, w[q], w1[q], x - 2, x + 1);
          w[q] += skip;
          take(w[q], n - skip, size);
        }
        o.size = size;
        test.flush(o, mine);
      }
    }
  }
}

// The same walk and pairs on a dense float grid, eight entries at a time (near_avx2.hpp).
void walk_dense(Call<float>& call, const Level<float>& lv, const LevelGrid<float>& grid, std::size_t first) {
  const PairTest<float> test = pair_test(call);
  DenseWalk walk;
  walk.cx = grid.cx;
  walk.pid = grid.pid;
  walk.start = grid.start;
  for (std::size_t q = 0; q < kRows.size(); ++q) walk.row_step[q] = Index(kRows[q][0] + kRows[q][1] * grid.dims[1]);
  walk.movers = call.g.movers.data()[0].x;
  walk.margin = call.margin;
  if (call.any_self) {
    walk.joined = call.g.joined.data();
    walk.joined_offsets = call.g.joined_offsets.data();
  }
  struct Sink {
    const PairTest<float>* test;
    std::vector<ParticleContact<float>>* mine;
  };
  const NearSink sink = [](void* context, const Index* pairs, std::size_t count) {
    const Sink& to = *static_cast<const Sink*>(context);
    for (std::size_t k = 0; k < count; ++k) to.test->keep(pairs[2 * k], pairs[2 * k + 1], *to.mine);
  };
  over_chunks(grid.small_chunks, call.fork(grid.small), [&](Index ch, Index, Index) {
    Sink to{&test, &call.g.lists[first + ch]};
    walk_dense_avx2(walk, lv.cut[ch], lv.cut[ch + 1], sink, &to);
  });
}

}  // namespace

template <class Real> void pair_each_with_each(Call<Real>& call, const Level<Real>& lv) {
  const PairTest<Real> test = pair_test(call);
  const Index members = Index(lv.members.size());
  std::vector<ParticleContact<Real>>& mine = call.g.lists[call.take_lists(1)];
  Others o;
  for (Index a = 0; a < members; ++a) {
    o.a = lv.members[a];
    for (Index b = a + 1; b < members; ++b) test.candidate(lv.members[b], o, mine);
    test.flush(o, mine);
  }
}

// Small with small: each box with those after it in its cell and the next cell along x, and with those in the
// neighbouring cells of the rows (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1): the 13 of the 26
// neighbouring cells that come after its own, so each pair once.
template <class Real> void walk_entries(Call<Real>& call, const Level<Real>& lv, const LevelGrid<Real>& grid) {
  if (grid.small <= 1) return;
  const std::size_t first = call.take_lists(std::size_t(grid.small_chunks));
  if constexpr (std::is_same_v<Real, float>) {
    if (grid.dense && call.avx2) {
      walk_dense(call, lv, grid, first);
      return;
    }
  }
  const PairTest<Real> test = pair_test(call);
  over_chunks(grid.small_chunks, call.fork(grid.small), [&](Index ch, Index, Index) {
    walk_buckets(test, grid, lv.cut[ch], lv.cut[ch + 1], call.g.lists[first + ch]);
  });
}

// Large with entered: each large box with the entries whose lower corners lie in its cells or one cell below (an
// entry that overlaps it has its lower corner there), or with every entry when that is too many rows.
template <class Real>
void query_large(Call<Real>& call, const Level<Real>& lv, const LevelGrid<Real>& grid, const Vec3<Real>& inv) {
  const Index large = Index(lv.large.size());
  const Index small = grid.small;
  if (large == 0 || small == 0) return;
  const PairTest<Real> test = pair_test(call);
  const std::int32_t* cx = grid.cx;
  const Index* pid = grid.pid;
  const Index* start = grid.start;
  const std::size_t first = call.take_lists(std::size_t(std::min<Index>(kChunks, large)));
  over_chunks(large, call.fork(16 * large), [&](Index ch, Index b, Index e) {  // a query costs tens of boxes' passes
    std::vector<ParticleContact<Real>>& mine = call.g.lists[first + ch];
    Others o;
    for (Index k = b; k < e; ++k) {
      const typename ParticleGrid<Real>::Box box = box_of(call.g, lv.large[k], call.frame, call.margin);
      o.a = lv.large[k];
      Cell lo = cell_of<Real>(box.lo, inv), hi = cell_of<Real>(box.hi, inv);
      std::uint64_t rows = 1;
      for (int d = 0; d < 3; ++d) lo[d] -= 1;
      for (int d = 1; d < 3; ++d) {
        if (grid.dense) {  // only the grid's rows hold boxes
          lo[d] = std::int32_t(std::max<std::int64_t>(lo[d], grid.base[d]));
          hi[d] = std::int32_t(std::min<std::int64_t>(hi[d], grid.base[d] + grid.dims[d] - 1));
        }
        rows *= std::uint64_t(std::max<std::int64_t>(0, std::int64_t(hi[d]) - lo[d] + 1));
      }
      if (rows > kMaxRows) {
        for (Index t = 0; t < small; ++t) test.candidate(pid[t], o, mine);
        test.flush(o, mine);
        continue;
      }
      for (std::int32_t cz = lo[2]; cz <= hi[2]; ++cz)
        for (std::int32_t cy = lo[1]; cy <= hi[1]; ++cy) {
          const std::uint32_t nb = grid.bucket_of(cy, cz);
          if (grid.dense) {  // the bucket is the row: its boxes in cells lo..hi along x, counted as the walk counts
            Index from = start[nb];
            const Index last = start[nb + 1];
            if (last - from > 32) from = Index(std::lower_bound(cx + from, cx + last, lo[0]) - cx);
            const auto [skip, end] = upto(cx, from, last, lo[0] - 1, hi[0]);
            for (Index t = from + skip; t < from + end; ++t) test.candidate(pid[t], o, mine);
          } else {
            for (Index t = grid.row_from(nb, cy, cz, lo[0]); t < start[nb + 1] && grid.in_row(grid.E[t], cy, cz) && cx[t] <= hi[0]; ++t)
              test.candidate(pid[t], o, mine);
          }
        }
      test.flush(o, mine);
    }
  });
}

template void pair_each_with_each(Call<float>&, const Level<float>&);
template void pair_each_with_each(Call<double>&, const Level<double>&);
template void walk_entries(Call<float>&, const Level<float>&, const LevelGrid<float>&);
template void walk_entries(Call<double>&, const Level<double>&, const LevelGrid<double>&);
template void query_large(Call<float>&, const Level<float>&, const LevelGrid<float>&, const Vec3<float>&);
template void query_large(Call<double>&, const Level<double>&, const LevelGrid<double>&, const Vec3<double>&);

}  // namespace pbd::detail::contact
