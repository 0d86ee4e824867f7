#include "particle_contacts.hpp"

#include "pbd/constraint_types.hpp"

#include "simd/cpu.hpp"  // avx2_enabled
#include "simd/wide.hpp"
#include "near_avx2.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>
#include <type_traits>
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

#if defined(__SSE2__)
// The cells of q (lanes 0-2) with widths 1/inv: floor(q·inv), clamped, three axes at once.
inline Cell cell_of4(__m128 q, __m128 inv) {
  const __m128 c = _mm_max_ps(_mm_min_ps(_mm_mul_ps(q, inv), _mm_set1_ps(1e9f)), _mm_set1_ps(-1e9f));
  const __m128i t = _mm_cvttps_epi32(c);  // toward zero, then one down where that rounded up
  const __m128i f = _mm_add_epi32(t, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(t), c)));
  alignas(16) std::int32_t out[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(out), f);
  return {out[0], out[1], out[2]};
}
#endif

template <class Real> inline Cell cell_of(const Vec3<Real>& q, const Vec3<Real>& inv) {
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Real, float>)  // the same cells, three axes at once
    return cell_of4(_mm_setr_ps(q[0], q[1], q[2], 0.0f), _mm_setr_ps(inv[0], inv[1], inv[2], 0.0f));
#endif
  auto axis = [&](int d) {  // clamped so that a far particle cannot overflow (it only shares a cell more often);
    const Real v = std::floor(q[d] * inv[d]);  // a NaN (a blown-up state) goes to the lowest cell, not to an
    return std::int32_t(v >= Real(1e9) ? Real(1e9) : v > Real(-1e9) ? v : Real(-1e9));  // undefined conversion
  };
  return {axis(0), axis(1), axis(2)};
}

#if defined(__SSE2__)
// A float path's swept box: from x and p (lanes 0-2; lane 3 is ignored) in the frame moving with `frame`, grown by
// `grow` (lo, hi). The boxes' pass and box_of (generate_particle_contacts) both call it: the same corners.
inline void swept_corners4(__m128 from, __m128 at, __m128 frame, __m128 grow, __m128& lo, __m128& hi) {
  const __m128 to = _mm_sub_ps(at, frame);
  lo = _mm_sub_ps(_mm_min_ps(from, to), grow);
  hi = _mm_add_ps(_mm_max_ps(from, to), grow);
}
#endif

// The same for any Real, an axis at a time (the corners of the float path's box for float).
template <class Real>
inline void swept_corners(const Vec3<Real>& from, const Vec3<Real>& at, const Vec3<Real>& frame, Real grow, Vec3<Real>& lo,
                          Vec3<Real>& hi) {
  const Vec3<Real> to = at - frame;
  lo = from.cwiseMin(to).array() - grow;
  hi = from.cwiseMax(to).array() + grow;
}

inline std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t mask) {
  const std::uint64_t h = std::uint64_t(x) * 73856093ull ^ std::uint64_t(y) * 19349663ull ^ std::uint64_t(z) * 83492791ull;
  return std::uint32_t((h ^ (h >> 29)) & mask);
}

