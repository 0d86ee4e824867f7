// AVX2 builds of the bending, area, tet volume, shape-matching and Neo-Hookean kernels (float and double) and of the
// double stretch kernel (kernels_avx2.hpp).
// This file alone is compiled with -mavx2 -mno-fma (engine/CMakeLists.txt). It instantiates no inline function the
// rest of the engine also instantiates (the scalar remainders are called out of line), so the linker never keeps an
// AVX2 copy of a function other files call on machines without AVX2.
#include "kernels_avx2.hpp"

#include "simd/wide_avx.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <type_traits>

#if defined(__AVX2__)
namespace pbd::detail::wide8 {
/// shape_match_math.hpp's cube_root lane by lane (found by argument-dependent lookup).
template <class W> [[gnu::always_inline]] inline W cube_root(W a) {
  using L = Lanes<W>;
  alignas(64) typename L::Real f[L::kCount];
  L::storeu(f, a);
  for (auto& x : f) x = shape_match::math::cube_root(x);
  return L::loadu(f);
}
}  // namespace pbd::detail::wide8

namespace pbd::detail::lane {
/// A constant in every lane: Real(v), as the scalar code converts it.
template <> struct Lit<wide8::FloatW8> {
  [[gnu::always_inline]] static wide8::FloatW8 of(double v) { return wide8::Lanes<wide8::FloatW8>::splat(float(v)); }
};
template <> struct Lit<wide8::DoubleW4> {
  [[gnu::always_inline]] static wide8::DoubleW4 of(double v) { return wide8::Lanes<wide8::DoubleW4>::splat(v); }
};
}  // namespace pbd::detail::lane
#endif

