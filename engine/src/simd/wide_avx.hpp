#pragma once
// 256-bit lanes for the kernels' AVX2 builds (private; include only in a file compiled with -mavx2 -mno-fma, see
// engine/CMakeLists.txt, and call it only after avx2_enabled()): eight floats or four doubles, with the operations
// wide.hpp gives its four floats (bending_math.hpp's list), plus the gathers and scatters of padded points
// (x y z w per particle), and eight int32 lanes for the particle contacts' walk (contact/near_avx2.cpp). Each
// operation is one correctly rounded instruction per lane and there is no fused multiply-add, so a lane gives the bits
// of the scalar expression.
// Keep every function here inline and specific to these types: the file is compiled for AVX2 only, and an inline
// function it shared with the rest of the engine could be the copy the linker keeps.
#if defined(__AVX2__)
#include <immintrin.h>

#include <cstdint>

namespace pbd::detail::wide8 {

#define PBD_W8 [[gnu::always_inline]] inline

/// Eight floats; four doubles.
struct FloatW8 {
  __m256 v;
};
struct DoubleW4 {
  __m256d v;
};
/// Lane masks (all bits set = true).
struct MaskF8 {
  __m256 v;
};
struct MaskD4 {
  __m256d v;
};

// Floats.
PBD_W8 FloatW8 operator+(FloatW8 a, FloatW8 b) { return {_mm256_add_ps(a.v, b.v)}; }
PBD_W8 FloatW8 operator-(FloatW8 a, FloatW8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
PBD_W8 FloatW8 operator*(FloatW8 a, FloatW8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
PBD_W8 FloatW8 operator/(FloatW8 a, FloatW8 b) { return {_mm256_div_ps(a.v, b.v)}; }
PBD_W8 FloatW8 operator-(FloatW8 a) { return {_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))}; }
PBD_W8 FloatW8 sqrt(FloatW8 a) { return {_mm256_sqrt_ps(a.v)}; }
PBD_W8 FloatW8 min(FloatW8 a, FloatW8 b) { return {_mm256_min_ps(a.v, b.v)}; }
PBD_W8 FloatW8 max(FloatW8 a, FloatW8 b) { return {_mm256_max_ps(a.v, b.v)}; }
PBD_W8 FloatW8 abs(FloatW8 a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
PBD_W8 MaskF8 operator>(FloatW8 a, FloatW8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
PBD_W8 MaskF8 operator<(FloatW8 a, FloatW8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
PBD_W8 MaskF8 operator==(FloatW8 a, FloatW8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)}; }
PBD_W8 MaskF8 operator!=(FloatW8 a, FloatW8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)}; }
PBD_W8 MaskF8 operator>=(FloatW8 a, FloatW8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)}; }
PBD_W8 MaskF8 operator&(MaskF8 a, MaskF8 b) { return {_mm256_and_ps(a.v, b.v)}; }
PBD_W8 MaskF8 operator|(MaskF8 a, MaskF8 b) { return {_mm256_or_ps(a.v, b.v)}; }
PBD_W8 MaskF8 andnot(MaskF8 a, MaskF8 b) { return {_mm256_andnot_ps(a.v, b.v)}; }  ///< b and not a
PBD_W8 int bits(MaskF8 m) { return _mm256_movemask_ps(m.v); }
PBD_W8 bool none(MaskF8 m) { return bits(m) == 0; }
PBD_W8 FloatW8 select(MaskF8 m, FloatW8 a, FloatW8 b) { return {_mm256_blendv_ps(b.v, a.v, m.v)}; }

