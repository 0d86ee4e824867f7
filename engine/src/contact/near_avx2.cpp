// AVX2 build of the particle contacts' pair test (near_avx2.hpp). This file alone among the contact files is compiled
// with -mavx2 -mno-fma (engine/CMakeLists.txt); it instantiates no inline function another file does.
#include "near_avx2.hpp"

#include <cstdlib>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace pbd::detail {

#if defined(__AVX2__)
namespace {

// Points at[0..8) (four floats each, 16-byte aligned) → their four coordinates across the lanes.
[[gnu::always_inline]] inline void gather(const float* const (&at)[8], __m256 (&xyzw)[4]) {
  __m256 r[4];
  for (int j = 0; j < 4; ++j)  // lane j holds point j in its low half and point j + 4 in its high half
    r[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(at[j])), _mm_load_ps(at[j + 4]), 1);
  const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpacklo_ps(r[2], r[3]);
  const __m256 t2 = _mm256_unpackhi_ps(r[0], r[1]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
  xyzw[0] = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
  xyzw[1] = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
  xyzw[2] = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
  xyzw[3] = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2));
}

// x + (y + z) of three products, as the scalar dot product sums them
[[gnu::always_inline]] inline __m256 dot(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
  return _mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_add_ps(_mm256_mul_ps(ay, by), _mm256_mul_ps(az, bz)));
}

}  // namespace

std::uint64_t near_bits_avx2(const float* movers, Index a, const Index* others, std::uint32_t count, float margin) {
  const float* A = movers + 8 * std::size_t(a);
  const __m256 ax = _mm256_set1_ps(A[0]), ay = _mm256_set1_ps(A[1]), az = _mm256_set1_ps(A[2]);
  const __m256 ar = _mm256_set1_ps(A[3]), px = _mm256_set1_ps(A[4]), py = _mm256_set1_ps(A[5]);
  const __m256 pz = _mm256_set1_ps(A[6]), m = _mm256_set1_ps(margin), zero = _mm256_setzero_ps();
  std::uint64_t bits = 0;
  for (std::uint32_t k = 0; k < count; k += 8) {
    const float* at_x[8];
    const float* at_p[8];
    for (int j = 0; j < 8; ++j) {
      at_x[j] = movers + 8 * std::size_t(others[k + j]);
      at_p[j] = at_x[j] + 4;
    }
    __m256 b[4], q[4];
    gather(at_x, b);
    gather(at_p, q);
    const __m256 R = _mm256_add_ps(_mm256_add_ps(ar, b[3]), m), reach = _mm256_mul_ps(R, R);
    const __m256 d0x = _mm256_sub_ps(ax, b[0]), d0y = _mm256_sub_ps(ay, b[1]), d0z = _mm256_sub_ps(az, b[2]);
    const __m256 d1x = _mm256_sub_ps(px, q[0]), d1y = _mm256_sub_ps(py, q[1]), d1z = _mm256_sub_ps(pz, q[2]);
    const __m256 ex = _mm256_sub_ps(d1x, d0x), ey = _mm256_sub_ps(d1y, d0y), ez = _mm256_sub_ps(d1z, d0z);
    const __m256 ee = dot(ex, ey, ez, ex, ey, ez), de = dot(d0x, d0y, d0z, ex, ey, ez);
    const __m256 q0 = dot(d0x, d0y, d0z, d0x, d0y, d0z), q1 = dot(d1x, d1y, d1z, d1x, d1y, d1z);
    const __m256 ahead = _mm256_cmp_ps(de, zero, _CMP_GE_OQ);
    const __m256 past = _mm256_cmp_ps(_mm256_xor_ps(de, _mm256_set1_ps(-0.0f)), ee, _CMP_GE_OQ);
    const __m256 start = _mm256_and_ps(ahead, _mm256_cmp_ps(q0, reach, _CMP_LT_OQ));
    const __m256 end = _mm256_andnot_ps(ahead, _mm256_and_ps(past, _mm256_cmp_ps(q1, reach, _CMP_LT_OQ)));
    const __m256 gap = _mm256_sub_ps(_mm256_mul_ps(q0, ee), _mm256_mul_ps(de, de));
    const __m256 mid = _mm256_andnot_ps(_mm256_or_ps(ahead, past),
                                        _mm256_cmp_ps(gap, _mm256_mul_ps(reach, ee), _CMP_LT_OQ));
    bits |= std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(start, end), mid)))) << k;
  }
  return count == 64 ? bits : bits & ((std::uint64_t(1) << count) - 1);
}
#else  // not built for AVX2: avx2_enabled() is false, this is never called
std::uint64_t near_bits_avx2(const float*, Index, const Index*, std::uint32_t, float) { std::abort(); }
#endif

}  // namespace pbd::detail