namespace pbd::detail {

#if defined(__AVX2__)
namespace {

using wide8::Lanes;

// k and α̃ of the lanes' constraints: read once when they share one set (the usual case), else lane by lane.
template <class W, bool kLambda, class C, class Real>
[[gnu::always_inline]] inline void lane_coefficients(const C* c, const SolveCoefficients<Real>* coeff, W& k, W& alpha) {
  using L = Lanes<W>;
  bool one_set = true;
  for (int j = 1; j < L::kCount; ++j) one_set = one_set && c[j].set == c[0].set;
  alpha = L::zero();
  if (one_set) {
    k = L::splat(coeff[c[0].set].k);
    if constexpr (kLambda) alpha = L::splat(coeff[c[0].set].alpha_tilde);
  } else {
    k = L::of([&](int j) { return coeff[c[j].set].k; });
    if constexpr (kLambda) alpha = L::of([&](int j) { return coeff[c[j].set].alpha_tilde; });
  }
}

// The corners of L::kCount constraints: their addresses in q ([corner][lane]), positions and inverse masses.
template <class W, class C, class Real, int kCorners, int kLanes>
[[gnu::always_inline]] inline void gather_corners(const C* c, Real* q, Real* (&at)[kCorners][kLanes],
                                                  lane::V3<W> (&p)[kCorners], W (&w)[kCorners]) {
  for (int i = 0; i < kCorners; ++i) {
    for (int j = 0; j < kLanes; ++j) at[i][j] = q + 4 * std::size_t(c[j].particles[i]);
    W xyzw[4];
    Lanes<W>::gather(at[i], xyzw);
    p[i] = {xyzw[0], xyzw[1], xyzw[2]};
    w[i] = xyzw[3];
  }
}

// The shared arithmetic of a constraint type written over lanes (bending_math.hpp, area_math.hpp).
template <class Real, class W>
[[gnu::always_inline]] inline auto lane_step(const BendingConstraint<Real>*, const lane::V3<W> (&p)[4],
                                             const W (&w)[4], W rest, W neg_k, W alpha, W lam) {
  return bend::bending_step<Real>(p, w, rest, neg_k, alpha, lam);
}
template <class Real, class W>
[[gnu::always_inline]] inline auto lane_step(const AreaConstraint<Real>*, const lane::V3<W> (&p)[3], const W (&w)[3],
                                             W rest, W neg_k, W alpha, W lam) {
  return area::area_step<Real>(p, w, rest, neg_k, alpha, lam);
}

template <class Real, class W>
[[gnu::always_inline]] inline auto lane_step(const TetVolumeConstraint<Real>*, const lane::V3<W> (&p)[4],
                                             const W (&w)[4], W rest, W neg_k, W alpha, W lam) {
  return tet_volume::tet_volume_step<Real>(p, w, rest, neg_k, alpha, lam);
}

// L::kCount constraints of one color (bending, area or tet volume) in the lanes: the step as the scalar correction() runs it,
// and only the writes project() makes (movable corners of lanes that project; λ of lanes with α̃ ≠ 0).
// kLambda = false: every α̃ is +0 and every λ 0 (the scalar "− α̃·λ" then subtracts +0, which changes no bit).
template <class W, bool kLambda, class C, class Real>
[[gnu::always_inline]] inline void lanes_block(const C* c, Real* q, const SolveCoefficients<Real>* coeff,
                                               Real* lambda) {
  using L = Lanes<W>;
  constexpr int n = L::kCount, corners = C::kArity;
  Real* at[corners][n];  // [corner][lane]
  lane::V3<W> p[corners];
  W w[corners];
  gather_corners(c, q, at, p, w);
  W k, alpha;
  lane_coefficients<W, kLambda>(c, coeff, k, alpha);
  const W lam = kLambda ? L::loadu(lambda) : L::zero();
  const W rest = L::of([&](int j) { return c[j].rest; });
  const auto r = lane_step<Real>(c, p, w, rest, -k, alpha, lam);
  const int active = bits(r.ok);
  if (active == 0) return;
  if constexpr (kLambda) L::storeu(lambda, select(r.ok & (alpha != L::zero()), lam + r.dlambda, lam));
  for (int i = 0; i < corners; ++i)
    if (const int moves = active & ~bits(w[i] == L::zero())) L::add(at[i], r.dp[i].x, r.dp[i].y, r.dp[i].z, moves);
}

// L::kCount stretch constraints in the lanes: stretch.hpp's correction() and project()'s writes. set: the set all
// of them belong to (k and α̃ splatted once per range), or kMixedSets.
template <class W, bool kLambda, class Real>
[[gnu::always_inline]] inline void stretch_block(const StretchConstraint<Real>* c, Real* q,
                                                 const SolveCoefficients<Real>* coeff, Real* lambda, Index set, W k1,
                                                 W alpha1) {
  using L = Lanes<W>;
  constexpr int n = L::kCount;
  Real* a[n];
  Real* b[n];
  for (int j = 0; j < n; ++j) {
    a[j] = q + 4 * std::size_t(c[j].particles[0]);
    b[j] = q + 4 * std::size_t(c[j].particles[1]);
  }
  W pa[4], pb[4];
  L::gather(a, pa);
  L::gather(b, pb);
  const W dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
  const W len2 = dx * dx + (dy * dy + dz * dz);
  W k = k1, alpha = alpha1;
  if (set == kMixedSets) lane_coefficients<W, kLambda>(c, coeff, k, alpha);
  const W denom = alpha + pa[3] + pb[3];
  constexpr Real tiny = tiny_squared<Real>();  // folded here, never called at run time
  const auto ok = (len2 > L::splat(tiny)) & (denom > L::zero());
  const int active = bits(ok);
  if (active == 0) return;
  const W len = sqrt(len2);
  const W rest = L::of([&](int j) { return c[j].rest; });
  W num = -k * (len - rest);
  const W lam = kLambda ? L::loadu(lambda) : L::zero();
  if constexpr (kLambda) num = num - alpha * lam;
  const W s = num / (denom * len);
  if constexpr (kLambda) L::storeu(lambda, select(ok & (alpha != L::zero()), lam + s * len, lam));
  const W sa = pa[3] * s, sb = -pb[3] * s;
  if (const int moves = active & ~bits(pa[3] == L::zero())) L::add(a, dx * sa, dy * sa, dz * sa, moves);
  if (const int moves = active & ~bits(pb[3] == L::zero())) L::add(b, dx * sb, dy * sb, dz * sb, moves);
}

// The last m (2 ≤ m < n) constraints [b, e) of a color in the lanes: the lanes past them repeat the first and are
// masked off, and their λ (kMul a constraint) are a copy; block(tail, λ, lanes) projects them. A color's constraints
// share no particle, so the tail gets the bits of one constraint after the other.
template <int n, int kMul, class C, class Real, class Block>
[[gnu::always_inline]] inline void masked_tail(const C* c, Index b, Index e, Real* lambda, const Block& block) {
  const Index m = e - b;
  C tail[n];
  alignas(64) Real lam[kMul * n] = {};
  for (Index j = 0; j < n; ++j) tail[j] = c[b + (j < m ? j : 0)];
  std::copy(lambda + kMul * std::size_t(b), lambda + kMul * std::size_t(e), lam);
  block(static_cast<const C*>(tail), lam, (1 << m) - 1);
  std::copy(lam, lam + kMul * m, lambda + kMul * std::size_t(b));
}

// The rest values of L::kCount Neo-Hookean tets across the lanes, one lane at a time.
template <class W, class Real>
[[gnu::always_inline]] inline neo_hookean::TetRest<W> tet_rest_by_lane(const NeoHookeanConstraint<Real>* c) {
  using L = Lanes<W>;
  auto column = [&](Vec3<Real> NeoHookeanConstraint<Real>::*m) {
    return lane::V3<W>{L::of([&](int j) { return (c[j].*m).x(); }), L::of([&](int j) { return (c[j].*m).y(); }),
                       L::of([&](int j) { return (c[j].*m).z(); })};
  };
  using N = NeoHookeanConstraint<Real>;
  return {{column(&N::inv_rest0), column(&N::inv_rest1), column(&N::inv_rest2)},
          L::of([&](int j) { return c[j].volume; }),
          L::of([&](int j) { return c[j].ratio; })};
}

// Eight float tets' rest values by three transposes: a tet is 64 bytes, its floats 4..15 are its set (not read),
// V0, Dm⁻¹'s columns r0, r1, r2 and μ/λ (the static_asserts), so four floats at a time from each of eight tets give
// four of those values across the lanes (some 50 instructions where one lane at a time takes some 130).
[[gnu::always_inline]] inline neo_hookean::TetRest<wide8::FloatW8> tet_rest_transposed(const NeoHookeanConstraint<float>* c) {
  using N = NeoHookeanConstraint<float>;
  static_assert(std::is_standard_layout_v<N> && sizeof(N) == 16 * sizeof(float));
  static_assert(offsetof(N, volume) == 5 * sizeof(float) && offsetof(N, inv_rest0) == 6 * sizeof(float) &&
                offsetof(N, inv_rest1) == 9 * sizeof(float) && offsetof(N, inv_rest2) == 12 * sizeof(float) &&
                offsetof(N, ratio) == 15 * sizeof(float));
  const float* at[8];
  wide8::FloatW8 f[3][4];  // floats 4..7, 8..11, 12..15
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 8; ++j) at[j] = reinterpret_cast<const float*>(c + j) + 4 * (k + 1);
    Lanes<wide8::FloatW8>::gather_unaligned(at, f[k]);
  }
  return {{{f[0][2], f[0][3], f[1][0]}, {f[1][1], f[1][2], f[1][3]}, {f[2][0], f[2][1], f[2][2]}}, f[0][1], f[2][3]};
}