// Doubles.
PBD_W8 DoubleW4 operator+(DoubleW4 a, DoubleW4 b) { return {_mm256_add_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 operator-(DoubleW4 a, DoubleW4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 operator*(DoubleW4 a, DoubleW4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 operator/(DoubleW4 a, DoubleW4 b) { return {_mm256_div_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 operator-(DoubleW4 a) { return {_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))}; }
PBD_W8 DoubleW4 sqrt(DoubleW4 a) { return {_mm256_sqrt_pd(a.v)}; }
PBD_W8 DoubleW4 min(DoubleW4 a, DoubleW4 b) { return {_mm256_min_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 max(DoubleW4 a, DoubleW4 b) { return {_mm256_max_pd(a.v, b.v)}; }
PBD_W8 DoubleW4 abs(DoubleW4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
PBD_W8 MaskD4 operator>(DoubleW4 a, DoubleW4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
PBD_W8 MaskD4 operator<(DoubleW4 a, DoubleW4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
PBD_W8 MaskD4 operator==(DoubleW4 a, DoubleW4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_EQ_OQ)}; }
PBD_W8 MaskD4 operator!=(DoubleW4 a, DoubleW4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_NEQ_UQ)}; }
PBD_W8 MaskD4 operator&(MaskD4 a, MaskD4 b) { return {_mm256_and_pd(a.v, b.v)}; }
PBD_W8 MaskD4 operator|(MaskD4 a, MaskD4 b) { return {_mm256_or_pd(a.v, b.v)}; }
PBD_W8 int bits(MaskD4 m) { return _mm256_movemask_pd(m.v); }
PBD_W8 bool none(MaskD4 m) { return bits(m) == 0; }
PBD_W8 DoubleW4 select(MaskD4 m, DoubleW4 a, DoubleW4 b) { return {_mm256_blendv_pd(b.v, a.v, m.v)}; }

// Eight int32 lanes (particle ids, cells) and the lane masks of their comparisons, for the particle contacts' walk.
struct IntW8 {
  __m256i v;
};
struct MaskI8 {
  __m256i v;
};
PBD_W8 IntW8 splat_int(std::int32_t a) { return {_mm256_set1_epi32(a)}; }
PBD_W8 IntW8 lanes_int(std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d, std::int32_t e, std::int32_t f,
                       std::int32_t g, std::int32_t h) {
  return {_mm256_setr_epi32(a, b, c, d, e, f, g, h)};
}
PBD_W8 IntW8 loadu8(const std::int32_t* p) { return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))}; }
PBD_W8 IntW8 loadu8(const std::uint32_t* p) { return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))}; }
PBD_W8 void storeu8(std::uint32_t* p, IntW8 a) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), a.v); }
/// p[0..4) in both halves.
PBD_W8 IntW8 broadcast4(const std::uint32_t* p) {
  return {_mm256_broadcastsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)))};
}
PBD_W8 IntW8 operator+(IntW8 a, IntW8 b) { return {_mm256_add_epi32(a.v, b.v)}; }
PBD_W8 MaskI8 operator==(IntW8 a, IntW8 b) { return {_mm256_cmpeq_epi32(a.v, b.v)}; }
PBD_W8 MaskI8 operator<(IntW8 a, IntW8 b) { return {_mm256_cmpgt_epi32(b.v, a.v)}; }  ///< signed
PBD_W8 MaskI8 operator&(MaskI8 a, MaskI8 b) { return {_mm256_and_si256(a.v, b.v)}; }
PBD_W8 MaskI8 operator|(MaskI8 a, MaskI8 b) { return {_mm256_or_si256(a.v, b.v)}; }
PBD_W8 MaskI8 none_int() { return {_mm256_setzero_si256()}; }
PBD_W8 int bits(MaskI8 m) { return _mm256_movemask_ps(_mm256_castsi256_ps(m.v)); }
/// Within each half: lane i of the result is lane (i + k) mod 4 of a.
template <int k> PBD_W8 IntW8 rotate(IntW8 a) {
  static_assert(k > 0 && k < 4);
  return {_mm256_shuffle_epi32(a.v, (k & 3) | ((k + 1) & 3) << 2 | ((k + 2) & 3) << 4 | ((k + 3) & 3) << 6)};
}

/// What a kernel needs of a lane type beyond arithmetic: its scalar, its lane count, constants, per-lane values,
/// λ in and out, and padded points gathered into x, y, z and w across lanes and added back.
template <class W> struct Lanes;

