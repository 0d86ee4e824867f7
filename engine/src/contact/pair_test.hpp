#pragma once
// The pair test of the particle contacts (private to contact/; particle_contacts.hpp, phase 4): a particle against the
// candidates gathered for it, four at a time with SSE2 (eight with AVX2: near_avx2.hpp), one at a time otherwise, all
// giving the same bits; then the near pairs joined by a constraint are masked out, and a contact is made of each pair
// that is kept. The walk (walk.cpp) gathers the candidates.
#include "budget.hpp"
#include "near_avx2.hpp"
#include "particle_contacts.hpp"
#include "phases.hpp"

#include "simd/wide.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

namespace pbd::detail::contact {

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

// The particles one particle (a) is to be tested against, gathered so that they are tested together (near_bits).
struct Others {
  static constexpr std::uint32_t kSize = 64;
  Index a = 0;
  std::uint32_t size = 0;
  std::array<Index, kSize + 8> of;  // [size, size + 8) padded with a, for the four- or eight-lane test
};

// Of the candidates `near` marks (bit k for o.of[k], k < o.size), those in a's row of joined particles [first, last)
// (a whole number of groups of four, padded with kNone, nearest first). The row's first kJoinedFirstGroups groups are
// compared with every candidate; the rest of the row only when a near candidate is left unmatched. o.of is padded
// with o.a past o.size (near_bits), which is never in its own row.
inline std::uint64_t joined_bits(const Index* first, const Index* last, const Others& o, std::uint64_t near) {
  std::uint64_t bits = 0;
  if (first == last) return bits;
#if defined(__SSE2__)
  auto compare = [&](const Index* from, const Index* to) {  // four candidates against four of the row's, rotated
    using namespace wide;
    for (std::uint32_t k = 0; k < o.size; k += 4) {
      const IntW of = loadu(o.of.data() + k);
      MaskIW any = none_int();
      for (const Index* q = from; q < to; q += 4) {
        const IntW r = loadu(q);
        any = any | ((of == r) | (of == rotate<1>(r)));
        any = any | ((of == rotate<2>(r)) | (of == rotate<3>(r)));
      }
      bits |= std::uint64_t(unsigned(wide::bits(any))) << k;
    }
  };
  const Index* split = last - first > 4 * kJoinedFirstGroups ? first + 4 * kJoinedFirstGroups : last;
  compare(first, split);
  if ((near & ~bits) != 0 && split < last) compare(split, last);
#else
  for (std::uint32_t k = 0; k < o.size; ++k) {
    bool found = false;
    for (const Index* q = first; q < last; ++q) found = found || *q == o.of[k];
    bits |= std::uint64_t(found) << k;
  }
#endif
  return bits & near;
}

// Whether the relative path (x_a − x_b) → (p_a − p_b) comes within r_a + r_b + margin at its closest, t ∈ [0, 1]:
// at t = 0 when the path moves apart (d0·e ≥ 0), at t = 1 when it ends before its closest point, else between
// (|d0|²|e|² − (d0·e)² < reach·|e|², without a division). Dot products as Eigen sums three terms: x + (y + z).
template <class Real> inline bool near_pair(const Real* ax, const Real* ap, const Real* bx, const Real* bp, Real margin) {
  const Real R = (ax[3] + bx[3]) + margin, reach = R * R;
  Real d0[3], d1[3], e[3];
  for (int d = 0; d < 3; ++d) {
    d0[d] = ax[d] - bx[d];
    d1[d] = ap[d] - bp[d];
    e[d] = d1[d] - d0[d];
  }
  auto dot = [](const Real* u, const Real* v) { return u[0] * v[0] + (u[1] * v[1] + u[2] * v[2]); };
  const Real ee = dot(e, e), de = dot(d0, e), q0 = dot(d0, d0), q1 = dot(d1, d1);
  const bool ahead = de >= Real(0), past = -de >= ee;
  return (ahead & (q0 < reach)) | (!ahead & past & (q1 < reach)) | (!(ahead | past) & (q0 * ee - de * de < reach * ee));
}

// Bit k set when o.of[k] is near o.a (near_pair), k < o.size ≤ 64.
template <class Mover, class Real> std::uint64_t near_bits(const Mover* P, Others& o, Real margin, bool avx2) {
  for (std::uint32_t k = o.size; k < o.size + 8; ++k) o.of[k] = o.a;
  const Mover& a = P[o.a];
  std::uint64_t bits = 0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Real, float>) {  // four or eight at a time: the same operations in the same order
    static_assert(sizeof(Mover) == 8 * sizeof(float));
    if (avx2) return near_bits_avx2(P[0].x, o.a, o.of.data(), o.size, margin);
    using namespace wide;
    const FloatW ax = splat(a.x[0]), ay = splat(a.x[1]), az = splat(a.x[2]), ar = splat(a.x[3]);
    const FloatW px = splat(a.p[0]), py = splat(a.p[1]), pz = splat(a.p[2]), m = splat(margin), z = zero();
    for (std::uint32_t k = 0; k < o.size; k += 4) {
      const Mover* b[4] = {P + o.of[k], P + o.of[k + 1], P + o.of[k + 2], P + o.of[k + 3]};
      const FloatW x0 = load(b[0]->x), x1 = load(b[1]->x), x2 = load(b[2]->x), x3 = load(b[3]->x);
      const Vec3W bx = transpose_xyz(x0, x1, x2, x3);
      const FloatW br = transpose_w(x0, x1, x2, x3);
      const Vec3W bp = transpose_xyz(load(b[0]->p), load(b[1]->p), load(b[2]->p), load(b[3]->p));
      const FloatW R = (ar + br) + m, reach = R * R;
      const Vec3W d0{ax - bx.x, ay - bx.y, az - bx.z}, d1{px - bp.x, py - bp.y, pz - bp.z};
      const Vec3W e{d1.x - d0.x, d1.y - d0.y, d1.z - d0.z};
      const FloatW ee = squared_norm(e), de = d0.x * e.x + (d0.y * e.y + d0.z * e.z);
      const FloatW q0 = squared_norm(d0), q1 = squared_norm(d1);
      const MaskW ahead = de >= z, past = -de >= ee;
      const MaskW start = ahead & (q0 < reach);
      const MaskW end = andnot(ahead, past & (q1 < reach));
      const MaskW mid = andnot(ahead | past, q0 * ee - de * de < reach * ee);
      bits |= std::uint64_t(wide::bits((start | end) | mid)) << k;
    }
    return o.size == 64 ? bits : bits & ((std::uint64_t(1) << o.size) - 1);
  }
#endif
  for (std::uint32_t k = 0; k < o.size; ++k)
    bits |= std::uint64_t(near_pair(a.x, a.p, P[o.of[k]].x, P[o.of[k]].p, margin)) << k;
  return bits;
}

