#include "particle_contacts.hpp"

#include "pbd/constraint_types.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace pbd::detail {

template <class Real> void cook_contact_bodies(Model<Real>& m) {
  ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  if (c.cooked && c.body_of.size() == std::size_t(n)) return;
  c.body_of.assign(n, ContactBodies<Real>::kNone);
  c.radius = VectorX<Real>::Zero(n);
  c.material.assign(n, ContactMaterial<Real>{});
  c.max_radius = 0;
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    const ContactBody<Real>& body = c.bodies[b];
    for (Index i = body.first; i < body.first + body.count; ++i) {
      c.body_of[i] = Index(b);
      c.radius[i] = body.radius;
      c.material[i] = body.material;
    }
    c.max_radius = std::max(c.max_radius, body.radius);
  }
  c.active.clear();
  for (Index i = 0; i < n; ++i)
    if (c.radius[i] > Real(0)) c.active.push_back(i);
  c.cooked = true;
}

namespace {

using Cell = std::array<std::int32_t, 3>;

inline bool same(const Cell& a, const Cell& b) { return ((a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2])) == 0; }

template <class Real> inline Cell cell_of(const Vec3<Real>& q, const Vec3<Real>& inv) {
  auto axis = [&](int d) {  // clamped so that a far particle cannot overflow (it only shares a cell more often)
    return std::int32_t(std::clamp(std::floor(q[d] * inv[d]), Real(-1e9), Real(1e9)));
  };
  return {axis(0), axis(1), axis(2)};
}

inline std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t mask) {
  const std::uint64_t h = std::uint64_t(x) * 73856093ull ^ std::uint64_t(y) * 19349663ull ^ std::uint64_t(z) * 83492791ull;
  return std::uint32_t((h ^ (h >> 29)) & mask);
}

// Particles joined to one another by a built-in constraint, both in the same self-colliding body: never in contact.
// Each particle's row lists those above it (pairs are tested as (i, j), i < j).
template <class Real> void build_exclusions(const Model<Real>& m, ParticleGrid<Real>& g) {
  const ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  std::vector<std::pair<Index, Index>> pairs;
  auto self = [&](Index i) { return c.body_of[i] != ContactBodies<Real>::kNone && c.bodies[c.body_of[i]].self_collision; };
  for_each_store(m.stores, [&](const auto& st, auto) {
    for (const auto& con : st.items)
      for (std::size_t a = 0; a < con.particles.size(); ++a)
        for (std::size_t b = 0; b < con.particles.size(); ++b) {
          const Index u = con.particles[a], v = con.particles[b];
          if (u < v && self(u) && c.body_of[u] == c.body_of[v]) pairs.emplace_back(u, v);
        }
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  g.joined_offsets.assign(std::size_t(n) + 1, 0);
  for (const auto& [u, v] : pairs) ++g.joined_offsets[u + 1];
  for (Index i = 0; i < n; ++i) g.joined_offsets[i + 1] += g.joined_offsets[i];
  g.joined.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) g.joined[k] = pairs[k].second;
  g.joined_edits = m.edits;
  g.joined_bodies = c.bodies.size();
}

// The direction from b to a at first contact of the relative path d0 → d1 (radii sum R), or where they are closest.
template <class Real> Vec3<Real> first_contact_normal(const Vec3<Real>& d0, const Vec3<Real>& d1, Real R) {
  const Vec3<Real> e = d1 - d0;
  Vec3<Real> d = d0;
  if (d0.squaredNorm() >= R * R) {  // apart at the start: where |d0 + t·e| first reaches R, if it does
    const Real a = e.squaredNorm(), b = d0.dot(e), c = d0.squaredNorm() - R * R;
    const Real disc = b * b - a * c;
    if (a > Real(0) && disc >= Real(0)) {
      const Real t = (-b - std::sqrt(disc)) / a;
      if (t >= Real(0) && t <= Real(1)) d = d0 + t * e;
      else d = d1;
    } else {
      d = d1;
    }
  }
  if (!(d.squaredNorm() > tiny_squared<Real>())) d = d0;
  if (!(d.squaredNorm() > tiny_squared<Real>())) d = d1;
  if (!(d.squaredNorm() > tiny_squared<Real>())) return Vec3<Real>::UnitZ();
  return d.normalized();
}

constexpr Index kChunks = 64;              // fixed, so the output never depends on the thread count
constexpr std::uint64_t kMaxRows = 4096;   // a larger box whose query spans more rows is paired with every small box
constexpr Index kBruteForce = 64;          // at most this many boxes left: paired with one another
constexpr std::uint32_t kLarge = ~std::uint32_t(0);
// Cells as wide as the boxes are on average along each axis (chosen by measurement on bench_contacts' draped cloth
// and grain lattice: wider cells hold more boxes to pair, narrower ones leave more boxes large). The boxes alone
// decide which pairs are tested, and the test alone which are kept, so the cells change only the cost.
constexpr double kCellScale = 1.0;

// Calls f(chunk, begin, end) for `count` items in min(kChunks, count) fixed chunks, in parallel when `fork`.
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

}  // namespace