template <> struct Lanes<FloatW8> {
  using Real = float;
  static constexpr int kCount = 8;
  PBD_W8 static FloatW8 splat(float a) { return {_mm256_set1_ps(a)}; }
  PBD_W8 static FloatW8 zero() { return {_mm256_setzero_ps()}; }
  template <class F> PBD_W8 static FloatW8 of(const F& f) {
    return {_mm256_setr_ps(f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7))};
  }
  PBD_W8 static FloatW8 loadu(const float* p) { return {_mm256_loadu_ps(p)}; }
  PBD_W8 static void storeu(float* p, FloatW8 a) { _mm256_storeu_ps(p, a.v); }
  /// p[0..16) as eight pairs: the first of each pair → first, the second → second.
  PBD_W8 static void load_pairs(const float* p, FloatW8& first, FloatW8& second) {
    const __m256 a = _mm256_loadu_ps(p), b = _mm256_loadu_ps(p + 8);  // pairs 0..3 | pairs 4..7
    const __m256d x = _mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)));  // 0 1 4 5 | 2 3 6 7
    const __m256d y = _mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)));
    first = {_mm256_castpd_ps(_mm256_permute4x64_pd(x, _MM_SHUFFLE(3, 1, 2, 0)))};
    second = {_mm256_castpd_ps(_mm256_permute4x64_pd(y, _MM_SHUFFLE(3, 1, 2, 0)))};
  }
  /// The inverse of load_pairs: p[2j] = first[j], p[2j + 1] = second[j].
  PBD_W8 static void store_pairs(float* p, FloatW8 first, FloatW8 second) {
    const __m256 lo = _mm256_unpacklo_ps(first.v, second.v), hi = _mm256_unpackhi_ps(first.v, second.v);  // 0 1 | 4 5, 2 3 | 6 7
    _mm256_storeu_ps(p, _mm256_permute2f128_ps(lo, hi, 0x20));
    _mm256_storeu_ps(p + 8, _mm256_permute2f128_ps(lo, hi, 0x31));
  }
  /// Points at[0..8) (x y z w, 16-byte aligned; P: float* or const float*) → x, y, z, w across the lanes.
  template <class P> PBD_W8 static void gather(P const (&at)[8], FloatW8 (&xyzw)[4]) {
    __m256 r[4];
    for (int j = 0; j < 4; ++j)  // lane j holds point j in its low half and point j + 4 in its high half
      r[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(at[j])), _mm_load_ps(at[j + 4]), 1);
    transpose(r, xyzw);
  }
  /// Four floats at each of at[0..8) (any alignment) → the first, second, third and fourth across the lanes.
  PBD_W8 static void gather_unaligned(const float* const (&at)[8], FloatW8 (&out)[4]) {
    __m256 r[4];
    for (int j = 0; j < 4; ++j)
      r[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(at[j])), _mm_loadu_ps(at[j + 4]), 1);
    transpose(r, out);
  }
  /// r[j]: four floats of item j in its low half and of item j + 4 in its high half → each float across the lanes.
  PBD_W8 static void transpose(const __m256 (&r)[4], FloatW8 (&xyzw)[4]) {
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpacklo_ps(r[2], r[3]);  // x0 x1 y0 y1 | ...
    const __m256 t2 = _mm256_unpackhi_ps(r[0], r[1]), t3 = _mm256_unpackhi_ps(r[2], r[3]);  // z0 z1 w0 w1 | ...
    xyzw[0] = {_mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0))};
    xyzw[1] = {_mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2))};
    xyzw[2] = {_mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0))};
    xyzw[3] = {_mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2))};
  }
  /// at[j] += (x, y, z) of lane j, for the lanes set in `moves` (w kept).
  PBD_W8 static void add(float* const (&at)[8], FloatW8 x, FloatW8 y, FloatW8 z, int moves) {
    const __m256 o = _mm256_setzero_ps();
    const __m256 t0 = _mm256_unpacklo_ps(x.v, y.v), t1 = _mm256_unpacklo_ps(z.v, o);  // x0 y0 x1 y1 | z0 0 z1 0
    const __m256 t2 = _mm256_unpackhi_ps(x.v, y.v), t3 = _mm256_unpackhi_ps(z.v, o);  // x2 y2 x3 y3 | z2 0 z3 0
    const __m256 r[4] = {_mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0)), _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2)),
                         _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0)), _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2))};
    for (int j = 0; j < 4; ++j) {
      if (moves >> j & 1) _mm_store_ps(at[j], _mm_add_ps(_mm_load_ps(at[j]), _mm256_castps256_ps128(r[j])));
      if (moves >> (j + 4) & 1) _mm_store_ps(at[j + 4], _mm_add_ps(_mm_load_ps(at[j + 4]), _mm256_extractf128_ps(r[j], 1)));
    }
  }
};