// The test and the contacts it makes, for one call (walk.cpp): a particle's candidates are gathered (candidate) and
// tested together (flush), and a contact is made of each near pair that is kept (keep).
template <class Real> struct PairTest {
  using Mover = typename ParticleGrid<Real>::Mover;
  const Mover* P;                 // the movers
  const ContactBodies<Real>& c;
  const Matrix3X<Real>& v;        // velocities after forces (restitution)
  const ParticleGrid<Real>& g;    // the rows of joined particles
  Real margin;
  bool any_self;                  // some rows of joined particles
  bool avx2;
  std::atomic<std::size_t>* found;  // the call's pairs so far, and the most it may find (budget.hpp)
  std::size_t limit;

  // A particle's body when that does not collide with itself, else kNone: two particles of one such group never touch.
  Index group_of(Index i) const {
    const Index body = c.body_of[i];
    return c.bodies[body].self_collision ? ContactBodies<Real>::kNone : body;
  }
  // A near pair, not joined: dropped when both are pinned or of one body that does not self-collide, else a contact.
  void keep(Index first, Index other, std::vector<ParticleContact<Real>>& mine) const {
    const Index i = std::min(first, other), j = std::max(first, other);
    const Mover& a = P[i];
    const Mover& b = P[j];
    if (a.p[3] != Real(0) && b.p[3] != Real(0)) return;
    const Index group = group_of(i);
    if (group != ContactBodies<Real>::kNone && group == group_of(j)) return;  // one body, no self-collision
    const Real R = a.x[3] + b.x[3];
    const Vec3<Real> d0(a.x[0] - b.x[0], a.x[1] - b.x[1], a.x[2] - b.x[2]);
    const Vec3<Real> d1(a.p[0] - b.p[0], a.p[1] - b.p[1], a.p[2] - b.p[2]);
    const Vec3<Real> nrm = first_contact_normal(d0, d1, R);
    mine.push_back({{i, j}, nrm, R, d0, nrm.dot(Vec3<Real>(v.col(i) - v.col(j))),
                    mix_materials(c.material[i], c.material[j])});
    if (mine.size() % kCountEvery == 0) {
      const std::size_t now = found->fetch_add(kCountEvery, std::memory_order_relaxed) + kCountEvery;
      if (now > limit) fail_too_many_contacts<Real>(c, std::span(&mine, 1), now, limit, margin);
    }
  }
  // o.a against its candidates gathered so far; then none are left.
  void flush(Others& o, std::vector<ParticleContact<Real>>& mine) const {
    std::uint64_t bits = o.size > 0 ? near_bits(P, o, margin, avx2) : 0;
    if (bits != 0 && any_self)  // joined by a constraint (the near pairs of a cloth are nearly all its neighbours)
      bits &= ~joined_bits(g.joined.data() + g.joined_offsets[o.a], g.joined.data() + g.joined_offsets[o.a + 1], o, bits);
    for (; bits != 0; bits &= bits - 1) keep(o.a, o.of[std::size_t(__builtin_ctzll(bits))], mine);
    o.size = 0;
  }
  // b joins a's candidates.
  void candidate(Index b, Others& o, std::vector<ParticleContact<Real>>& mine) const {
    if (o.size == Others::kSize) flush(o, mine);
    o.of[o.size++] = b;
  }
};

// The pair test of a call's movers, bodies and margin.
template <class Real> PairTest<Real> pair_test(const Call<Real>& call) {
  return {call.g.movers.data(), call.m.contact, call.v, call.g, call.margin, call.any_self, call.avx2, &call.found,
          call.limit};
}

}  // namespace pbd::detail::contact