// The rest values of L::kCount Neo-Hookean tets across the lanes.
template <class W, class Real>
[[gnu::always_inline]] inline neo_hookean::TetRest<W> tet_rest(const NeoHookeanConstraint<Real>* c) {
  if constexpr (std::is_same_v<W, wide8::FloatW8>) return tet_rest_transposed(c);
  else return tet_rest_by_lane<W>(c);
}

// L::kCount Neo-Hookean tets of one color in the lanes: neo_hookean.hpp's correction() and project()'s writes
// (movable corners of the lanes that project, and their two λ: a lane projects only where α̃ > 0). Only the lanes
// in `lanes` write positions (all of them write λ).
template <class W, class Real>
[[gnu::always_inline]] inline void neo_hookean_block(const NeoHookeanConstraint<Real>* c, Real* q,
                                                     const SolveCoefficients<Real>* coeff, Real* lambda,
                                                     int lanes = (1 << Lanes<W>::kCount) - 1) {
  using L = Lanes<W>;
  constexpr int n = L::kCount;
  Real* at[4][n];  // [corner][lane]
  lane::V3<W> p[4];
  W w[4];
  gather_corners(c, q, at, p, w);
  W k, alpha;
  lane_coefficients<W, true>(c, coeff, k, alpha);
  W lam_d, lam_h;
  L::load_pairs(lambda, lam_d, lam_h);
  const auto r = neo_hookean::neo_hookean_step<Real>(p, w, tet_rest<W, Real>(c), alpha, lam_d, lam_h);
  const int active = bits(r.ok) & lanes;
  if (active == 0) return;
  L::store_pairs(lambda, select(r.ok, lam_d + r.dlambda[0], lam_d), select(r.ok, lam_h + r.dlambda[1], lam_h));
  for (int i = 0; i < 4; ++i)
    if (const int moves = active & ~bits(w[i] == L::zero())) L::add(at[i], r.dp[i].x, r.dp[i].y, r.dp[i].z, moves);
}