// Particles joined to one another by a built-in constraint, both in the same self-colliding body: never in contact.
// Each particle's row lists all the particles joined to it (a candidate is tested against its row, whichever of the
// two is lower).
template <class Real> void build_exclusions(const Model<Real>& m, const Matrix3X<Real>& x, ParticleGrid<Real>& g) {
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
  // each row nearest first (at x; a non-finite distance last): the pairs found near are nearly always the nearest
  // joined ones (a cloth's edges), so the row's first groups decide them (joined_bits); the order changes only the cost
  std::vector<std::tuple<Index, Real, Index>> rows(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [u, v] = pairs[k];
    const Real gap = (x.col(u) - x.col(v)).squaredNorm();
    rows[k] = {u, std::isfinite(gap) ? gap : std::numeric_limits<Real>::infinity(), v};
  }
  std::sort(rows.begin(), rows.end());
  for (std::size_t k = 0; k < pairs.size(); ++k) pairs[k] = {std::get<0>(rows[k]), std::get<2>(rows[k])};
  // rows padded to whole groups of four with kNone (no particle), so that a row is compared four at a time
  g.joined_offsets.assign(std::size_t(n) + 1, 0);
  for (const auto& [u, v] : pairs) ++g.joined_offsets[u + 1];
  for (Index i = 0; i < n; ++i) g.joined_offsets[i + 1] = g.joined_offsets[i] + (g.joined_offsets[i + 1] + 3) / 4 * 4;
  g.joined.assign(g.joined_offsets[n], ContactBodies<Real>::kNone);
  std::vector<Index> fill(g.joined_offsets.begin(), g.joined_offsets.end() - 1);
  for (const auto& [u, v] : pairs) g.joined[fill[u]++] = v;
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
    for (std::uint32_t k = 0; k < o.size; k += 4) {
      const __m128i of = _mm_loadu_si128(reinterpret_cast<const __m128i*>(o.of.data() + k));
      __m128i any = _mm_setzero_si128();
      for (const Index* q = from; q < to; q += 4) {
        const __m128i r = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
        any = _mm_or_si128(any, _mm_or_si128(_mm_cmpeq_epi32(of, r), _mm_cmpeq_epi32(of, _mm_shuffle_epi32(r, 0x39))));
        any = _mm_or_si128(any, _mm_or_si128(_mm_cmpeq_epi32(of, _mm_shuffle_epi32(r, 0x4e)),
                                             _mm_cmpeq_epi32(of, _mm_shuffle_epi32(r, 0x93))));
      }
      bits |= std::uint64_t(unsigned(_mm_movemask_ps(_mm_castsi128_ps(any)))) << k;
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
      const MaskW ahead{_mm_cmpge_ps(de.v, z.v)}, past{_mm_cmpge_ps((-de).v, ee.v)};
      const __m128 start = (ahead & (q0 < reach)).v;
      const __m128 end = _mm_andnot_ps(ahead.v, (past & (q1 < reach)).v);
      const __m128 mid = _mm_andnot_ps((ahead | past).v, (q0 * ee - de * de < reach * ee).v);
      const MaskW near{_mm_or_ps(_mm_or_ps(start, end), mid)};
      bits |= std::uint64_t(wide::bits(near)) << k;
    }
    return o.size == 64 ? bits : bits & ((std::uint64_t(1) << o.size) - 1);
  }
#endif
  for (std::uint32_t k = 0; k < o.size; ++k)
    bits |= std::uint64_t(near_pair(a.x, a.p, P[o.of[k]].x, P[o.of[k]].p, margin)) << k;
  return bits;
}

