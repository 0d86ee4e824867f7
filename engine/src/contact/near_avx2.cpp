// AVX2 build of the particle contacts' walk over a dense grid and its pair test (near_avx2.hpp), in the 256-bit lanes of
// simd/wide_avx.hpp. This file alone among the contact files is compiled with -mavx2 -mno-fma (engine/CMakeLists.txt);
// it instantiates no inline function a file built without AVX2 does (no standard container: the pairs leave through
// the caller's sink; wide_avx.hpp is included only by AVX2 files).
#include "near_avx2.hpp"

#include "simd/wide_avx.hpp"

#include <cstdlib>

namespace pbd::detail {

#if defined(__AVX2__)
namespace {

using namespace wide8;

// x + (y + z) of three products, as the scalar dot product sums them
[[gnu::always_inline]] inline FloatW8 dot(FloatW8 ax, FloatW8 ay, FloatW8 az, FloatW8 bx, FloatW8 by, FloatW8 bz) {
  return ax * bx + (ay * by + az * bz);
}

// near_bits_avx2's test (below), for others[0, count) and a's eight floats at A
[[gnu::always_inline]] inline std::uint64_t near8(const float* movers, const float* A, const Index* others,
                                                  std::uint32_t count, float margin) {
  using L = Lanes<FloatW8>;
  const FloatW8 ax = L::splat(A[0]), ay = L::splat(A[1]), az = L::splat(A[2]);
  const FloatW8 ar = L::splat(A[3]), px = L::splat(A[4]), py = L::splat(A[5]);
  const FloatW8 pz = L::splat(A[6]), m = L::splat(margin), zero = L::zero();
  std::uint64_t bits = 0;
  for (std::uint32_t k = 0; k < count; k += 8) {
    const float* at_x[8];
    const float* at_p[8];
    for (int j = 0; j < 8; ++j) {
      at_x[j] = movers + 8 * std::size_t(others[k + j]);
      at_p[j] = at_x[j] + 4;
    }
    FloatW8 b[4], q[4];
    L::gather(at_x, b);
    L::gather(at_p, q);
    const FloatW8 R = (ar + b[3]) + m, reach = R * R;
    const FloatW8 d0x = ax - b[0], d0y = ay - b[1], d0z = az - b[2];
    const FloatW8 d1x = px - q[0], d1y = py - q[1], d1z = pz - q[2];
    const FloatW8 ex = d1x - d0x, ey = d1y - d0y, ez = d1z - d0z;
    const FloatW8 ee = dot(ex, ey, ez, ex, ey, ez), de = dot(d0x, d0y, d0z, ex, ey, ez);
    const FloatW8 q0 = dot(d0x, d0y, d0z, d0x, d0y, d0z), q1 = dot(d1x, d1y, d1z, d1x, d1y, d1z);
    const MaskF8 ahead = de >= zero;
    const MaskF8 past = -de >= ee;
    const MaskF8 start = ahead & (q0 < reach);
    const MaskF8 end = andnot(ahead, past & (q1 < reach));
    const FloatW8 gap = q0 * ee - de * de;
    const MaskF8 mid = andnot(ahead | past, gap < reach * ee);
    bits |= std::uint64_t(unsigned(wide8::bits((start | end) | mid))) << k;
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
  const IntW8 lanes = lanes_int(0, 1, 2, 3, 4, 5, 6, 7);
  // of[0, size) against a: near, and not joined to it (joined_bits' rule: the row's first two groups, the rest only
  // when a near candidate is left unmatched); each such pair appended to `near`
  auto flush = [&] {
    storeu8(of + size, splat_int(std::int32_t(a)));
    std::uint64_t bits = size > 0 ? near8(w.movers, w.movers + 8 * std::size_t(a), of, size, w.margin) : 0;
    if (bits != 0 && w.joined) {
      const Index* row = w.joined + w.joined_offsets[a];
      const Index* end = w.joined + w.joined_offsets[std::size_t(a) + 1];
      std::uint64_t joined = 0;
      auto compare = [&](const Index* from, const Index* to) {  // eight candidates against four of the row's, rotated
        for (std::uint32_t k = 0; k < size; k += 8) {
          const IntW8 c = loadu8(of + k);
          MaskI8 any = none_int();
          for (const Index* q = from; q < to; q += 4) {
            const IntW8 r = broadcast4(q);
            any = any | ((c == r) | (c == rotate<1>(r)));
            any = any | ((c == rotate<2>(r)) | (c == rotate<3>(r)));
          }
          joined |= std::uint64_t(unsigned(wide8::bits(any))) << k;
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
    const IntW8 high = splat_int(top + 1), low_end = splat_int(below + 1);
    const IntW8 stop = splat_int(std::int32_t(end));
    for (;;) {
      const Index at = from + n;  // indices and cells fit in 31 bits: signed compares
      const IntW8 cells = loadu8(w.cx + at);
      const IntW8 index = splat_int(std::int32_t(at)) + lanes;
      const MaskI8 inside = (index < stop) & (cells < high);
      const MaskI8 lower = inside & (cells < low_end);
      const Index k8 = Index(__builtin_ctz(~unsigned(wide8::bits(inside))));
      under += Index(__builtin_ctz(~unsigned(wide8::bits(lower))));
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
    storeu8(of + size, loadu8(w.pid + from));
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