template <class Real>
void generate_particle_contacts(const Model<Real>& m, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                const Matrix3X<Real>& v, Real margin, bool parallel, ParticleGrid<Real>& g,
                                std::vector<ParticleContact<Real>>& out) {
  using Entry = typename ParticleGrid<Real>::Entry;
  using Level = typename ParticleGrid<Real>::Level;
  const ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  if (!c.particle_contacts() || n == 0) return;
  bool any_self = false;
  for (const auto& b : c.bodies) any_self = any_self || (b.self_collision && b.radius > Real(0));
  if (any_self && (g.joined_edits != m.edits || g.joined_bodies != c.bodies.size() ||
                   g.joined_offsets.size() != std::size_t(n) + 1))
    build_exclusions(m, g);
  const std::vector<Index>& active = c.active;
  const Index count = Index(active.size());
  if (count == 0) return;
  // Loops run in fixed chunks (over_chunks): whatever a chunk computes depends on its items only, and chunk results
  // are joined in chunk order, so nothing depends on threads.
  auto fork = [&](Index items) { return parallel && items >= 4096; };
  // 2. swept boxes in the frame that moves with the mean path Δ̄ (relative paths, all a pair test reads, are the
  // same there; a falling cloth's boxes stay short)
  g.partial.resize(kChunks);
  over_chunks(count, fork(count), [&](Index ch, Index b, Index e) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index k = b; k < e; ++k) sum += (p.col(active[k]) - x.col(active[k])).template cast<double>();
    g.partial[ch] = sum;
  });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) mean += g.partial[ch];
  const Vec3<Real> shared = (mean / double(count)).template cast<Real>();
  g.movers.resize(n);
  g.boxes.resize(n);
  over_chunks(count, fork(count), [&](Index ch, Index b, Index e) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index k = b; k < e; ++k) {
      const Index i = active[k];
      const Vec3<Real> from = x.col(i), to = p.col(i) - shared;
      const Real grow = c.radius[i] + Real(0.5) * margin;
      const Index body = c.body_of[i];
      g.movers[i] = {x.col(i), p.col(i), c.radius[i], m.inverse_mass[i] == Real(0)};
      Entry& box = g.boxes[i];
      box.lo = from.cwiseMin(to).array() - grow;
      box.hi = from.cwiseMax(to).array() + grow;
      box.particle = i;
      box.group = c.bodies[body].self_collision ? ContactBodies<Real>::kNone : body;
      sum += (box.hi - box.lo).template cast<double>();
    }
    g.partial[ch] = sum;
  });
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) extent += g.partial[ch];
  Eigen::Vector3d width = kCellScale * extent / double(count);
  // 4. the pair test: the boxes must overlap, then the relative path must come within reach
  const typename ParticleGrid<Real>::Mover* P = g.movers.data();
  auto test_pair = [&](Index i, Index j, std::vector<ParticleContact<Real>>& mine) {  // i < j
    const auto& a = P[i];
    const auto& b = P[j];
    if (a.pinned && b.pinned) return;
    const Real R = a.radius + b.radius;
    const Vec3<Real> d0 = a.x - b.x, d1 = a.p - b.p;
    const Vec3<Real> e = d1 - d0;
    // closest approach of d0 + t·e, t ∈ [0, 1], within R + margin (without a division)
    const Real ee = e.squaredNorm(), de = d0.dot(e), reach = (R + margin) * (R + margin);
    const Real q0 = d0.squaredNorm();
    const bool ahead = de >= Real(0), past = -de >= ee;  // closest at t = 0, at t = 1 (else between)
    const bool near = (ahead & (q0 < reach)) | (!ahead & past & (d1.squaredNorm() < reach)) |
                      (!ahead & !past & (q0 * ee - de * de < reach * ee));  // bitwise: no branch to mispredict
    if (!near) return;
    const Index bi = c.body_of[i];
    if (c.body_of[j] == bi) {  // within a body: only if it self-collides and no constraint joins the two
      if (!c.bodies[bi].self_collision) return;
      for (Index k = g.joined_offsets[i]; k < g.joined_offsets[i + 1] && g.joined[k] <= j; ++k)  // sorted row
        if (g.joined[k] == j) return;
    }
    const Vec3<Real> nrm = first_contact_normal(d0, d1, R);
    mine.push_back({{i, j}, nrm, R, d0, nrm.dot(Vec3<Real>(v.col(i) - v.col(j))),
                    mix_materials(c.material[i], c.material[j])});
  };
  auto candidate = [&](const Entry& a, const Entry& b, std::vector<ParticleContact<Real>>& mine) {
    if (a.group == b.group && a.group != ContactBodies<Real>::kNone) return;  // one body, no self-collision
    if (((a.lo.array() > b.hi.array()) || (b.lo.array() > a.hi.array())).any()) return;  // boxes apart
    test_pair(std::min(a.particle, b.particle), std::max(a.particle, b.particle), mine);
  };
  std::size_t lists = 0;  // contact lists used so far
  auto take_lists = [&](std::size_t k) {
    if (g.lists.size() < lists + k) g.lists.resize(lists + k);
    for (std::size_t l = lists; l < lists + k; ++l) g.lists[l].clear();
    lists += k;
    return lists - k;
  };
  // 3. level by level
  if (g.levels.empty()) g.levels.resize(1);
  g.levels[0].members.assign(active.begin(), active.end());
  for (std::size_t level = 0;; ++level) {
    if (g.levels.size() < level + 2) g.levels.resize(level + 2);
    Level& lv = g.levels[level];
    const Index members = Index(lv.members.size());
    if (members <= kBruteForce) {  // few left: each with each
      std::vector<ParticleContact<Real>>& mine = g.lists[take_lists(1)];
      for (Index a = 0; a < members; ++a)
        for (Index b = a + 1; b < members; ++b) candidate(g.boxes[lv.members[a]], g.boxes[lv.members[b]], mine);
      break;
    }
    const Vec3<Real> inv = width.cwiseInverse().template cast<Real>();
    const Index chunks = std::min<Index>(kChunks, members);
    lv.lo.resize(members);
    lv.hi.resize(members);
    lv.key.resize(members);
    lv.bounds.resize(chunks);
    lv.extent.resize(chunks);
    // cells of each box's corners; small or large; per chunk the range of the small boxes' lower cells
    over_chunks(members, fork(members), [&](Index ch, Index b, Index e) {
      constexpr std::int32_t top = std::numeric_limits<std::int32_t>::max(), bottom = std::numeric_limits<std::int32_t>::min();
      Cell lo{top, top, top}, hi{bottom, bottom, bottom};
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (Index k = b; k < e; ++k) {
        const Entry& box = g.boxes[lv.members[k]];
        const Cell a = cell_of<Real>(box.lo, inv), z = cell_of<Real>(box.hi, inv);
        lv.lo[k] = a;
        lv.hi[k] = z;
        const bool small = std::int64_t(z[0]) - a[0] <= 1 && std::int64_t(z[1]) - a[1] <= 1 && std::int64_t(z[2]) - a[2] <= 1;
        lv.key[k] = small ? 0 : kLarge;
        if (!small) {
          sum += (box.hi - box.lo).template cast<double>();
          continue;
        }
        for (int d = 0; d < 3; ++d) {
          lo[d] = std::min(lo[d], a[d]);
          hi[d] = std::max(hi[d], a[d]);
        }
      }
      lv.bounds[ch] = {lo, hi};
      lv.extent[ch] = sum;
    });
    lv.large.clear();
    Index small = 0;
    for (Index k = 0; k < members; ++k) {
      if (lv.key[k] == kLarge) lv.large.push_back(lv.members[k]);
      else ++small;
    }
    // buckets: rows of cells along x, keyed by (y, z): the rows of the small boxes' lower corners' bounding grid
    // grown by one row on every side (so that a neighbouring row's bucket is the box's own plus a fixed step), y
    // fastest, when there are at most 8 rows per small box; else a hash table of about twice as many buckets as small
    // boxes. Within a bucket the boxes are sorted by cell (z, y, x), then particle: a row's boxes lie together, in x
    // order.
    Cell base{0, 0, 0};
    std::array<std::int64_t, 3> dims{0, 0, 0};
    if (small > 0) {
      Cell lo = lv.bounds[0].first, hi = lv.bounds[0].second;
      for (Index ch = 1; ch < chunks; ++ch)
        for (int d = 0; d < 3; ++d) {
          lo[d] = std::min(lo[d], lv.bounds[ch].first[d]);
          hi[d] = std::max(hi[d], lv.bounds[ch].second[d]);
        }
      for (int d = 1; d < 3; ++d) {
        base[d] = lo[d] - 1;  // cells are clamped to ±1e9: no overflow
        dims[d] = std::int64_t(hi[d]) - lo[d] + 3;
      }
    }
    const std::uint64_t dense_rows = std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
    const bool dense = small > 0 && dense_rows <= 8 * std::uint64_t(small) && dense_rows < (1ull << 31);
    std::uint32_t buckets = 1;
    if (dense) {
      buckets = std::uint32_t(dense_rows);
    } else {
      while (buckets < 2 * std::uint64_t(small)) buckets <<= 1;
    }
    const std::uint32_t mask = buckets - 1;
    auto bucket_of = [&](std::int32_t y, std::int32_t z) -> std::uint32_t {
      if (dense) return std::uint32_t((std::int64_t(z) - base[2]) * dims[1] + (std::int64_t(y) - base[1]));
      return hash_cell(0, y, z, mask);
    };
    if (small > 0)
      over_chunks(members, fork(members), [&](Index, Index b, Index e) {
        for (Index k = b; k < e; ++k)
          if (lv.key[k] != kLarge) lv.key[k] = bucket_of(lv.lo[k][1], lv.lo[k][2]);
      });
    // counting sort of the small boxes by bucket, then each bucket sorted by (cell z, y, x, particle)
    lv.bucket_start.assign(std::size_t(buckets) + 1, 0);
    for (Index k = 0; k < members; ++k)
      if (lv.key[k] != kLarge) ++lv.bucket_start[lv.key[k] + 1];
    for (std::uint32_t b = 0; b < buckets; ++b) lv.bucket_start[b + 1] += lv.bucket_start[b];
    lv.entries.resize(small);
    lv.fill.assign(lv.bucket_start.begin(), lv.bucket_start.end() - 1);
    for (Index k = 0; k < members; ++k) {
      if (lv.key[k] == kLarge) continue;
      Entry& to = lv.entries[lv.fill[lv.key[k]]++];
      to = g.boxes[lv.members[k]];
      to.cell = lv.lo[k];
    }
    Entry* E = lv.entries.data();
    const Index* start = lv.bucket_start.data();
    auto before = [](const Entry& a, const Entry& b) {
      if (a.cell[2] != b.cell[2]) return a.cell[2] < b.cell[2];
      if (a.cell[1] != b.cell[1]) return a.cell[1] < b.cell[1];
      if (a.cell[0] != b.cell[0]) return a.cell[0] < b.cell[0];
      return a.particle < b.particle;
    };
    const Index small_chunks = std::min<Index>(kChunks, std::max<Index>(small, 1));
    lv.cut.resize(std::size_t(small_chunks) + 1);
    for (Index ch = 0; ch < small_chunks; ++ch)  // chunk ch: the buckets from the first at or after entry ch·small/chunks
      lv.cut[ch] = Index(std::lower_bound(lv.bucket_start.begin(), lv.bucket_start.end() - 1,
                                          Index(std::uint64_t(ch) * small / small_chunks)) - lv.bucket_start.begin());
    lv.cut[small_chunks] = buckets;
    if (small > 1)
      over_chunks(small_chunks, fork(small), [&](Index ch, Index, Index) {
        for (Index b = lv.cut[ch]; b < lv.cut[ch + 1]; ++b) {
          Entry* first = E + start[b];
          Entry* last = E + start[b + 1];
          if (last - first <= 24) {  // insertion sort: a row of particles added in x order is sorted already
            for (Entry* q = first + 1; q < last; ++q)
              for (Entry* r = q; r > first && before(*r, *(r - 1)); --r) std::swap(*r, *(r - 1));
          } else {
            std::sort(first, last, before);
          }
        }
      });
    // the boxes of row (y, z) in bucket `nb` from cell x0 on: [from, end of the row)
    auto row_from = [&](std::uint32_t nb, std::int32_t y, std::int32_t z, std::int32_t x0) {
      Entry probe;
      probe.cell = {x0, y, z};
      probe.particle = 0;
      return Index(std::lower_bound(E + start[nb], E + start[nb + 1], probe, before) - E);
    };
    auto in_row = [&](const Entry& e, std::int32_t y, std::int32_t z) { return e.cell[1] == y && e.cell[2] == z; };
    // small with small: each box with those after it in its cell and the next cell along x, and with those in the
    // neighbouring cells of the rows (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1): the 13 of the 26
    // neighbouring cells that come after its own, so each pair once
    if (small > 1) {
      static constexpr std::array<std::array<std::int32_t, 2>, 4> kRows = {{{1, 0}, {-1, 1}, {0, 1}, {1, 1}}};
      const std::size_t first = take_lists(std::size_t(small_chunks));
      over_chunks(small_chunks, fork(small), [&](Index ch, Index, Index) {
        std::vector<ParticleContact<Real>>& mine = g.lists[first + ch];
        for (Index b = lv.cut[ch]; b < lv.cut[ch + 1]; ++b) {
          const Index s1 = start[b + 1];
          for (Index r0 = start[b], r1; r0 < s1; r0 = r1) {  // one row at a time: [r0, r1)
            const std::int32_t y = E[r0].cell[1], z = E[r0].cell[2];
            for (r1 = r0 + 1; r1 < s1 && in_row(E[r1], y, z); ++r1) {}
            for (Index s = r0; s < r1; ++s)  // its own cell (after s) and the next along x
              for (Index t = s + 1; t < r1 && E[t].cell[0] <= E[s].cell[0] + 1; ++t) candidate(E[s], E[t], mine);
            for (const auto& r : kRows) {  // each neighbouring row, walked along with this one
              const std::int32_t ny = y + r[0], nz = z + r[1];
              const std::uint32_t nb = bucket_of(ny, nz);
              Index w = start[nb], w1 = start[nb + 1];  // dense: the bucket is the row
              if (!dense) {
                w = row_from(nb, ny, nz, E[r0].cell[0] - 1);
                for (w1 = w; w1 < start[nb + 1] && in_row(E[w1], ny, nz); ++w1) {}
              }
              for (Index s = r0; s < r1 && w < w1; ++s) {
                const std::int32_t x = E[s].cell[0];
                while (w < w1 && E[w].cell[0] < x - 1) ++w;
                for (Index t = w; t < w1 && E[t].cell[0] <= x + 1; ++t) candidate(E[s], E[t], mine);
              }
            }
          }
        }
      });
    }
    // large with small: each large box with the small boxes whose lower corners lie in its cells or one cell below
    // (a small box that overlaps it has its lower corner there), or with every small box when that is too many rows
    const Index large = Index(lv.large.size());
    if (large > 0 && small > 0) {
      const std::size_t first = take_lists(std::size_t(std::min<Index>(kChunks, large)));
      over_chunks(large, fork(large), [&](Index ch, Index b, Index e) {
        std::vector<ParticleContact<Real>>& mine = g.lists[first + ch];
        for (Index k = b; k < e; ++k) {
          const Entry& box = g.boxes[lv.large[k]];
          Cell lo = cell_of<Real>(box.lo, inv), hi = cell_of<Real>(box.hi, inv);
          std::uint64_t rows = 1;
          for (int d = 0; d < 3; ++d) lo[d] -= 1;
          for (int d = 1; d < 3; ++d) {
            if (dense) {  // only the grid's rows hold boxes
              lo[d] = std::int32_t(std::max<std::int64_t>(lo[d], base[d]));
              hi[d] = std::int32_t(std::min<std::int64_t>(hi[d], base[d] + dims[d] - 1));
            }
            rows *= std::uint64_t(std::max<std::int64_t>(0, std::int64_t(hi[d]) - lo[d] + 1));
          }
          if (rows > kMaxRows) {
            for (Index t = 0; t < small; ++t) candidate(box, E[t], mine);
            continue;
          }
          for (std::int32_t cz = lo[2]; cz <= hi[2]; ++cz)
            for (std::int32_t cy = lo[1]; cy <= hi[1]; ++cy) {
              const std::uint32_t nb = bucket_of(cy, cz);
              for (Index t = row_from(nb, cy, cz, lo[0]); t < start[nb + 1] && in_row(E[t], cy, cz) && E[t].cell[0] <= hi[0]; ++t)
                candidate(box, E[t], mine);
            }
        }
      });
    }
    if (large == 0) break;
    // the large boxes form the next level, with cells at least twice as wide and as wide as they are on average
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index ch = 0; ch < chunks; ++ch) sum += lv.extent[ch];
    width = (2.0 * width).cwiseMax(kCellScale * sum / double(large));
    g.levels[level + 1].members.swap(lv.large);
  }
  // 5. in the order of the pairs (i, j): a counting sort by i of the lists, then by j among each i's few. The list
  // is then the same whatever the grid's cells, and Gauss-Seidel meets a pile's contacts in particle order
  // (measured on contact_test's pile, 4 × 10: worst overlap 1.3% serial in that order, 2.3% in bucket order).
  g.first_of.assign(std::size_t(n) + 1, 0);
  std::size_t found = 0;
  for (std::size_t l = 0; l < lists; ++l) {
    found += g.lists[l].size();
    for (const auto& k : g.lists[l]) ++g.first_of[k.particles[0] + 1];
  }
  for (Index i = 0; i < n; ++i) g.first_of[i + 1] += g.first_of[i];
  const std::size_t before = out.size();
  out.resize(before + found);
  ParticleContact<Real>* to = out.data() + before;
  for (std::size_t l = 0; l < lists; ++l)
    for (const auto& k : g.lists[l]) to[g.first_of[k.particles[0]]++] = k;  // first_of[i] ends where i's contacts end
  Index begin = 0;
  for (Index i = 0; i < n; ++i) {
    const Index end = g.first_of[i];
    if (end - begin > 1)
      std::sort(to + begin, to + end, [](const auto& a, const auto& b) { return a.particles[1] < b.particles[1]; });
    begin = end;
  }
}

template void cook_contact_bodies(Model<float>&);
template void cook_contact_bodies(Model<double>&);
template void generate_particle_contacts(const Model<float>&, const Matrix3X<float>&, const Matrix3X<float>&,
                                         const Matrix3X<float>&, float, bool, ParticleGrid<float>&,
                                         std::vector<ParticleContact<float>>&);
template void generate_particle_contacts(const Model<double>&, const Matrix3X<double>&, const Matrix3X<double>&,
                                         const Matrix3X<double>&, double, bool, ParticleGrid<double>&,
                                         std::vector<ParticleContact<double>>&);

}  // namespace pbd::detail