constexpr Index kChunks = 64;              // fixed, so the output never depends on the thread count
constexpr std::uint64_t kMaxRows = 4096;   // a larger box whose query spans more rows is paired with every small box
constexpr Index kBruteForce = 64;          // at most this many boxes left: paired with one another
constexpr std::uint32_t kLarge = ~std::uint32_t(0);
constexpr std::uint32_t kSplit = kLarge - 1;  // a box entered as a few small ones (see generate_particle_contacts)
constexpr int kMaxPieces = 4;                 // pieces a box is entered as at most (else it is large)
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
  using Box = typename ParticleGrid<Real>::Box;
  using Slot = typename ParticleGrid<Real>::Slot;
  const ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  if (!c.particle_contacts() || n == 0) return;
  bool any_self = false;
  for (const auto& b : c.bodies) any_self = any_self || (b.self_collision && b.radius > Real(0));
  if (any_self && (g.joined_edits != m.edits || g.joined_bodies != c.bodies.size() ||
                   g.joined_offsets.size() != std::size_t(n) + 1))
    build_exclusions(m, x, g);
  const std::vector<Index>& active = c.active;
  const Index count = Index(active.size());
  if (count == 0) return;
  // Loops run in fixed chunks (over_chunks): whatever a chunk computes depends on its items only, and chunk results
  // are joined in chunk order, so nothing depends on threads.
  auto fork = [&](Index items) { return parallel && items >= kParallelContactsFrom; };
  // 2. swept boxes in a frame that moves with a mean path Δ̄ (relative paths, all a pair test reads, are the same in
  // any such frame; a falling cloth's boxes stay short there): the last sub-step's when there was one with as many
  // particles, else this one's, from a pass of its own. With the last sub-step's cell widths known as well, level 0's
  // cells are found in the same pass. Δ̄ and the widths change only which pairs are tested, never the result.
  const bool known = g.known == count;
  g.partial.resize(kChunks);
  g.partial_path.resize(kChunks);
  Vec3<Real> shared = g.frame;
  if (!known) {
    over_chunks(count, fork(count), [&](Index ch, Index b, Index e) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (Index k = b; k < e; ++k) sum += (p.col(active[k]) - x.col(active[k])).template cast<double>();
      g.partial[ch] = sum;
    });
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) mean += g.partial[ch];
    shared = (mean / double(count)).template cast<Real>();
  }
  // A box's cells (the lower and upper corners'), as the level's member k: small (0), in pieces (kSplit) or large
  // (kLarge); an entry's lower cells widen [lo, hi]. True when large (its size then adds to the chunk's sum).
  using Level = typename ParticleGrid<Real>::Level;
  auto open_range = [](Cell& lo, Cell& hi, Eigen::Vector3d& sum) {
    constexpr std::int32_t top = std::numeric_limits<std::int32_t>::max(), bottom = std::numeric_limits<std::int32_t>::min();
    lo = {top, top, top};
    hi = {bottom, bottom, bottom};
    sum.setZero();
  };
  auto classify_cells = [&](Level& lv, Index k, const Cell& a, const Cell& z, Cell& lo, Cell& hi) {
    lv.lo[k] = a;
    lv.hi[k] = z;
    // pieces along each axis: blocks of two cells from the lower corner's (cells are clamped to ±1e9: no
    // overflow)
    const std::int32_t sx = z[0] - a[0], sy = z[1] - a[1], sz = z[2] - a[2];
    Cell top_corner = a;  // the last piece's lower corner
    int pieces = 1;
    if ((sx | sy | sz) > 1) {
      const std::int32_t span[3] = {sx, sy, sz};
      for (int d = 0; d < 3; ++d) {
        const int along = span[d] <= 1 ? 1 : span[d] <= 3 ? 2 : kMaxPieces + 1;
        pieces *= along;
        top_corner[d] = a[d] + 2 * (along - 1);
      }
    }
    lv.key[k] = pieces == 1 ? 0 : pieces <= kMaxPieces ? kSplit : kLarge;
    if (pieces > kMaxPieces) return true;
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], a[d]);
      hi[d] = std::max(hi[d], top_corner[d]);
    }
    return false;
  };
  auto classify = [&](Level& lv, Index k, const Box& box, const Vec3<Real>& inv, Cell& lo, Cell& hi,
                      Eigen::Vector3d& sum) {
    if (classify_cells(lv, k, cell_of<Real>(box.lo, inv), cell_of<Real>(box.hi, inv), lo, hi))
      sum += (box.hi - box.lo).template cast<double>();
  };
  if (g.levels.empty()) g.levels.resize(1);
  Level& top = g.levels[0];
  top.members.assign(active.begin(), active.end());
  Eigen::Vector3d width = g.width;
  const Vec3<Real> inv0 = width.cwiseInverse().template cast<Real>();
  if (known) {
    top.lo.resize(count);
    top.hi.resize(count);
    top.key.resize(count);
    top.bounds.resize(std::min<Index>(kChunks, count));
    top.extent.resize(std::min<Index>(kChunks, count));
  }
  g.movers.resize(n);
  over_chunks(count, fork(count), [&](Index ch, Index b, Index e) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), path = Eigen::Vector3d::Zero(), large;
    Cell lo, hi;
    open_range(lo, hi, large);
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Real, float>) {  // the same boxes and movers, a particle's three axes at once
      const __m128 frame = _mm_setr_ps(shared[0], shared[1], shared[2], 0.0f);
      const __m128 inv4 = _mm_setr_ps(inv0[0], inv0[1], inv0[2], 0.0f);
      __m128 size4 = _mm_setzero_ps(), path4 = _mm_setzero_ps();  // this chunk's sums (they only size the cells)
      auto load3 = [](const float* q) {  // q[0..2], 0
        return _mm_movelh_ps(_mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(q)), _mm_load_ss(q + 2));
      };
      auto with_w = [](__m128 q, float w) {  // q[0..2], w
        const __m128 tail = _mm_shuffle_ps(q, _mm_set_ss(w), _MM_SHUFFLE(0, 0, 2, 2));  // q2, q2, w, w
        return _mm_shuffle_ps(q, tail, _MM_SHUFFLE(2, 0, 1, 0));
      };
      for (Index k = b; k < e; ++k) {
        const Index i = active[k];
        const __m128 from = load3(x.data() + 3 * std::size_t(i)), at = load3(p.data() + 3 * std::size_t(i));
        _mm_store_ps(g.movers[i].x, with_w(from, c.radius[i]));
        _mm_store_ps(g.movers[i].p, with_w(at, m.inverse_mass[i] == 0.0f ? 1.0f : 0.0f));
        __m128 lo4, hi4;
        swept_corners4(from, at, frame, _mm_set1_ps(c.radius[i] + 0.5f * margin), lo4, hi4);
        const __m128 size = _mm_sub_ps(hi4, lo4);
        size4 = _mm_add_ps(size4, size);
        path4 = _mm_add_ps(path4, _mm_sub_ps(at, from));
        if (known && classify_cells(top, k, cell_of4(lo4, inv4), cell_of4(hi4, inv4), lo, hi)) {
          alignas(16) float extent[4];
          _mm_store_ps(extent, size);
          large += Eigen::Vector3d(extent[0], extent[1], extent[2]);
        }
      }
      alignas(16) float sums[2][4];
      _mm_store_ps(sums[0], size4);
      _mm_store_ps(sums[1], path4);
      sum = Eigen::Vector3d(sums[0][0], sums[0][1], sums[0][2]);
      path = Eigen::Vector3d(sums[1][0], sums[1][1], sums[1][2]);
    } else
