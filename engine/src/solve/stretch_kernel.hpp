#pragma once
// Gauss-Seidel projection of one color's stretch constraints on padded positions, four at a time with SSE2
// (private). Padded positions hold x y z w per particle (w = inverse mass), 16-byte aligned, so a particle is one
// aligned load and one aligned store. Every lane does the operations of the scalar correction() in
// constraints/stretch.hpp in the same order with correctly rounded SSE arithmetic (no estimates), so positions and
// λ match project() bit for bit; the solver still cuts ranges at multiples of kStretchBlock from the color's start
// so that each constraint takes the same path whatever the thread count.
// Requires: no two constraints of a range share a movable particle (true within a color).
#include "pbd/constraints/stretch.hpp"
#include "pbd/detail/model.hpp"  // kMixedSets

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pbd::detail {


/// Constraints per SIMD block: parallel ranges of the stretch colors are cut at multiples of this.
inline constexpr Index kStretchBlock = 4;

/// True when the float stretch kernel runs on padded positions (an SSE2 target); otherwise every type, stretch
/// included, is projected by project() on the 3-per-particle positions.
#if defined(__SSE2__)
inline constexpr bool kPaddedStretch = true;
#else
inline constexpr bool kPaddedStretch = false;
#endif

/// Scalar projection of stretch constraint c on padded positions q (4 per particle, w in the fourth): the same
/// correction() as project() and the same writes.
inline void project_stretch_padded(const StretchConstraint<float>& c, float* q, SolveCoefficients<float> coeff,
                                   float& lambda) {
  float* qa = q + 4 * std::size_t(c.particles[0]);
  float* qb = q + 4 * std::size_t(c.particles[1]);
  const Vec3<float> pos[2] = {Vec3<float>(qa[0], qa[1], qa[2]), Vec3<float>(qb[0], qb[1], qb[2])};
  const float w[2] = {qa[3], qb[3]};
  Vec3<float> dp[2];
  float dlambda;
  if (!correction(c, pos, w, coeff, lambda, dp, dlambda)) return;
  if (coeff.alpha_tilde != 0.0f) lambda += dlambda;  // λ is kept only where it enters (projection.hpp)
  if (w[0] != 0.0f) Eigen::Map<Vec3<float>>(qa) += dp[0];
  if (w[1] != 0.0f) Eigen::Map<Vec3<float>>(qb) += dp[1];
}

#if defined(__SSE2__)
namespace sse {
template <int k> inline __m128 lane(__m128 v) { return _mm_shuffle_ps(v, v, _MM_SHUFFLE(k, k, k, k)); }
// Particle at a += s_k · d (d has w-lane 0, so w is kept), as p += (w·s)·d in the scalar projection. Reloads the
// position (nothing else wrote it since) rather than keeping eight positions in registers.
template <int k> inline void move(float* a, __m128 s, __m128 d) {
  _mm_store_ps(a, _mm_add_ps(_mm_load_ps(a), _mm_mul_ps(lane<k>(s), d)));
}
}  // namespace sse

/// Four constraints c[0, 4) of one color on padded positions q, λ in lambda[0, 4): the four corrections side by
/// side, and only the writes the scalar projection makes (movable particles of constraints that project; λ of
/// lanes with α̃ ≠ 0). kLambda = false when no set has α̃ ≠ 0: every λ is 0, so λ is neither read nor written.
/// kOneSet: the four belong to one set, whose −k and α̃ are given broadcast in neg_k1 and alpha1 (otherwise they are
/// read from coeff per block and the last two arguments are ignored).
template <bool kLambda, bool kOneSet>
[[gnu::always_inline]] inline void project_stretch_block4(const StretchConstraint<float>* c, float* q,
                                                          const SolveCoefficients<float>* coeff, float* lambda,
                                                          __m128 neg_k1, __m128 alpha1) {
  using namespace sse;
  float* const qa0 = q + 4 * std::size_t(c[0].particles[0]);
  float* const qa1 = q + 4 * std::size_t(c[1].particles[0]);
  float* const qa2 = q + 4 * std::size_t(c[2].particles[0]);
  float* const qa3 = q + 4 * std::size_t(c[3].particles[0]);
  float* const qb0 = q + 4 * std::size_t(c[0].particles[1]);
  float* const qb1 = q + 4 * std::size_t(c[1].particles[1]);
  float* const qb2 = q + 4 * std::size_t(c[2].particles[1]);
  float* const qb3 = q + 4 * std::size_t(c[3].particles[1]);
  const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  __m128 d0, d1, d2, d3, wa, wb;
  {
    const __m128 pa0 = _mm_load_ps(qa0), pa1 = _mm_load_ps(qa1), pa2 = _mm_load_ps(qa2), pa3 = _mm_load_ps(qa3);
    const __m128 pb0 = _mm_load_ps(qb0), pb1 = _mm_load_ps(qb1), pb2 = _mm_load_ps(qb2), pb3 = _mm_load_ps(qb3);
    wa = _mm_movehl_ps(_mm_unpackhi_ps(pa2, pa3), _mm_unpackhi_ps(pa0, pa1));  // w of the four particles a
    wb = _mm_movehl_ps(_mm_unpackhi_ps(pb2, pb3), _mm_unpackhi_ps(pb0, pb1));  // w of the four particles b
    d0 = _mm_and_ps(_mm_sub_ps(pa0, pb0), xyz);
    d1 = _mm_and_ps(_mm_sub_ps(pa1, pb1), xyz);
    d2 = _mm_and_ps(_mm_sub_ps(pa2, pb2), xyz);
    d3 = _mm_and_ps(_mm_sub_ps(pa3, pb3), xyz);
  }
  // Transpose: x, y, z of d across the four constraints.
  const __m128 t0 = _mm_unpacklo_ps(d0, d1), t1 = _mm_unpacklo_ps(d2, d3);  // x0 x1 y0 y1 | x2 x3 y2 y3
  const __m128 t2 = _mm_unpackhi_ps(d0, d1), t3 = _mm_unpackhi_ps(d2, d3);  // z0 z1 0 0 | z2 z3 0 0
  const __m128 dx = _mm_movelh_ps(t0, t1), dy = _mm_movehl_ps(t1, t0), dz = _mm_movelh_ps(t2, t3);
  // len2 = x² + (y² + z²), the order of Eigen's squaredNorm of a 3-vector (it halves the sum recursively).
  const __m128 len2 = _mm_add_ps(_mm_mul_ps(dx, dx), _mm_add_ps(_mm_mul_ps(dy, dy), _mm_mul_ps(dz, dz)));
  const __m128 sign = _mm_set1_ps(-0.0f);
  __m128 neg_k = neg_k1, alpha = alpha1;
  if constexpr (!kOneSet) {
    const Index set = c[0].set;
    if (c[1].set == set && c[2].set == set && c[3].set == set) {
      neg_k = _mm_xor_ps(_mm_set1_ps(coeff[set].k), sign);
      alpha = _mm_set1_ps(coeff[set].alpha_tilde);
    } else {
      neg_k = _mm_xor_ps(_mm_setr_ps(coeff[set].k, coeff[c[1].set].k, coeff[c[2].set].k, coeff[c[3].set].k), sign);
      alpha = _mm_setr_ps(coeff[set].alpha_tilde, coeff[c[1].set].alpha_tilde, coeff[c[2].set].alpha_tilde,
                          coeff[c[3].set].alpha_tilde);
    }
  }
  const __m128 denom = _mm_add_ps(_mm_add_ps(alpha, wa), wb);
  // Lanes that project: a direction exists and the denominator is positive (false for NaN, as in the scalar test).
  const __m128 zero = _mm_setzero_ps();
  const __m128 ok = _mm_and_ps(_mm_cmpgt_ps(len2, _mm_set1_ps(tiny_squared<float>())), _mm_cmpgt_ps(denom, zero));
  const int active = _mm_movemask_ps(ok);
  if (active == 0) return;
  const __m128 rest = _mm_setr_ps(c[0].rest, c[1].rest, c[2].rest, c[3].rest);
  const __m128 len = _mm_sqrt_ps(len2);
  // Without λ (every α̃ is +0, every λ 0) the scalar's "− α̃·λ" subtracts +0, which changes no bit: left out.
  __m128 num = _mm_mul_ps(neg_k, _mm_sub_ps(len, rest));
  __m128 lam = zero;
  if constexpr (kLambda) {
    lam = _mm_loadu_ps(lambda);
    num = _mm_sub_ps(num, _mm_mul_ps(alpha, lam));
  }
  const __m128 s = _mm_div_ps(num, _mm_mul_ps(denom, len));
  if constexpr (kLambda) {
    const __m128 keep = _mm_and_ps(ok, _mm_cmpneq_ps(alpha, zero));  // lanes whose λ the scalar projection adds to
    const __m128 new_lam = _mm_add_ps(lam, _mm_mul_ps(s, len));
    _mm_storeu_ps(lambda, _mm_or_ps(_mm_and_ps(keep, new_lam), _mm_andnot_ps(keep, lam)));
  }
  const __m128 sa = _mm_mul_ps(wa, s), sb = _mm_mul_ps(_mm_xor_ps(wb, sign), s);
  // A particle is written when its constraint projects and it is movable (w ≠ 0), as in project_into(). The usual
  // case, all eight, takes one test instead of eight.
  const __m128 pinned_a = _mm_cmpeq_ps(wa, zero), pinned_b = _mm_cmpeq_ps(wb, zero);
  if ((active | _mm_movemask_ps(_mm_or_ps(pinned_a, pinned_b)) << 4) == 0xF) {
    move<0>(qa0, sa, d0);
    move<0>(qb0, sb, d0);
    move<1>(qa1, sa, d1);
    move<1>(qb1, sb, d1);
    move<2>(qa2, sa, d2);
    move<2>(qb2, sb, d2);
    move<3>(qa3, sa, d3);
    move<3>(qb3, sb, d3);
    return;
  }
  const int move_a = active & ~_mm_movemask_ps(pinned_a), move_b = active & ~_mm_movemask_ps(pinned_b);
  if (move_a & 1) move<0>(qa0, sa, d0);
  if (move_b & 1) move<0>(qb0, sb, d0);
  if (move_a & 2) move<1>(qa1, sa, d1);
  if (move_b & 2) move<1>(qb1, sb, d1);
  if (move_a & 4) move<2>(qa2, sa, d2);
  if (move_b & 4) move<2>(qb2, sb, d2);
  if (move_a & 8) move<3>(qa3, sa, d3);
  if (move_b & 8) move<3>(qb3, sb, d3);
}
#endif

/// Gauss-Seidel projection of stretch constraints c[b, e) of one color on padded positions q: blocks of
/// kStretchBlock counted from b with SIMD, the remainder scalar. Same result, bit for bit, as project() one by one.
/// any_xpbd = false promises that every set of the range has α̃ = +0 (coefficients() never gives −0): λ is then
/// never touched (nor fetched).
/// set: the set every constraint of the range belongs to (k and α̃ are then read once), or kMixedSets.
/// Compiled twice (stretch_block.cpp): for AVX2 machines (three-operand encoding) and for any x86-64; a CPU check
/// on first use picks one for the process, and both do the same arithmetic.
void project_stretch_range(const StretchConstraint<float>* c, Index b, Index e, float* q,
                           const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, Index set);

/// Particles [b, e) from positions p (3 per particle) and inverse masses w into padded positions q (4 per particle).
void pad_positions(const float* p, const float* w, Index b, Index e, float* q);
/// Particles [b, e) from padded positions q back into p (3 per particle).
void unpad_positions(const float* q, Index b, Index e, float* p);

}  // namespace pbd::detail