template <class W, class Real>
void neo_hookean_range(const NeoHookeanConstraint<Real>* c, Index b, Index e, Real* q,
                       const SolveCoefficients<Real>* coeff, Real* lambda) {
  constexpr Index n = Lanes<W>::kCount;
  for (; b + n <= e; b += n) neo_hookean_block<W>(c + b, q, coeff, lambda + 2 * std::size_t(b));
  if (e - b == 1) project_padded_one(c[b], q, coeff[c[b].set], lambda + 2 * std::size_t(b));
  if (e - b < 2) return;
  // A tail of two or more in the lanes as well: a one-tet lane costs more than half of all eight.
  masked_tail<n, 2>(c, b, e, lambda, [&](const auto* tail, Real* lam, int lanes) {
    neo_hookean_block<W>(tail, q, coeff, lam, lanes);
  });
}

// L::kCount shape-matching clusters of one color in the lanes (shape_match_math.hpp): correction()'s step and
// project()'s writes; only the lanes in `lanes` write positions. The clusters Newton's iteration does not take get
// the SVD's rotation lane by lane, out of line (shape_match_svd.cpp: compiled for any x86-64, one copy for both).
template <class W, bool kLambda, class Real>
[[gnu::always_inline]] inline void shape_match_block(const ShapeMatchConstraint<Real>* c, Real* q,
                                                     const SolveCoefficients<Real>* coeff, Real* lambda, int lanes) {
  using L = Lanes<W>;
  constexpr int n = L::kCount;
  Real* at[8][n];  // [corner][lane]
  lane::V3<W> p[8];
  W w[8];
  gather_corners(c, q, at, p, w);
  W k, alpha;
  lane_coefficients<W, kLambda>(c, coeff, k, alpha);
  const W lam = kLambda ? L::loadu(lambda) : L::zero();
  constexpr auto members = ShapeMatchConstraint<Real>::offsets();
  lane::V3<W> rest[8];
  for (int i = 0; i < 8; ++i)
    rest[i] = {L::of([&](int j) { return (c[j].*members[i]).x(); }), L::of([&](int j) { return (c[j].*members[i]).y(); }),
               L::of([&](int j) { return (c[j].*members[i]).z(); })};
  const W beta = L::of([&](int j) { return c[j].beta; });
  auto fallback = [&](const shape_match::math::M3<W>& a, shape_match::math::M3<W>& r, auto done) {
    const int need = lanes & ~bits(done);
    if (need == 0) return;
    alignas(64) Real in[9][n], out[9][n];
    for (int i = 0; i < 3; ++i) {
      const W ai[3] = {a.r[i].x, a.r[i].y, a.r[i].z}, ri[3] = {r.r[i].x, r.r[i].y, r.r[i].z};
      for (int j = 0; j < 3; ++j) {
        L::storeu(in[3 * i + j], ai[j]);
        L::storeu(out[3 * i + j], ri[j]);
      }
    }
    for (int lane = 0; lane < n; ++lane) {
      if (!(need >> lane & 1)) continue;
      Real a9[9], r9[9];
      for (int e = 0; e < 9; ++e) a9[e] = in[e][lane];
      shape_match::svd_rotation(a9, r9);
      for (int e = 0; e < 9; ++e) out[e][lane] = r9[e];
    }
    for (int i = 0; i < 3; ++i) r.r[i] = {L::loadu(out[3 * i]), L::loadu(out[3 * i + 1]), L::loadu(out[3 * i + 2])};
  };
  const auto r = shape_match::math::shape_match_step<Real>(p, w, rest, beta, -k, alpha, lam, fallback);
  const int active = bits(r.ok) & lanes;
  if (active == 0) return;
  if constexpr (kLambda) L::storeu(lambda, select(r.ok & (alpha != L::zero()), lam + r.dlambda, lam));
  for (int i = 0; i < 8; ++i)
    if (const int moves = active & ~bits(w[i] == L::zero())) L::add(at[i], r.dp[i].x, r.dp[i].y, r.dp[i].z, moves);
}