template <> struct Lanes<DoubleW4> {
  using Real = double;
  static constexpr int kCount = 4;
  PBD_W8 static DoubleW4 splat(double a) { return {_mm256_set1_pd(a)}; }
  PBD_W8 static DoubleW4 zero() { return {_mm256_setzero_pd()}; }
  template <class F> PBD_W8 static DoubleW4 of(const F& f) { return {_mm256_setr_pd(f(0), f(1), f(2), f(3))}; }
  PBD_W8 static DoubleW4 loadu(const double* p) { return {_mm256_loadu_pd(p)}; }
  PBD_W8 static void storeu(double* p, DoubleW4 a) { _mm256_storeu_pd(p, a.v); }
  /// p[0..8) as four pairs: the first of each pair → first, the second → second.
  PBD_W8 static void load_pairs(const double* p, DoubleW4& first, DoubleW4& second) {
    const __m256d a = _mm256_loadu_pd(p), b = _mm256_loadu_pd(p + 4);  // pairs 0, 1 | pairs 2, 3
    first = {_mm256_permute4x64_pd(_mm256_unpacklo_pd(a, b), _MM_SHUFFLE(3, 1, 2, 0))};   // from 0 2 1 3
    second = {_mm256_permute4x64_pd(_mm256_unpackhi_pd(a, b), _MM_SHUFFLE(3, 1, 2, 0))};
  }
  /// The inverse of load_pairs: p[2j] = first[j], p[2j + 1] = second[j].
  PBD_W8 static void store_pairs(double* p, DoubleW4 first, DoubleW4 second) {
    const __m256d lo = _mm256_unpacklo_pd(first.v, second.v), hi = _mm256_unpackhi_pd(first.v, second.v);  // 0 | 2, 1 | 3
    _mm256_storeu_pd(p, _mm256_permute2f128_pd(lo, hi, 0x20));
    _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(lo, hi, 0x31));
  }
  /// Points at[0..4) (x y z w, 32-byte aligned) → x, y, z, w across the lanes.
  PBD_W8 static void gather(double* const (&at)[4], DoubleW4 (&xyzw)[4]) {
    const __m256d r0 = _mm256_load_pd(at[0]), r1 = _mm256_load_pd(at[1]), r2 = _mm256_load_pd(at[2]),
                  r3 = _mm256_load_pd(at[3]);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);  // x0 x1 z0 z1 | y0 y1 w0 w1
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);  // x2 x3 z2 z3 | y2 y3 w2 w3
    xyzw[0] = {_mm256_permute2f128_pd(t0, t2, 0x20)};
    xyzw[1] = {_mm256_permute2f128_pd(t1, t3, 0x20)};
    xyzw[2] = {_mm256_permute2f128_pd(t0, t2, 0x31)};
    xyzw[3] = {_mm256_permute2f128_pd(t1, t3, 0x31)};
  }
  PBD_W8 static void add(double* const (&at)[4], DoubleW4 x, DoubleW4 y, DoubleW4 z, int moves) {
    const __m256d o = _mm256_setzero_pd();
    const __m256d t0 = _mm256_unpacklo_pd(x.v, y.v), t1 = _mm256_unpackhi_pd(x.v, y.v);  // x0 y0 x2 y2 | x1 y1 x3 y3
    const __m256d t2 = _mm256_unpacklo_pd(z.v, o), t3 = _mm256_unpackhi_pd(z.v, o);      // z0 0 z2 0 | z1 0 z3 0
    const __m256d r[4] = {_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
                          _mm256_permute2f128_pd(t0, t2, 0x31), _mm256_permute2f128_pd(t1, t3, 0x31)};
    for (int j = 0; j < 4; ++j)
      if (moves >> j & 1) _mm256_store_pd(at[j], _mm256_add_pd(_mm256_load_pd(at[j]), r[j]));
  }
};

#undef PBD_W8

}  // namespace pbd::detail::wide8
#endif
