#include "particle_contacts.hpp"

#include "pbd/constraint_types.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
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
  c.cooked = true;
}

namespace {

using Cell = std::array<std::int32_t, 3>;

template <class Real> Cell cell_of(const Vec3<Real>& q, Real inv) {
  auto axis = [&](Real u) {  // clamped so that a far particle cannot overflow (it only shares a cell more often)
    return std::int32_t(std::clamp(std::floor(u * inv), Real(-1e9), Real(1e9)));
  };
  return {axis(q.x()), axis(q.y()), axis(q.z())};
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
  g.active.clear();
  for (Index i = 0; i < n; ++i)
    if (c.radius[i] > Real(0)) g.active.push_back(i);
  const Index count = Index(g.active.size());
  // 2. the grid over p: two particles whose paths come within r_i + r_j + margin end within r_i + r_j + margin +
  // |Δ_i − Δ_j| of each other (Δ = p − x), and |Δ_i − Δ_j| ≤ 2·s_max, s_max the largest |Δ − Δ̄| about the mean
  // path Δ̄; with cells 2·r_max + margin + 2·s_max wide they end in the same or neighbouring cells. (About the mean:
  // a falling cloth moves far in a sub-step, but its particles move nearly alike.)
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // one thread, particle order: the same bits on any thread count
  for (Index i : g.active) mean += (p.col(i) - x.col(i)).template cast<double>();
  const Vec3<Real> shared = (mean / double(std::max<Index>(1, count))).template cast<Real>();
  Real s_max2 = 0;
  for (Index i : g.active) s_max2 = std::max(s_max2, Real((p.col(i) - x.col(i) - shared).squaredNorm()));
  const Real cell = Real(2) * c.max_radius + margin + Real(2) * std::sqrt(s_max2);
  const Real inv = Real(1) / cell;
  std::uint32_t buckets = 1;
  while (buckets < 2 * std::uint32_t(count)) buckets <<= 1;
  const std::uint32_t mask = buckets - 1;
  g.bucket_start.assign(std::size_t(buckets) + 1, 0);
  g.bucket_of.resize(count);
  g.cell.resize(n);
  for (Index k = 0; k < count; ++k) {
    const Index i = g.active[k];
    const Cell q = cell_of<Real>(p.col(i), inv);
    g.cell[i] = q;
    g.bucket_of[k] = hash_cell(q[0], q[1], q[2], mask);
    ++g.bucket_start[g.bucket_of[k] + 1];
  }
  for (std::uint32_t b = 0; b < buckets; ++b) g.bucket_start[b + 1] += g.bucket_start[b];
  g.bucket_items.resize(count);
  {
    std::vector<Index> fill(g.bucket_start.begin(), g.bucket_start.end() - 1);
    for (Index k = 0; k < count; ++k) g.bucket_items[fill[g.bucket_of[k]]++] = g.active[k];
  }
  // 3. pairs: particle i takes the particles j > i of its own cell and every particle of the 13 cells after it
  // (a pair in two cells is found once, from the earlier cell), checked against their exact cells (hash
  // collisions would find a pair twice)
  const Index chunks = std::min<Index>(kChunks, std::max<Index>(1, count));
  g.chunks.resize(chunks);
  auto chunk = [&](Index ch) {
    std::vector<ParticleContact<Real>>& mine = g.chunks[ch];
    mine.clear();
    const Index kb = Index(std::uint64_t(ch) * count / chunks), ke = Index(std::uint64_t(ch + 1) * count / chunks);
    for (Index k = kb; k < ke; ++k) {
      const Index i = g.active[k];
      const Cell ci = g.cell[i];
      const Vec3<Real> xi = x.col(i), pi = p.col(i);
      const Real ri = c.radius[i];
      const Index bi = c.body_of[i];
      for (int dx = 0; dx <= 1; ++dx)
        for (int dy = dx ? -1 : 0; dy <= 1; ++dy)
          for (int dz = (dx || dy) ? -1 : 0; dz <= 1; ++dz) {
            const Cell cj = {ci[0] + dx, ci[1] + dy, ci[2] + dz};
            const bool same = dx == 0 && dy == 0 && dz == 0;
            const std::uint32_t b = hash_cell(cj[0], cj[1], cj[2], mask);
            for (Index s = g.bucket_start[b]; s < g.bucket_start[b + 1]; ++s) {
              const Index j = g.bucket_items[s];
              const Cell& cell_j = g.cell[j];
              if ((same && j <= i) || cell_j[0] != cj[0] || cell_j[1] != cj[1] || cell_j[2] != cj[2]) continue;
              if (m.inverse_mass[i] == Real(0) && m.inverse_mass[j] == Real(0)) continue;
              if (c.body_of[j] == bi) {
                if (!c.bodies[bi].self_collision) continue;
                const Index* row = g.joined.data() + g.joined_offsets[i];
                const Index* row_end = g.joined.data() + g.joined_offsets[i + 1];
                if (std::binary_search(row, row_end, j)) continue;
              }
              const Real R = ri + c.radius[j];
              const Vec3<Real> d0 = xi - x.col(j), d1 = pi - p.col(j);
              const Vec3<Real> e = d1 - d0;
              const Real ee = e.squaredNorm();
              const Real t = ee > Real(0) ? std::clamp(-d0.dot(e) / ee, Real(0), Real(1)) : Real(0);
              if ((d0 + t * e).squaredNorm() >= (R + margin) * (R + margin)) continue;
              const Vec3<Real> nrm = first_contact_normal(d0, d1, R);
              const ContactMaterial<Real> mat = mix_materials(c.material[i], c.material[j]);
              if (i < j) mine.push_back({{i, j}, nrm, R, d0, nrm.dot(Vec3<Real>(v.col(i) - v.col(j))), mat});
              else mine.push_back({{j, i}, -nrm, R, -d0, nrm.dot(Vec3<Real>(v.col(i) - v.col(j))), mat});
            }
          }
    }
  };
  if (parallel && count >= 2048) {
    tbb::parallel_for(tbb::blocked_range<Index>(0, chunks, 1), [&](const tbb::blocked_range<Index>& r) {
      for (Index ch = r.begin(); ch < r.end(); ++ch) chunk(ch);
    });
  } else {
    for (Index ch = 0; ch < chunks; ++ch) chunk(ch);
  }
  // 4. joined in chunk order
  std::size_t total = out.size();
  for (const auto& ch : g.chunks) total += ch.size();
  out.reserve(total);
  for (const auto& ch : g.chunks) out.insert(out.end(), ch.begin(), ch.end());
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