// A color's clusters, L::kCount at a time; a tail of two or more in the lanes too (masked_tail), one alone scalar.
template <class W, bool kLambda, class Real>
void shape_match_range(const ShapeMatchConstraint<Real>* c, Index b, Index e, Real* q,
                       const SolveCoefficients<Real>* coeff, Real* lambda) {
  constexpr Index n = Lanes<W>::kCount;
  constexpr int all = (1 << n) - 1;
  for (; b + n <= e; b += n) shape_match_block<W, kLambda>(c + b, q, coeff, lambda + b, all);
  if (e - b == 1) project_padded_one(c[b], q, coeff[c[b].set], lambda[b]);
  if (e - b < 2) return;
  masked_tail<n, 1>(c, b, e, lambda, [&](const auto* tail, Real* lam, int lanes) {
    shape_match_block<W, kLambda>(tail, q, coeff, lam, lanes);
  });
}

template <class W, bool kLambda, class C, class Real>
void lanes_range(const C* c, Index b, Index e, Real* q, const SolveCoefficients<Real>* coeff, Real* lambda) {
  constexpr Index n = Lanes<W>::kCount;
  for (; b + n <= e; b += n) lanes_block<W, kLambda>(c + b, q, coeff, lambda + b);
  for (; b < e; ++b) project_padded_one(c[b], q, coeff[c[b].set], lambda[b]);
}

template <class W, bool kLambda, class Real>
void stretch_range(const StretchConstraint<Real>* c, Index b, Index e, Real* q, const SolveCoefficients<Real>* coeff,
                   Real* lambda, Index set) {
  using L = Lanes<W>;
  constexpr Index n = L::kCount;
  W k = L::zero(), alpha = L::zero();
  if (set != kMixedSets) {
    k = L::splat(coeff[set].k);
    if constexpr (kLambda) alpha = L::splat(coeff[set].alpha_tilde);
  }
  for (; b + n <= e; b += n) {
    // the constraint and λ streams, well ahead (stretch_kernel.cpp: needed once they leave the cache, 1000² cloth)
    _mm_prefetch(reinterpret_cast<const char*>(reinterpret_cast<std::uintptr_t>(c + b) + 128 * sizeof(*c)), _MM_HINT_T0);
    if constexpr (kLambda)
      _mm_prefetch(reinterpret_cast<const char*>(reinterpret_cast<std::uintptr_t>(lambda + b) + 128 * sizeof(Real)), _MM_HINT_T0);
    stretch_block<W, kLambda>(c + b, q, coeff, lambda + b, set, k, alpha);
  }
  for (; b < e; ++b) project_padded_one(c[b], q, coeff[c[b].set], lambda[b]);
}

}  // namespace

