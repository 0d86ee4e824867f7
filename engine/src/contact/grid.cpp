// Phase 3 of the particle contacts (particle_contacts.hpp), per level: the cells of each box's corners, the level's
// entries (small boxes, pieces of larger ones) and large members, the entries' buckets (rows of cells along x), and
// the entries sorted within their buckets, with the copies of their cells along x and particles that the walk reads.
#include "phases.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace pbd::detail::contact {

namespace {

// The level's entries (small boxes once, boxes in pieces as their pieces) in lv.slots, its large members in lv.large.
template <class Real> void enter_slots(Call<Real>& call, Level<Real>& lv) {
  const Index members = Index(lv.members.size());
  lv.large.clear();
  lv.slots.clear();
  for (Index k = 0; k < members; ++k) {
    if (lv.key[k] == kLarge) {
      lv.large.push_back(lv.members[k]);
    } else if (lv.key[k] == 0) {
      lv.slots.push_back({lv.lo[k], lv.members[k]});
    } else {
      call.repeats = true;
      const Cell& a = lv.lo[k];
      const Cell& z = lv.hi[k];
      for (std::int32_t cz = a[2]; cz <= z[2]; cz += 2)  // pieces' lower corners: two cells apart, so that no
        for (std::int32_t cy = a[1]; cy <= z[1]; cy += 2)  // two of one box are ever paired
          for (std::int32_t cx0 = a[0]; cx0 <= z[0]; cx0 += 2) lv.slots.push_back({{cx0, cy, cz}, lv.members[k]});
    }
  }
}

// Buckets: rows of cells along x, keyed by (y, z): the rows of the small boxes' lower corners' bounding grid grown by
// one row on every side (so that a neighbouring row's bucket is the box's own plus a fixed step), y fastest, when
// there are at most 8 rows per small box; else a hash table of about twice as many buckets as small boxes.
template <class Real> void lay_out_buckets(const Level<Real>& lv, LevelGrid<Real>& grid) {
  const Index small = grid.small;
  const Index chunks = std::min<Index>(kChunks, Index(lv.members.size()));
  Cell& base = grid.base;
  std::array<std::int64_t, 3>& dims = grid.dims;
  if (small > 0) {
    Cell lo = lv.bounds[0].first, hi = lv.bounds[0].second;
    for (Index ch = 1; ch < chunks; ++ch)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], lv.bounds[ch].first[d]);
        hi[d] = std::max(hi[d], lv.bounds[ch].second[d]);
      }
    base[0] = lo[0];  // along x: the lower corners' range
    dims[0] = std::int64_t(hi[0]) - lo[0] + 1;
    for (int d = 1; d < 3; ++d) {
      base[d] = lo[d] - 1;  // cells are clamped to ±1e9: no overflow
      dims[d] = std::int64_t(hi[d]) - lo[d] + 3;
    }
  }
  const std::uint64_t dense_rows = std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
  grid.dense = small > 0 && dense_rows <= 8 * std::uint64_t(small) && dense_rows < (1ull << 31);
  grid.buckets = 1;
  if (grid.dense) {
    grid.buckets = std::uint32_t(dense_rows);
  } else {
    while (grid.buckets < 2 * std::uint64_t(small)) grid.buckets <<= 1;
  }
  grid.mask = grid.buckets - 1;
}

// A bucket's entries sorted by `less`: insertion sort when few (a row of particles added in x order is sorted
// already).
template <class Slot, class Less> void sort_bucket(Slot* first, Slot* last, const Less& less) {
  if (last - first <= 24) {
    for (Slot* q = first + 1; q < last; ++q)
      for (Slot* r = q; r > first && less(*r, *(r - 1)); --r) std::swap(*r, *(r - 1));
  } else {
    std::sort(first, last, less);
  }
}

