#pragma once
// A thin wide-float layer (private) so that SIMD kernels read like the scalar math they match bit for bit: four
// float lanes (SSE2) with the arithmetic operators, comparisons giving lane masks, select, and the loads, stores and
// shuffles the kernels need; and four int32 lanes with the few operations the particle contacts' grid needs (cells,
// counts, particle ids compared four at a time). Every operation is one correctly rounded instruction per lane (no
// estimates, no fused multiply-add), so an expression gives each lane the bits the same scalar expression gives.
// Box2D's b2FloatW helpers (contact_solver.c) are the model. Used by solve/ (the kernels) and contact/ (the broad
// phase); the 256-bit lanes of the AVX2 files are wide_avx.hpp.
#if defined(__SSE2__)
#include <emmintrin.h>

#include <cstdint>

namespace pbd::detail::wide {

#define PBD_WIDE [[gnu::always_inline]] inline

/// Four floats, one per lane.
struct FloatW {
  __m128 v;
};
/// Four lane masks (all bits set = true), from comparisons.
struct MaskW {
  __m128 v;
};

PBD_WIDE FloatW operator+(FloatW a, FloatW b) { return {_mm_add_ps(a.v, b.v)}; }
PBD_WIDE FloatW operator-(FloatW a, FloatW b) { return {_mm_sub_ps(a.v, b.v)}; }
PBD_WIDE FloatW operator*(FloatW a, FloatW b) { return {_mm_mul_ps(a.v, b.v)}; }
PBD_WIDE FloatW operator/(FloatW a, FloatW b) { return {_mm_div_ps(a.v, b.v)}; }
/// −a: flips the sign bit (exact, as the scalar unary minus).
PBD_WIDE FloatW operator-(FloatW a) { return {_mm_xor_ps(a.v, _mm_set1_ps(-0.0f))}; }
PBD_WIDE FloatW sqrt(FloatW a) { return {_mm_sqrt_ps(a.v)}; }
/// Lane by lane: the smaller (larger) of a and b; for numbers, as std::min (std::max).
PBD_WIDE FloatW min(FloatW a, FloatW b) { return {_mm_min_ps(a.v, b.v)}; }
PBD_WIDE FloatW max(FloatW a, FloatW b) { return {_mm_max_ps(a.v, b.v)}; }
/// |a|: clears the sign bit (exact, as std::abs).
PBD_WIDE FloatW abs(FloatW a) { return {_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)}; }

PBD_WIDE MaskW operator>(FloatW a, FloatW b) { return {_mm_cmpgt_ps(a.v, b.v)}; }   ///< false for NaN
PBD_WIDE MaskW operator<(FloatW a, FloatW b) { return {_mm_cmplt_ps(a.v, b.v)}; }   ///< false for NaN
PBD_WIDE MaskW operator>=(FloatW a, FloatW b) { return {_mm_cmpge_ps(a.v, b.v)}; }  ///< false for NaN
PBD_WIDE MaskW operator==(FloatW a, FloatW b) { return {_mm_cmpeq_ps(a.v, b.v)}; }
PBD_WIDE MaskW operator!=(FloatW a, FloatW b) { return {_mm_cmpneq_ps(a.v, b.v)}; }
PBD_WIDE MaskW operator&(MaskW a, MaskW b) { return {_mm_and_ps(a.v, b.v)}; }
PBD_WIDE MaskW operator|(MaskW a, MaskW b) { return {_mm_or_ps(a.v, b.v)}; }
/// Lane by lane: b and not a.
PBD_WIDE MaskW andnot(MaskW a, MaskW b) { return {_mm_andnot_ps(a.v, b.v)}; }
/// Bit k set when lane k is true.
PBD_WIDE int bits(MaskW m) { return _mm_movemask_ps(m.v); }
/// Lane by lane: m ? a : b.
PBD_WIDE FloatW select(MaskW m, FloatW a, FloatW b) { return {_mm_or_ps(_mm_and_ps(m.v, a.v), _mm_andnot_ps(m.v, b.v))}; }

PBD_WIDE FloatW zero() { return {_mm_setzero_ps()}; }
PBD_WIDE FloatW splat(float a) { return {_mm_set1_ps(a)}; }                                      ///< a in every lane
PBD_WIDE FloatW lanes(float a, float b, float c, float d) { return {_mm_setr_ps(a, b, c, d)}; }  ///< lanes 0..3
PBD_WIDE FloatW load(const float* p) { return {_mm_load_ps(p)}; }     ///< 16-byte aligned
PBD_WIDE FloatW loadu(const float* p) { return {_mm_loadu_ps(p)}; }   ///< unaligned
PBD_WIDE void store(float* p, FloatW a) { _mm_store_ps(p, a.v); }     ///< 16-byte aligned
PBD_WIDE void storeu(float* p, FloatW a) { _mm_storeu_ps(p, a.v); }   ///< unaligned
/// p[0..2] in lanes 0..2, 0 in lane 3 (reads three floats only).
PBD_WIDE FloatW load3(const float* p) {
  return {_mm_movelh_ps(_mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(p)), _mm_load_ss(p + 2))};
}
/// Lanes 0..2 of a, then w in lane 3.
PBD_WIDE FloatW with_w(FloatW a, float w) {
  const __m128 tail = _mm_shuffle_ps(a.v, _mm_set_ss(w), _MM_SHUFFLE(0, 0, 2, 2));  // a2, a2, w, w
  return {_mm_shuffle_ps(a.v, tail, _MM_SHUFFLE(2, 0, 1, 0))};
}
/// Lane k of a in every lane.
template <int k> PBD_WIDE FloatW broadcast(FloatW a) { return {_mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(k, k, k, k))}; }
/// x y z of a point held as x y z w, with the w lane set to 0.
PBD_WIDE FloatW xyz(FloatW a) { return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)))}; }