#endif
    for (Index k = b; k < e; ++k) {
      const Index i = active[k];
      g.movers[i] = {{x(0, i), x(1, i), x(2, i), c.radius[i]},
                     {p(0, i), p(1, i), p(2, i), m.inverse_mass[i] == Real(0) ? Real(1) : Real(0)}};
      Box box;
      swept_corners<Real>(x.col(i), p.col(i), shared, c.radius[i] + Real(0.5) * margin, box.lo, box.hi);
      sum += (box.hi - box.lo).template cast<double>();
      path += (p.col(i) - x.col(i)).template cast<double>();
      if (known) classify(top, k, box, inv0, lo, hi, large);
    }
    g.partial[ch] = sum;
    g.partial_path[ch] = path;
    if (known) {
      top.bounds[ch] = {lo, hi};
      top.extent[ch] = large;
    }
  });
  Eigen::Vector3d extent = Eigen::Vector3d::Zero(), path = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) {
    extent += g.partial[ch];
    path += g.partial_path[ch];
  }
  g.width = kCellScale * extent / double(count);  // for the next sub-step
  g.frame = (path / double(count)).template cast<Real>();
  g.known = count;
  if (!known) width = g.width;
  // 4. the pair test: a particle is tested against the candidates gathered for it, several at a time (near_bits);
  // boxes are not compared first, since two paths within reach have overlapping boxes (each box is its path grown by
  // its radius and half the margin). The few pairs within reach are then kept unless both are pinned, or they are
  // of one body that does not self-collide, or a constraint joins them.
  using Mover = typename ParticleGrid<Real>::Mover;
  const Mover* P = g.movers.data();
  const bool avx2 = avx2_enabled();
  // A particle's swept box, found again from its mover as the boxes' pass found it (only the few boxes of the levels
  // after the first and the large ones need it: no pass stores them).
  auto box_of = [&](Index i) {
    Box box;
    const Mover& a = P[i];
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Real, float>) {
      __m128 lo4, hi4;
      swept_corners4(_mm_load_ps(a.x), _mm_load_ps(a.p), _mm_setr_ps(shared[0], shared[1], shared[2], 0.0f),
                     _mm_set1_ps(a.x[3] + 0.5f * margin), lo4, hi4);
      alignas(16) float corner[2][4];
      _mm_store_ps(corner[0], lo4);
      _mm_store_ps(corner[1], hi4);
      box.lo = Vec3<Real>(corner[0][0], corner[0][1], corner[0][2]);
      box.hi = Vec3<Real>(corner[1][0], corner[1][1], corner[1][2]);
      return box;
    }