// Counting sort of the entries by bucket, then each bucket sorted by (cell z, y, x, particle) (a row's boxes lie
// together, in x order). Dense, and when the cells along x are not too many: a counting sort by cell x first, so
// that the one by bucket (stable) leaves each row in (x, particle) order with no sort (members are ascending). One
// pass finds each entry's bucket and counts both sorts' keys. Also the walk's copies of the entries' cells along x
// and particles, eight past the end; and the walk's chunks of buckets (lv.cut).
template <class Real> void sort_entries(Call<Real>& call, Level<Real>& lv, LevelGrid<Real>& grid) {
  using Slot = typename ParticleGrid<Real>::Slot;
  const Index small = grid.small;
  const std::uint32_t buckets = grid.buckets;
  const bool dense = grid.dense;
  const bool by_x = dense && grid.dims[0] <= 4 * std::int64_t(small) + 64;
  lv.key.resize(std::size_t(small));
  lv.bucket_start.assign(std::size_t(buckets) + 1, 0);
  if (by_x) {
    lv.x_start.assign(std::size_t(grid.dims[0]) + 1, 0);
    for (Index t = 0; t < small; ++t) {
      const Cell& cell = lv.slots[t].cell;
      const std::uint32_t key = grid.bucket_of(cell[1], cell[2]);
      lv.key[t] = key;
      ++lv.bucket_start[key + 1];
      ++lv.x_start[cell[0] - grid.base[0] + 1];
    }
  } else {
    for (Index t = 0; t < small; ++t) {
      const std::uint32_t key = grid.bucket_of(lv.slots[t].cell[1], lv.slots[t].cell[2]);
      lv.key[t] = key;
      ++lv.bucket_start[key + 1];
    }
  }
  for (std::uint32_t b = 0; b < buckets; ++b) lv.bucket_start[b + 1] += lv.bucket_start[b];
  lv.entries.resize(small);
  lv.cell_x.resize(std::size_t(small) + 8);
  lv.particle.resize(std::size_t(small) + 8);
  lv.fill.assign(lv.bucket_start.begin(), lv.bucket_start.end() - 1);
  auto enter = [&](Index t) {  // also the walk's copies of the entries' cells along x and particles
    const Slot& slot = lv.slots[t];
    const Index at = lv.fill[lv.key[t]]++;
    lv.entries[at] = slot;
    lv.cell_x[at] = slot.cell[0];
    lv.particle[at] = slot.particle;
  };
  if (by_x) {
    for (std::int64_t x = 0; x < grid.dims[0]; ++x) lv.x_start[x + 1] += lv.x_start[x];
    lv.by_x.resize(small);
    for (Index t = 0; t < small; ++t) lv.by_x[lv.x_start[lv.slots[t].cell[0] - grid.base[0]]++] = t;
    for (Index t = 0; t < small; ++t) enter(lv.by_x[t]);
  } else {
    for (Index t = 0; t < small; ++t) enter(t);
  }
  Slot* E = lv.entries.data();
  const Index* start = lv.bucket_start.data();
  auto before_x = [](const Slot& a, const Slot& b) {  // dense: a bucket is one row
    return a.cell[0] != b.cell[0] ? a.cell[0] < b.cell[0] : a.particle < b.particle;
  };
  auto by_cell = [](const Slot& a, const Slot& b) { return before(a, b); };
  const Index small_chunks = std::min<Index>(kChunks, std::max<Index>(small, 1));
  lv.cut.resize(std::size_t(small_chunks) + 1);
  for (Index ch = 0; ch < small_chunks; ++ch)  // chunk ch: the buckets from the first at or after entry ch·small/chunks
    lv.cut[ch] = Index(std::lower_bound(lv.bucket_start.begin(), lv.bucket_start.end() - 1,
                                        Index(std::uint64_t(ch) * small / small_chunks)) - lv.bucket_start.begin());
  lv.cut[small_chunks] = buckets;
  if (small > 1 && !by_x)
    over_chunks(small_chunks, call.fork(small), [&](Index ch, Index, Index) {
      for (Index b = lv.cut[ch]; b < lv.cut[ch + 1]; ++b) {
        if (dense) sort_bucket(E + start[b], E + start[b + 1], before_x);
        else sort_bucket(E + start[b], E + start[b + 1], by_cell);
      }
    });
  if (small > 1 && !by_x)  // the buckets' sorts moved entries: copy them again
    for (Index k = 0; k < small; ++k) {
      lv.cell_x[k] = E[k].cell[0];
      lv.particle[k] = E[k].particle;
    }
  for (Index k = small; k < small + 8; ++k) {
    lv.cell_x[k] = std::numeric_limits<std::int32_t>::max();
    lv.particle[k] = small > 0 ? E[0].particle : 0;
  }
  grid.small_chunks = small_chunks;
  grid.E = E;
  grid.start = start;
  grid.cx = lv.cell_x.data();
  grid.pid = lv.particle.data();
}

}  // namespace

template <class Real> void find_cells(Call<Real>& call, Level<Real>& lv, const Vec3<Real>& inv) {
  const Index members = Index(lv.members.size());
  const Index chunks = std::min<Index>(kChunks, members);
  lv.lo.resize(members);
  lv.hi.resize(members);
  lv.key.resize(members);
  lv.bounds.resize(chunks);
  lv.extent.resize(chunks);
  // cells of each box's corners; small, in pieces or large; per chunk the range of the entries' lower cells
  over_chunks(members, call.fork(members), [&](Index ch, Index b, Index e) {
    Cell lo, hi;
    Eigen::Vector3d sum;
    open_range(lo, hi, sum);
    for (Index k = b; k < e; ++k) classify(lv, k, box_of(call.g, lv.members[k], call.frame, call.margin), inv, lo, hi, sum);
    lv.bounds[ch] = {lo, hi};
    lv.extent[ch] = sum;
  });
}

template <class Real> LevelGrid<Real> build_grid(Call<Real>& call, Level<Real>& lv) {
  LevelGrid<Real> grid;
  enter_slots(call, lv);
  grid.small = Index(lv.slots.size());
  lay_out_buckets(lv, grid);
  sort_entries(call, lv, grid);
  return grid;
}

template void find_cells(Call<float>&, Level<float>&, const Vec3<float>&);
template void find_cells(Call<double>&, Level<double>&, const Vec3<double>&);
template LevelGrid<float> build_grid(Call<float>&, Level<float>&);
template LevelGrid<double> build_grid(Call<double>&, Level<double>&);

}  // namespace pbd::detail::contact