/// Three coordinates of four vectors, one vector per lane.
struct Vec3W {
  FloatW x, y, z;
};
/// Four points held as x y z w (one per argument) → their x, y and z across lanes.
PBD_WIDE Vec3W transpose_xyz(FloatW a, FloatW b, FloatW c, FloatW d) {
  const __m128 t0 = _mm_unpacklo_ps(a.v, b.v), t1 = _mm_unpacklo_ps(c.v, d.v);  // x0 x1 y0 y1 | x2 x3 y2 y3
  const __m128 t2 = _mm_unpackhi_ps(a.v, b.v), t3 = _mm_unpackhi_ps(c.v, d.v);  // z0 z1 w0 w1 | z2 z3 w2 w3
  return {{_mm_movelh_ps(t0, t1)}, {_mm_movehl_ps(t1, t0)}, {_mm_movelh_ps(t2, t3)}};
}
/// The w lanes of four points held as x y z w.
PBD_WIDE FloatW transpose_w(FloatW a, FloatW b, FloatW c, FloatW d) {
  return {_mm_movehl_ps(_mm_unpackhi_ps(c.v, d.v), _mm_unpackhi_ps(a.v, b.v))};
}
/// The inverse of transpose_xyz: four vectors given by their x, y and z across lanes → one per lane as x y z 0.
PBD_WIDE void transpose_points(const Vec3W& v, FloatW (&out)[4]) {
  const __m128 xy01 = _mm_unpacklo_ps(v.x.v, v.y.v), xy23 = _mm_unpackhi_ps(v.x.v, v.y.v);  // x0 y0 x1 y1 | x2 y2 x3 y3
  const __m128 z = v.z.v, o = _mm_setzero_ps();
  const __m128 z01 = _mm_unpacklo_ps(z, o), z23 = _mm_unpackhi_ps(z, o);  // z0 0 z1 0 | z2 0 z3 0
  out[0] = {_mm_movelh_ps(xy01, z01)};
  out[1] = {_mm_movehl_ps(z01, xy01)};
  out[2] = {_mm_movelh_ps(xy23, z23)};
  out[3] = {_mm_movehl_ps(z23, xy23)};
}
/// |v|² as Eigen computes it for a 3-vector: x² + (y² + z²).
PBD_WIDE FloatW squared_norm(const Vec3W& v) { return v.x * v.x + (v.y * v.y + v.z * v.z); }

/// Four int32 lanes; lane masks of their comparisons (all bits set = true).
struct IntW {
  __m128i v;
};
struct MaskIW {
  __m128i v;
};

PBD_WIDE IntW splat_int(std::int32_t a) { return {_mm_set1_epi32(a)}; }  ///< a in every lane
PBD_WIDE IntW lanes_int(std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d) {  ///< lanes 0..3
  return {_mm_setr_epi32(a, b, c, d)};
}
PBD_WIDE IntW loadu(const std::int32_t* p) { return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))}; }  ///< unaligned
PBD_WIDE IntW loadu(const std::uint32_t* p) { return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))}; }  ///< the bits
PBD_WIDE void store(std::int32_t* p, IntW a) { _mm_store_si128(reinterpret_cast<__m128i*>(p), a.v); }  ///< 16-byte aligned
PBD_WIDE IntW operator+(IntW a, IntW b) { return {_mm_add_epi32(a.v, b.v)}; }  ///< wraps, as unsigned addition
PBD_WIDE MaskIW operator==(IntW a, IntW b) { return {_mm_cmpeq_epi32(a.v, b.v)}; }
PBD_WIDE MaskIW operator<(IntW a, IntW b) { return {_mm_cmplt_epi32(a.v, b.v)}; }  ///< signed
PBD_WIDE MaskIW operator&(MaskIW a, MaskIW b) { return {_mm_and_si128(a.v, b.v)}; }
PBD_WIDE MaskIW operator|(MaskIW a, MaskIW b) { return {_mm_or_si128(a.v, b.v)}; }
/// Every lane false.
PBD_WIDE MaskIW none_int() { return {_mm_setzero_si128()}; }
/// Bit k set when lane k is true.
PBD_WIDE int bits(MaskIW m) { return _mm_movemask_ps(_mm_castsi128_ps(m.v)); }
/// Lane i of the result is lane (i + k) mod 4 of a.
template <int k> PBD_WIDE IntW rotate(IntW a) {
  static_assert(k > 0 && k < 4);
  return {_mm_shuffle_epi32(a.v, (k & 3) | ((k + 1) & 3) << 2 | ((k + 2) & 3) << 4 | ((k + 3) & 3) << 6)};
}
/// floor(a) per lane, for lanes within the int32 range (clamp first): toward zero, then one down where that rounded
/// up (the comparison's mask is −1 there).
PBD_WIDE IntW floor_to_int(FloatW a) {
  const __m128i t = _mm_cvttps_epi32(a.v);
  return {_mm_add_epi32(t, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(t), a.v)))};
}

#undef PBD_WIDE

}  // namespace pbd::detail::wide
#endif