#endif
    swept_corners<Real>(Vec3<Real>(a.x[0], a.x[1], a.x[2]), Vec3<Real>(a.p[0], a.p[1], a.p[2]), shared,
                        a.x[3] + Real(0.5) * margin, box.lo, box.hi);
    return box;
  };
  // A particle's body when that does not collide with itself, else kNone: two particles of one such group never touch.
  auto group_of = [&](Index i) {
    const Index body = c.body_of[i];
    return c.bodies[body].self_collision ? ContactBodies<Real>::kNone : body;
  };
  auto keep = [&](Index first, Index other, std::vector<ParticleContact<Real>>& mine) {  // a near pair, not joined
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
  };
  auto flush = [&](Others& o, std::vector<ParticleContact<Real>>& mine) {
    std::uint64_t bits = o.size > 0 ? near_bits(P, o, margin, avx2) : 0;
    if (bits != 0 && any_self)  // joined by a constraint (the near pairs of a cloth are nearly all its neighbours)
      bits &= ~joined_bits(g.joined.data() + g.joined_offsets[o.a], g.joined.data() + g.joined_offsets[o.a + 1], o, bits);
    for (; bits != 0; bits &= bits - 1) keep(o.a, o.of[std::size_t(__builtin_ctzll(bits))], mine);
    o.size = 0;
  };
  auto candidate = [&](Index b, Others& o, std::vector<ParticleContact<Real>>& mine) {  // b joins a's candidates
    if (o.size == Others::kSize) flush(o, mine);
    o.of[o.size++] = b;
  };
  bool repeats = false;    // a box was entered in pieces: a pair may have been found more than once
  std::size_t lists = 0;  // contact lists used so far
  auto take_lists = [&](std::size_t k) {
    if (g.lists.size() < lists + k) g.lists.resize(lists + k);
    for (std::size_t l = lists; l < lists + k; ++l) g.lists[l].clear();
    lists += k;
    return lists - k;
  };
  // 3. level by level
  for (std::size_t level = 0;; ++level) {
    if (g.levels.size() < level + 2) g.levels.resize(level + 2);
    Level& lv = g.levels[level];
    const Index members = Index(lv.members.size());
    if (members <= kBruteForce) {  // few left: each with each
      std::vector<ParticleContact<Real>>& mine = g.lists[take_lists(1)];
      Others o;
      for (Index a = 0; a < members; ++a) {
        o.a = lv.members[a];
        for (Index b = a + 1; b < members; ++b) candidate(lv.members[b], o, mine);
        flush(o, mine);
      }
      break;
    }
    const Vec3<Real> inv = width.cwiseInverse().template cast<Real>();
    const Index chunks = std::min<Index>(kChunks, members);
    if (level > 0 || !known) {
      lv.lo.resize(members);
      lv.hi.resize(members);
      lv.key.resize(members);
      lv.bounds.resize(chunks);
      lv.extent.resize(chunks);
    }
    // cells of each box's corners; small, in pieces or large; per chunk the range of the entries' lower cells (level
    // 0's were found with the boxes when the cells' widths were known)
    if (level > 0 || !known)
      over_chunks(members, fork(members), [&](Index ch, Index b, Index e) {
        Cell lo, hi;
        Eigen::Vector3d sum;
        open_range(lo, hi, sum);
        for (Index k = b; k < e; ++k) classify(lv, k, box_of(lv.members[k]), inv, lo, hi, sum);
        lv.bounds[ch] = {lo, hi};
        lv.extent[ch] = sum;
      });
    lv.large.clear();
    lv.slots.clear();
    for (Index k = 0; k < members; ++k) {
      if (lv.key[k] == kLarge) {
        lv.large.push_back(lv.members[k]);
      } else if (lv.key[k] == 0) {
        lv.slots.push_back({lv.lo[k], lv.members[k]});
      } else {
        repeats = true;
        const Cell& a = lv.lo[k];
        const Cell& z = lv.hi[k];
        for (std::int32_t cz = a[2]; cz <= z[2]; cz += 2)  // pieces' lower corners: two cells apart, so that no
          for (std::int32_t cy = a[1]; cy <= z[1]; cy += 2)  // two of one box are ever paired
            for (std::int32_t cx0 = a[0]; cx0 <= z[0]; cx0 += 2) lv.slots.push_back({{cx0, cy, cz}, lv.members[k]});
      }
    }
    const Index small = Index(lv.slots.size());
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
      base[0] = lo[0];  // along x: the lower corners' range
      dims[0] = std::int64_t(hi[0]) - lo[0] + 1;
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
    // counting sort of the small boxes by bucket, then each bucket sorted by (cell z, y, x, particle). Dense, and
    // when the cells along x are not too many: a counting sort by cell x first, so that the one by bucket (stable)
    // leaves each row in (x, particle) order with no sort (members are ascending). One pass finds each box's bucket
    // and counts both sorts' keys.
    const bool by_x = dense && dims[0] <= 4 * std::int64_t(small) + 64;
    lv.key.resize(std::size_t(small));
    lv.bucket_start.assign(std::size_t(buckets) + 1, 0);
    if (by_x) {
      lv.x_start.assign(std::size_t(dims[0]) + 1, 0);
      for (Index t = 0; t < small; ++t) {
        const Cell& cell = lv.slots[t].cell;
        const std::uint32_t key = bucket_of(cell[1], cell[2]);
        lv.key[t] = key;
        ++lv.bucket_start[key + 1];
        ++lv.x_start[cell[0] - base[0] + 1];
      }
    } else {
      for (Index t = 0; t < small; ++t) {
        const std::uint32_t key = bucket_of(lv.slots[t].cell[1], lv.slots[t].cell[2]);
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
      for (std::int64_t x = 0; x < dims[0]; ++x) lv.x_start[x + 1] += lv.x_start[x];
      lv.by_x.resize(small);
      for (Index t = 0; t < small; ++t) lv.by_x[lv.x_start[lv.slots[t].cell[0] - base[0]]++] = t;
      for (Index t = 0; t < small; ++t) enter(lv.by_x[t]);
    } else {
      for (Index t = 0; t < small; ++t) enter(t);
    }
    Slot* E = lv.entries.data();
    const Index* start = lv.bucket_start.data();
    auto before = [](const Slot& a, const Slot& b) {
      if (a.cell[2] != b.cell[2]) return a.cell[2] < b.cell[2];
      if (a.cell[1] != b.cell[1]) return a.cell[1] < b.cell[1];
      if (a.cell[0] != b.cell[0]) return a.cell[0] < b.cell[0];
      return a.particle < b.particle;
    };
    auto before_x = [](const Slot& a, const Slot& b) {  // dense: a bucket is one row
      return a.cell[0] != b.cell[0] ? a.cell[0] < b.cell[0] : a.particle < b.particle;
    };
    auto sort_bucket = [&](Slot* first, Slot* last, const auto& less) {
      if (last - first <= 24) {  // insertion sort: a row of particles added in x order is sorted already
        for (Slot* q = first + 1; q < last; ++q)
          for (Slot* r = q; r > first && less(*r, *(r - 1)); --r) std::swap(*r, *(r - 1));
      } else {
        std::sort(first, last, less);
      }
    };
    const Index small_chunks = std::min<Index>(kChunks, std::max<Index>(small, 1));
    lv.cut.resize(std::size_t(small_chunks) + 1);
    for (Index ch = 0; ch < small_chunks; ++ch)  // chunk ch: the buckets from the first at or after entry ch·small/chunks
      lv.cut[ch] = Index(std::lower_bound(lv.bucket_start.begin(), lv.bucket_start.end() - 1,
                                          Index(std::uint64_t(ch) * small / small_chunks)) - lv.bucket_start.begin());
    lv.cut[small_chunks] = buckets;
    if (small > 1 && !by_x)
      over_chunks(small_chunks, fork(small), [&](Index ch, Index, Index) {
        for (Index b = lv.cut[ch]; b < lv.cut[ch + 1]; ++b) {
          if (dense) sort_bucket(E + start[b], E + start[b + 1], before_x);
          else sort_bucket(E + start[b], E + start[b + 1], before);
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
    const std::int32_t* cx = lv.cell_x.data();
    const Index* pid = lv.particle.data();
    // the boxes of row (y, z) in bucket `nb` from cell x0 on: [from, end of the row)
    auto row_from = [&](std::uint32_t nb, std::int32_t y, std::int32_t z, std::int32_t x0) {
      Slot probe;
      probe.cell = {x0, y, z};
      probe.particle = 0;
      return Index(std::lower_bound(E + start[nb], E + start[nb + 1], probe, before) - E);
    };
    auto in_row = [&](const Slot& e, std::int32_t y, std::int32_t z) { return e.cell[1] == y && e.cell[2] == z; };
    // Entries [from, end) whose cells along x are at most `top`: counted eight at a time without a branch (the
    // arrays run eight past the last entry), as the rows hold one or two boxes per cell, so that one probe nearly
    // always ends the count. With `below` < `top`, also those whose cells are at most `below` (a prefix: the row
    // is sorted).
    auto upto = [&](Index from, Index end, std::int32_t below, std::int32_t top) {
      Index n = 0, under = 0;
      for (;;) {
        Index k8 = 0;
#if defined(__SSE2__)
        const Index at = from + n;  // indices and cells fit in 31 bits: signed compares
        const __m128i last = _mm_set1_epi32(std::int32_t(end)), high = _mm_set1_epi32(top + 1);
        const __m128i low_end = _mm_set1_epi32(below + 1);
        const __m128i index = _mm_add_epi32(_mm_set1_epi32(std::int32_t(at)), _mm_setr_epi32(0, 1, 2, 3));
        const __m128i c0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cx + at));
        const __m128i c1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cx + at + 4));
        const __m128i in0 = _mm_and_si128(_mm_cmplt_epi32(index, last), _mm_cmplt_epi32(c0, high));
        const __m128i in1 = _mm_and_si128(_mm_cmplt_epi32(_mm_add_epi32(index, _mm_set1_epi32(4)), last),
                                          _mm_cmplt_epi32(c1, high));
        const __m128i lo0 = _mm_and_si128(in0, _mm_cmplt_epi32(c0, low_end));
        const __m128i lo1 = _mm_and_si128(in1, _mm_cmplt_epi32(c1, low_end));
        const unsigned inside = unsigned(_mm_movemask_ps(_mm_castsi128_ps(in0))) |
                                unsigned(_mm_movemask_ps(_mm_castsi128_ps(in1))) << 4;
        const unsigned lower = unsigned(_mm_movemask_ps(_mm_castsi128_ps(lo0))) |
                               unsigned(_mm_movemask_ps(_mm_castsi128_ps(lo1))) << 4;
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
    };
    // small with small: each box with those after it in its cell and the next cell along x, and with those in the
    // neighbouring cells of the rows (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1): the 13 of the 26
    // neighbouring cells that come after its own, so each pair once
    if (small > 1) {
      static constexpr std::array<std::array<std::int32_t, 2>, 4> kRows = {{{1, 0}, {-1, 1}, {0, 1}, {1, 1}}};
      const std::size_t first = take_lists(std::size_t(small_chunks));
      if (std::is_same_v<Real, float> && dense && avx2) {
        if constexpr (std::is_same_v<Real, float>) {  // the same walk and pairs, eight entries at a time (near_avx2.hpp)
          DenseWalk walk;
          walk.cx = cx;
          walk.pid = pid;
          walk.start = start;
          for (std::size_t q = 0; q < kRows.size(); ++q) walk.row_step[q] = Index(kRows[q][0] + kRows[q][1] * dims[1]);
          walk.movers = P[0].x;
          walk.margin = margin;
          if (any_self) {
            walk.joined = g.joined.data();
            walk.joined_offsets = g.joined_offsets.data();
          }
          struct Sink {
            decltype(keep)* pair;  // keep
            std::vector<ParticleContact<Real>>* mine;
          };
          const NearSink sink = [](void* context, const Index* pairs, std::size_t count) {
            const Sink& to = *static_cast<const Sink*>(context);
            for (std::size_t k = 0; k < count; ++k) (*to.pair)(pairs[2 * k], pairs[2 * k + 1], *to.mine);
          };
          over_chunks(small_chunks, fork(small), [&](Index ch, Index, Index) {
            Sink to{&keep, &g.lists[first + ch]};
            walk_dense_avx2(walk, lv.cut[ch], lv.cut[ch + 1], sink, &to);
          });
        }
      } else {
        over_chunks(small_chunks, fork(small), [&](Index ch, Index, Index) {
          std::vector<ParticleContact<Real>>& mine = g.lists[first + ch];
          Others o;
          // b's candidates from row entries [from, from + count), counted in `size` (o.size once they are all taken:
          // a local count stays in a register)
          auto take = [&](Index from, Index count, std::uint32_t& size) {
            if (size + count > Others::kSize) {  // a crowded cell: one at a time
              o.size = size;
              for (Index k = 0; k < count; ++k) candidate(pid[from + k], o, mine);
              size = o.size;
              return;
            }
            Index* to = o.of.data() + size;
            std::memcpy(to, pid + from, 8 * sizeof(Index));  // eight at once; `count` of them kept
            for (Index k = 8; k < count; ++k) to[k] = pid[from + k];
            size += count;
          };
          for (Index b = lv.cut[ch]; b < lv.cut[ch + 1]; ++b) {
            const Index s1 = start[b + 1];
            for (Index r0 = start[b], r1; r0 < s1; r0 = r1) {  // one row at a time: [r0, r1)
              const std::int32_t y = E[r0].cell[1], z = E[r0].cell[2];
              if (dense) r1 = s1;  // the bucket is the row
              else for (r1 = r0 + 1; r1 < s1 && in_row(E[r1], y, z); ++r1) {}
              std::array<Index, 4> w, w1;  // each neighbouring row that holds boxes, walked along with this one: [w, w1)
              std::size_t rows = 0;
              for (std::size_t q = 0; q < kRows.size(); ++q) {
                const std::int32_t ny = y + kRows[q][0], nz = z + kRows[q][1];
                const std::uint32_t nb = bucket_of(ny, nz);
                w[rows] = start[nb];  // dense: the bucket is the row
                w1[rows] = start[nb + 1];
                if (!dense) {
                  w[rows] = row_from(nb, ny, nz, E[r0].cell[0] - 1);
                  for (w1[rows] = w[rows]; w1[rows] < start[nb + 1] && in_row(E[w1[rows]], ny, nz); ++w1[rows]) {}
                }
                rows += w[rows] < w1[rows] ? 1 : 0;  // an empty row (a flat cloth's rows above it) is not walked
              }
              for (Index s = r0; s < r1; ++s) {
                const std::int32_t x = cx[s];
                o.a = pid[s];
                if (any_self) __builtin_prefetch(g.joined.data() + g.joined_offsets[pid[s + 2]]);  // pid runs 8 past
                std::uint32_t size = 0;
                take(s + 1, upto(s + 1, r1, x, x + 1).second, size);  // its own cell (after s) and the next along x
                for (std::size_t q = 0; q < rows; ++q) {  // the neighbouring rows' cells x − 1, x, x + 1
                  const auto [skip, n] = upto(w[q], w1[q], x - 2, x + 1);
                  w[q] += skip;
                  take(w[q], n - skip, size);
                }
                o.size = size;
                flush(o, mine);
              }
            }
          }
        });
      }
    }
    // large with entered: each large box with the entries whose lower corners lie in its cells or one cell below (an
    // entry that overlaps it has its lower corner there), or with every entry when that is too many rows
    const Index large = Index(lv.large.size());
    if (large > 0 && small > 0) {
      const std::size_t first = take_lists(std::size_t(std::min<Index>(kChunks, large)));
      over_chunks(large, fork(16 * large), [&](Index ch, Index b, Index e) {  // a query costs tens of boxes' passes
        std::vector<ParticleContact<Real>>& mine = g.lists[first + ch];
        Others o;
        for (Index k = b; k < e; ++k) {
          const Box box = box_of(lv.large[k]);
          o.a = lv.large[k];
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
            for (Index t = 0; t < small; ++t) candidate(pid[t], o, mine);
            flush(o, mine);
            continue;
          }
          for (std::int32_t cz = lo[2]; cz <= hi[2]; ++cz)
            for (std::int32_t cy = lo[1]; cy <= hi[1]; ++cy) {
              const std::uint32_t nb = bucket_of(cy, cz);
              if (dense) {  // the bucket is the row: its boxes in cells lo..hi along x, counted as the walk counts
                Index from = start[nb];
                const Index last = start[nb + 1];
                if (last - from > 32) from = Index(std::lower_bound(cx + from, cx + last, lo[0]) - cx);
                const auto [skip, end] = upto(from, last, lo[0] - 1, hi[0]);
                for (Index t = from + skip; t < from + end; ++t) candidate(pid[t], o, mine);
              } else {
                for (Index t = row_from(nb, cy, cz, lo[0]); t < start[nb + 1] && in_row(E[t], cy, cz) && cx[t] <= hi[0]; ++t)
                  candidate(pid[t], o, mine);
              }
            }
          flush(o, mine);
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
  if (repeats) {  // a pair found more than once gave the same contact each time: keep one
    auto last = std::unique(to, to + found, [](const auto& a, const auto& b) { return a.particles == b.particles; });
    out.resize(before + std::size_t(last - to));
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