void project_bending_range_avx2(const BendingConstraint<float>* c, Index b, Index e, float* q,
                                const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::FloatW8, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::FloatW8, false>(c, b, e, q, coeff, lambda);
}
void project_bending_range_avx2(const BendingConstraint<double>* c, Index b, Index e, double* q,
                                const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::DoubleW4, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::DoubleW4, false>(c, b, e, q, coeff, lambda);
}
void project_area_range_avx2(const AreaConstraint<float>* c, Index b, Index e, float* q,
                             const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::FloatW8, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::FloatW8, false>(c, b, e, q, coeff, lambda);
}
void project_area_range_avx2(const AreaConstraint<double>* c, Index b, Index e, double* q,
                             const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::DoubleW4, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::DoubleW4, false>(c, b, e, q, coeff, lambda);
}
void project_tet_volume_range_avx2(const TetVolumeConstraint<float>* c, Index b, Index e, float* q,
                                   const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::FloatW8, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::FloatW8, false>(c, b, e, q, coeff, lambda);
}
void project_tet_volume_range_avx2(const TetVolumeConstraint<double>* c, Index b, Index e, double* q,
                                   const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd) {
  if (any_xpbd) lanes_range<wide8::DoubleW4, true>(c, b, e, q, coeff, lambda);
  else lanes_range<wide8::DoubleW4, false>(c, b, e, q, coeff, lambda);
}
void project_shape_match_range_avx2(const ShapeMatchConstraint<float>* c, Index b, Index e, float* q,
                                    const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) shape_match_range<wide8::FloatW8, true>(c, b, e, q, coeff, lambda);
  else shape_match_range<wide8::FloatW8, false>(c, b, e, q, coeff, lambda);
}
void project_shape_match_range_avx2(const ShapeMatchConstraint<double>* c, Index b, Index e, double* q,
                                    const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd) {
  if (any_xpbd) shape_match_range<wide8::DoubleW4, true>(c, b, e, q, coeff, lambda);
  else shape_match_range<wide8::DoubleW4, false>(c, b, e, q, coeff, lambda);
}
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<float>* c, Index b, Index e, float* q,
                                    const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) neo_hookean_range<wide8::FloatW8>(c, b, e, q, coeff, lambda);
}
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<double>* c, Index b, Index e, double* q,
                                    const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd) {
  if (any_xpbd) neo_hookean_range<wide8::DoubleW4>(c, b, e, q, coeff, lambda);
}
void project_stretch_range_avx2(const StretchConstraint<double>* c, Index b, Index e, double* q,
                                const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd, Index set) {
  if (any_xpbd) stretch_range<wide8::DoubleW4, true>(c, b, e, q, coeff, lambda, set);
  else stretch_range<wide8::DoubleW4, false>(c, b, e, q, coeff, lambda, set);
}

#else  // not built for AVX2 (another architecture or compiler): avx2_enabled() is false, these are never called
void project_bending_range_avx2(const BendingConstraint<float>*, Index, Index, float*, const SolveCoefficients<float>*,
                                float*, bool) {
  std::abort();
}
void project_bending_range_avx2(const BendingConstraint<double>*, Index, Index, double*,
                                const SolveCoefficients<double>*, double*, bool) {
  std::abort();
}
void project_stretch_range_avx2(const StretchConstraint<double>*, Index, Index, double*,
                                const SolveCoefficients<double>*, double*, bool, Index) {
  std::abort();
}
void project_area_range_avx2(const AreaConstraint<float>*, Index, Index, float*, const SolveCoefficients<float>*,
                             float*, bool) {
  std::abort();
}
void project_area_range_avx2(const AreaConstraint<double>*, Index, Index, double*, const SolveCoefficients<double>*,
                             double*, bool) {
  std::abort();
}
void project_tet_volume_range_avx2(const TetVolumeConstraint<float>*, Index, Index, float*,
                                   const SolveCoefficients<float>*, float*, bool) {
  std::abort();
}
void project_shape_match_range_avx2(const ShapeMatchConstraint<float>*, Index, Index, float*,
                                    const SolveCoefficients<float>*, float*, bool) {
  std::abort();
}
void project_shape_match_range_avx2(const ShapeMatchConstraint<double>*, Index, Index, double*,
                                    const SolveCoefficients<double>*, double*, bool) {
  std::abort();
}
void project_tet_volume_range_avx2(const TetVolumeConstraint<double>*, Index, Index, double*,
                                   const SolveCoefficients<double>*, double*, bool) {
  std::abort();
}
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<float>*, Index, Index, float*,
                                    const SolveCoefficients<float>*, float*, bool) {
  std::abort();
}
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<double>*, Index, Index, double*,
                                    const SolveCoefficients<double>*, double*, bool) {
  std::abort();
}
#endif

}  // namespace pbd::detail
