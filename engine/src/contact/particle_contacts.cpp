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

template <class Real> Cell cell_of(const Vec3<Real>& q, const Vec3<Real>& inv) {
  auto axis = [&](int d) {  // clamped so that a far particle cannot overflow (it only shares a cell more often)
    return std::int32_t(std::clamp(std::floor(q[d] * inv[d]), Real(-1e9), Real(1e9)));
  };
  return {axis(0), axis(1), axis(2)};
}

std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t mask) {
  const std::uint64_t h = std::uint64_t(x) * 73856093ull ^ std::uint64_t(y) * 19349663ull ^ std::uint64_t(z) * 83492791ull;
  return std::uint32_t((h ^ (h >> 29)) & mask);
}

// Particles joined to one another by a built-in constraint, both in the same self-colliding body: never in contact.
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
          if (u != v && self(u) && c.body_of[u] == c.body_of[v]) pairs.emplace_back(u, v);
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

constexpr Index kChunks = 64;  // fixed, so the output never depends on the thread count
constexpr std::uint64_t kMaxCells = 4096;  // a swept box over more cells is tested against every particle

}  // namespace

template <class Real>
void generate_particle_contacts(const Model<Real>& m, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                const Matrix3X<Real>& v, Real margin, bool parallel, ParticleGrid<Real>& g,
                                std::vector<ParticleContact<Real>>& out) {
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
  // Loops over the active particles in kChunks fixed chunks, in parallel when asked: whatever a chunk computes
  // depends on its particles only, and chunk results are joined in chunk order, so nothing depends on threads.
  const Index chunks = std::min<Index>(kChunks, count);
  const bool fork = parallel && count >= 4096;
  auto over_chunks = [&](const auto& f) {
    if (fork)
      tbb::parallel_for(tbb::blocked_range<Index>(0, chunks, 1), [&](const tbb::blocked_range<Index>& r) {
        for (Index ch = r.begin(); ch < r.end(); ++ch) f(ch);
      });
    else
      for (Index ch = 0; ch < chunks; ++ch) f(ch);
  };
  auto first_of = [&](Index ch) { return Index(std::uint64_t(ch) * count / chunks); };
  // 2. swept boxes in the frame that moves with the mean path Δ̄ (relative paths, all a pair test reads, are the
  // same there; a falling cloth's boxes stay short)
  g.partial.resize(2 * std::size_t(chunks));
  over_chunks([&](Index ch) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index k = first_of(ch); k < first_of(ch + 1); ++k) sum += (p.col(active[k]) - x.col(active[k])).template cast<double>();
    g.partial[ch] = sum;
  });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < chunks; ++ch) mean += g.partial[ch];
  const Vec3<Real> shared = (mean / double(count)).template cast<Real>();
  over_chunks([&](Index ch) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index k = first_of(ch); k < first_of(ch + 1); ++k)
      sum += (p.col(active[k]) - x.col(active[k]) - shared).template cast<double>().cwiseAbs();
    g.partial[ch] = sum;
  });
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < chunks; ++ch) spread += g.partial[ch];
  // Cells 1.5·(2·r_max + margin) wide, stretched along each axis by three times the paths' mean departure from Δ̄
  // along it, whichever way the bodies move (chosen by measurement on bench_contacts' draped cloth: cells as wide as
  // a box give each box more entries to sort, cells twice as wide more pairs per cell to check). The boxes alone
  // decide which pairs are tested, and the test alone which are kept, so the cells change only the cost and the
  // order of the list.
  const Vec3<Real> inv = (Real(1.5) * (Real(2) * c.max_radius + margin +
                                       Real(2) * (spread / double(count)).template cast<Real>().array()))
                             .cwiseInverse()
                             .matrix();
  // each box's cell range, the cells it covers (0: too many, tested against every particle instead) and, per
  // chunk, the range of cells its boxes cover
  g.lo.resize(n);
  g.hi.resize(n);
  g.cells.resize(count);
  g.movers.resize(n);
  g.chunk_bounds.resize(chunks);
  over_chunks([&](Index ch) {
    Cell lo{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max()};
    Cell hi{std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min()};
    for (Index k = first_of(ch); k < first_of(ch + 1); ++k) {
      const Index i = active[k];
      const Vec3<Real> a = x.col(i), b = p.col(i) - shared;
      const Real grow = c.radius[i] + Real(0.5) * margin;
      g.movers[i] = {x.col(i), p.col(i), c.radius[i], m.inverse_mass[i] == Real(0),
                     Vec3<Real>(a.cwiseMin(b).array() - grow), Vec3<Real>(a.cwiseMax(b).array() + grow)};
      g.lo[i] = cell_of<Real>(Vec3<Real>(a.cwiseMin(b).array() - grow), inv);
      g.hi[i] = cell_of<Real>(Vec3<Real>(a.cwiseMax(b).array() + grow), inv);
      std::uint64_t cells = 1;
      for (int d = 0; d < 3; ++d) cells *= std::uint64_t(std::int64_t(g.hi[i][d]) - g.lo[i][d] + 1);
      g.cells[k] = cells > kMaxCells ? 0 : std::uint32_t(cells);
      if (cells > kMaxCells) continue;
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], g.lo[i][d]);
        hi[d] = std::max(hi[d], g.hi[i][d]);
      }
    }
    g.chunk_bounds[ch] = {lo, hi};
  });
  g.huge.clear();
  std::size_t entries = 0;
  for (Index k = 0; k < count; ++k) {
    if (g.cells[k] == 0) g.huge.push_back(active[k]);
    entries += g.cells[k];
  }
  // Buckets: the cells of the boxes' bounding grid in x-fastest order when it has at most 8 cells per entry, else
  // a hash table of about twice as many buckets as entries.
  Cell base{0, 0, 0};
  std::array<std::int64_t, 3> dims{0, 0, 0};
  {
    Cell lo = g.chunk_bounds[0].first, hi = g.chunk_bounds[0].second;
    for (Index ch = 1; ch < chunks; ++ch)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], g.chunk_bounds[ch].first[d]);
        hi[d] = std::max(hi[d], g.chunk_bounds[ch].second[d]);
      }
    base = lo;
    for (int d = 0; d < 3; ++d) dims[d] = std::max<std::int64_t>(0, std::int64_t(hi[d]) - lo[d] + 1);
  }
  const std::uint64_t dense_cells = std::uint64_t(dims[0]) * std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
  const bool dense = entries > 0 && dense_cells <= 8 * std::uint64_t(entries) && dense_cells < (1ull << 31);
  std::uint32_t buckets = 1;
  if (dense) {
    buckets = std::uint32_t(dense_cells);
  } else {
    while (buckets < 2 * entries) buckets <<= 1;
  }
  const std::uint32_t mask = buckets - 1;
  auto bucket_of = [&](const Cell& q) -> std::uint32_t {
    if (dense)
      return std::uint32_t(((std::int64_t(q[2]) - base[2]) * dims[1] + (std::int64_t(q[1]) - base[1])) * dims[0] +
                           (std::int64_t(q[0]) - base[0]));
    return hash_cell(q[0], q[1], q[2], mask);
  };
  auto for_each_cell = [&](Index i, const auto& f) {
    for (std::int32_t cz = g.lo[i][2]; cz <= g.hi[i][2]; ++cz)
      for (std::int32_t cy = g.lo[i][1]; cy <= g.hi[i][1]; ++cy)
        for (std::int32_t cx = g.lo[i][0]; cx <= g.hi[i][0]; ++cx) f(Cell{cx, cy, cz});
  };
  // counting sort of (particle, cell) by bucket, particle order within a bucket; each entry notes along which axes
  // its cell is the box's first (lower) one
  g.bucket_start.assign(std::size_t(buckets) + 1, 0);
  for (Index k = 0; k < count; ++k)
    if (g.cells[k] != 0) for_each_cell(active[k], [&](const Cell& q) { ++g.bucket_start[bucket_of(q) + 1]; });
  for (std::uint32_t b = 0; b < buckets; ++b) g.bucket_start[b + 1] += g.bucket_start[b];
  g.entries.resize(entries);
  g.fill.assign(g.bucket_start.begin(), g.bucket_start.end() - 1);
  for (Index k = 0; k < count; ++k) {
    if (g.cells[k] == 0) continue;
    const Index i = active[k];
    const Cell lo = g.lo[i];
    const Index body = c.body_of[i];
    const Index group = c.bodies[body].self_collision ? ContactBodies<Real>::kNone : body;
    for_each_cell(i, [&](const Cell& q) {
      const std::uint8_t lower = std::uint8_t((q[0] == lo[0] ? 1 : 0) | (q[1] == lo[1] ? 2 : 0) | (q[2] == lo[2] ? 4 : 0));
      g.entries[g.fill[bucket_of(q)]++] = {i, group, lower, q};
    });
  }
  // 3. pairs: in every bucket, each two entries of one cell; the pair is tested there when that cell is the first
  // the two boxes share, the larger of their lower corners, i.e. when along each axis the cell is the lower one of
  // one box or the other, so each pair once
  // The pair test reads each particle's packed copy (filled with the boxes above).
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
    bool near;
    if (de >= Real(0)) near = d0.squaredNorm() < reach;
    else if (-de >= ee) near = d1.squaredNorm() < reach;
    else near = d0.squaredNorm() * ee - de * de < reach * ee;
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
  // chunk ch takes the buckets from the first one at or after entry ch·entries/chunks
  g.bucket_cut.resize(std::size_t(chunks) + 1);
  for (Index ch = 0; ch < chunks; ++ch)
    g.bucket_cut[ch] = Index(std::lower_bound(g.bucket_start.begin(), g.bucket_start.end() - 1,
                                              Index(std::uint64_t(ch) * entries / chunks)) - g.bucket_start.begin());
  g.bucket_cut[chunks] = buckets;
  g.chunks.resize(std::size_t(chunks) + 1);
  const auto* E = g.entries.data();
  over_chunks([&](Index ch) {
    std::vector<ParticleContact<Real>>& mine = g.chunks[ch];
    mine.clear();
    for (Index b = g.bucket_cut[ch]; b < g.bucket_cut[ch + 1]; ++b) {
      const Index s1 = g.bucket_start[b + 1];
      for (Index s = g.bucket_start[b]; s + 1 < s1; ++s) {
        const auto& ea = E[s];
        for (Index t = s + 1; t < s1; ++t) {
          const auto& eb = E[t];
          if ((ea.lower | eb.lower) != 7) continue;
          if (ea.group == eb.group && ea.group != ContactBodies<Real>::kNone) continue;  // one body, no self-collision
          if (!dense && ea.cell != eb.cell) continue;
          const auto& ma = P[ea.particle];
          const auto& mb = P[eb.particle];
          if (((ma.lo.array() > mb.hi.array()) || (mb.lo.array() > ma.hi.array())).any()) continue;  // boxes apart
          test_pair(ea.particle, eb.particle, mine);  // ea.particle < eb.particle: particle order in a bucket
        }
      }
    }
  });
  // particles whose boxes span too many cells (far faster than the rest): against every other particle, by box
  std::vector<ParticleContact<Real>>& rest = g.chunks[chunks];
  rest.clear();
  for (Index i : g.huge)
    for (Index j : active) {
      if (j == i || (j < i && std::binary_search(g.huge.begin(), g.huge.end(), j))) continue;  // huge pairs once
      bool overlap = true;
      for (int d = 0; d < 3; ++d) overlap = overlap && g.lo[i][d] <= g.hi[j][d] && g.lo[j][d] <= g.hi[i][d];
      if (overlap) test_pair(std::min(i, j), std::max(i, j), rest);
    }
  // 4. in the order of the pairs (i, j): a counting sort by i of the chunks' lists, then by j among each i's few.
  // The list is then the same whatever the grid's cells, and Gauss-Seidel meets a pile's contacts in particle order
  // (measured on contact_test's pile, 4 × 10: worst overlap 1.3% serial in that order, 2.3% in bucket order).
  g.first_of.assign(std::size_t(n) + 1, 0);
  std::size_t found = 0;
  for (const auto& ch : g.chunks) {
    found += ch.size();
    for (const auto& k : ch) ++g.first_of[k.particles[0] + 1];
  }
  for (Index i = 0; i < n; ++i) g.first_of[i + 1] += g.first_of[i];
  const std::size_t before = out.size();
  out.resize(before + found);
  ParticleContact<Real>* to = out.data() + before;
  for (const auto& ch : g.chunks)
    for (const auto& k : ch) to[g.first_of[k.particles[0]]++] = k;  // first_of[i] ends where i's contacts end
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
