// AVX2 build of the particle contacts' walk over a dense grid and its pair test (near_avx2.hpp). This file alone among
// the contact files is compiled with -mavx2 -mno-fma (engine/CMakeLists.txt); it instantiates no inline function another
// file does (no standard container: the pairs leave through the caller's sink).
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

// near_bits_avx2's test (below), for others[0, count) and a's eight floats at A
[[gnu::always_inline]] inline std::uint64_t near8(const float* movers, const float* A, const Index* others,
                                                  std::uint32_t count, float margin) {
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

}  // namespace

std::uint64_t near_bits_avx2(const float* movers, Index a, const Index* others, std::uint32_t count, float margin) {
  return near8(movers, movers + 8 * std::size_t(a), others, count, margin);
}

void walk_dense_avx2(const DenseWalk& w, Index first, Index last, NearSink sink, void* context) {
  constexpr std::uint32_t kSize = 64;  // candidates tested together at most
  alignas(32) Index of[kSize + 8];
  constexpr std::size_t kPairs = 64;   // near pairs handed to the sink at a time
  Index pairs[2 * kPairs];
  std::size_t found = 0;
  std::uint32_t size = 0;
  Index a = 0;
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  // of[0, size) against a: near, and not joined to it (joined_bits' rule: the row's first two groups, the rest only
  // when a near candidate is left unmatched); each such pair appended to `near`
  auto flush = [&] {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(of + size), _mm256_set1_epi32(std::int32_t(a)));
    std::uint64_t bits = size > 0 ? near8(w.movers, w.movers + 8 * std::size_t(a), of, size, w.margin) : 0;
    if (bits != 0 && w.joined) {
      const Index* row = w.joined + w.joined_offsets[a];
      const Index* end = w.joined + w.joined_offsets[std::size_t(a) + 1];
      std::uint64_t joined = 0;
      auto compare = [&](const Index* from, const Index* to) {  // eight candidates against four of the row's, rotated
        for (std::uint32_t k = 0; k < size; k += 8) {
          const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(of + k));
          __m256i any = _mm256_setzero_si256();
          for (const Index* q = from; q < to; q += 4) {
            const __m256i r = _mm256_broadcastsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q)));
            any = _mm256_or_si256(any, _mm256_or_si256(_mm256_cmpeq_epi32(c, r),
                                                       _mm256_cmpeq_epi32(c, _mm256_shuffle_epi32(r, 0x39))));
            any = _mm256_or_si256(any, _mm256_or_si256(_mm256_cmpeq_epi32(c, _mm256_shuffle_epi32(r, 0x4e)),
                                                       _mm256_cmpeq_epi32(c, _mm256_shuffle_epi32(r, 0x93))));
          }
          joined |= std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(any)))) << k;
        }
      };
      const Index* split = end - row > 4 * kJoinedFirstGroups ? row + 4 * kJoinedFirstGroups : end;
      compare(row, split);
      if ((bits & ~joined) != 0 && split < end) compare(split, end);
      bits &= ~joined;
    }
    for (; bits != 0; bits &= bits - 1) {
      if (found == kPairs) {
        sink(context, pairs, found);
        found = 0;
      }
      pairs[2 * found] = a;
      pairs[2 * found + 1] = of[__builtin_ctzll(bits)];
      ++found;
    }
    size = 0;
  };
  // entries [from, end) whose cells along x are at most `top`, eight at a time (the arrays run eight past the last
  // entry); of those, the prefix whose cells are at most `below`
  auto upto = [&](Index from, Index end, std::int32_t below, std::int32_t top, Index& under) {
    Index n = 0;
    under = 0;
    const __m256i high = _mm256_set1_epi32(top + 1), low_end = _mm256_set1_epi32(below + 1);
    const __m256i stop = _mm256_set1_epi32(std::int32_t(end));
    for (;;) {
      const Index at = from + n;  // indices and cells fit in 31 bits: signed compares
      const __m256i cells = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w.cx + at));
      const __m256i index = _mm256_add_epi32(_mm256_set1_epi32(std::int32_t(at)), lanes);
      const __m256i inside = _mm256_and_si256(_mm256_cmpgt_epi32(stop, index), _mm256_cmpgt_epi32(high, cells));
      const __m256i lower = _mm256_and_si256(inside, _mm256_cmpgt_epi32(low_end, cells));
      const Index k8 = Index(__builtin_ctz(~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(inside)))));
      under += Index(__builtin_ctz(~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(lower)))));
      n += k8;
      if (k8 < 8) return n;
    }
  };
  auto take = [&](Index from, Index count) {  // entries [from, from + count) join a's candidates
    if (size + count > kSize) {  // a crowded cell: one at a time
      for (Index k = 0; k < count; ++k) {
        if (size == kSize) flush();
        of[size++] = w.pid[from + k];
      }
      return;
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(of + size),
                        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w.pid + from)));
    for (Index k = 8; k < count; ++k) of[size + k] = w.pid[from + k];
    size += count;
  };
  for (Index b = first; b < last; ++b) {
    const Index r0 = w.start[b], r1 = w.start[b + 1];
    if (r0 == r1) continue;
    Index nw[4], nw1[4];  // the neighbouring rows' entries, walked along with this row
    for (int q = 0; q < 4; ++q) {
      nw[q] = w.start[b + w.row_step[q]];
      nw1[q] = w.start[b + w.row_step[q] + 1];
    }
    for (Index s = r0; s < r1; ++s) {
      const std::int32_t x = w.cx[s];
      a = w.pid[s];
      if (w.joined) __builtin_prefetch(w.joined + w.joined_offsets[w.pid[s + 2]]);  // pid runs 8 past
      Index under;
      take(s + 1, upto(s + 1, r1, x, x + 1, under));  // its own cell (after s) and the next along x
      for (int q = 0; q < 4; ++q) {  // the neighbouring rows' cells x − 1, x, x + 1
        const Index n = upto(nw[q], nw1[q], x - 2, x + 1, under);
        nw[q] += under;
        take(nw[q], n - under);
      }
      flush();
    }
  }
  if (found > 0) sink(context, pairs, found);
}
#else  // not built for AVX2: avx2_enabled() is false, these are never called
std::uint64_t near_bits_avx2(const float*, Index, const Index*, std::uint32_t, float) { std::abort(); }
void walk_dense_avx2(const DenseWalk&, Index, Index, NearSink, void*) { std::abort(); }
#endif

}  // namespace pbd::detail
