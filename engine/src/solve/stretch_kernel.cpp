#include "stretch_kernel.hpp"

#include "kernels_avx2.hpp"

#include <algorithm>
#include <cassert>
#include <cstdint>

namespace pbd::detail {

namespace {

using RangeFn = void (*)(const StretchConstraint<float>*, Index, Index, float*, const SolveCoefficients<float>*,
                         float*, bool, Index);
using InterleavedFn = void (*)(const StretchConstraint<float>*, const Index*, Index, Index, float*,
                               const SolveCoefficients<float>*, float*, bool, bool);

#if defined(__SSE2__)
// Software prefetch of the constraint and λ streams kPrefetchAhead constraints ahead of the block being projected.
// Once these streams no longer fit in cache (a 1000² cloth: 3M constraints), the hardware prefetcher alone does not
// keep ahead of the kernel, and a projection waits on memory (docs/performance.md). A prefetch never faults, so reaching past the range's end is
// harmless; the address is formed as an integer so no out-of-bounds pointer is ever made.
constexpr std::size_t kPrefetchAhead = 128;  // 2 KB of constraints, 512 B of λ
[[gnu::always_inline]] inline void prefetch_ahead(const void* p, std::size_t bytes) {
  _mm_prefetch(reinterpret_cast<const char*>(reinterpret_cast<std::uintptr_t>(p) + bytes), _MM_HINT_T0);
}
#endif

// kLambda = false (no set has α̃ ≠ 0): λ is neither read nor written, so its stream is not fetched either.
template <bool kLambda, bool kOneSet>
[[gnu::always_inline]] inline void range_body(const StretchConstraint<float>* c, Index b, Index e, float* q,
                                              const SolveCoefficients<float>* coeff, float* lambda, Index set) {
#if defined(__SSE2__)
  if (e - b >= kStretchBlock) {
    wide::FloatW neg_k = wide::zero(), alpha = wide::zero();
    if constexpr (kOneSet) {
      neg_k = wide::splat(-coeff[set].k);
      alpha = wide::splat(coeff[set].alpha_tilde);
    }
    const StretchConstraint<float>* const last = c + (e - kStretchBlock);
    const StretchConstraint<float>* it = c + b;
    float* lam = lambda + b;
    for (; it <= last; it += kStretchBlock, lam += kStretchBlock) {
      prefetch_ahead(it, kPrefetchAhead * sizeof(*it));  // a block is 64 bytes: every line gets one
      if constexpr (kLambda) prefetch_ahead(lam, kPrefetchAhead * sizeof(*lam));
      project_stretch_block4<kLambda, kOneSet>(it, q, coeff, lam, neg_k, alpha);
    }
    b = Index(it - c);
  }
#endif
  for (; b < e; ++b) project_stretch_padded(c[b], q, coeff[c[b].set], lambda[b]);
}

[[gnu::always_inline]] inline void range_either(const StretchConstraint<float>* c, Index b, Index e, float* q,
                                                const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd,
                                                Index set) {
  if (set != kMixedSets) {
    if (any_xpbd) range_body<true, true>(c, b, e, q, coeff, lambda, set);
    else range_body<false, true>(c, b, e, q, coeff, lambda, set);
  } else {
    if (any_xpbd) range_body<true, false>(c, b, e, q, coeff, lambda, set);
    else range_body<false, false>(c, b, e, q, coeff, lambda, set);
  }
}

// The k-th constraints of four independent ranges starting at begin[0..4), four lanes at once, read in place; λ
// gathered into four lanes and scattered back. interleaved_body runs kChains / 4 of these per k, so the
// core overlaps that many independent chains (the k-th and k+1-th constraints of one range mostly share a
// particle, so one group of four alone waits on its square roots; docs/performance.md has the measured gain).
template <bool kLambda>
[[gnu::always_inline]] inline void interleaved_one(const StretchConstraint<float>* items, const Index* begin, Index k,
                                                   float* q, const SolveCoefficients<float>* coeff, float* lambda) {
#if defined(__SSE2__)
  const StretchConstraint<float>* const c[4] = {items + begin[0] + k, items + begin[1] + k, items + begin[2] + k,
                                                items + begin[3] + k};
  float lam[4] = {0, 0, 0, 0};
  if constexpr (kLambda)
    for (int j = 0; j < 4; ++j) lam[j] = lambda[begin[j] + k];
  project_stretch_block4_of<kLambda, false>([&c](int j) -> const StretchConstraint<float>& { return *c[j]; }, q,
                                            coeff, lam, wide::zero(), wide::zero());
  if constexpr (kLambda)
    for (int j = 0; j < 4; ++j) lambda[begin[j] + k] = lam[j];
#else
  for (int j = 0; j < 4; ++j) {
    const Index i = begin[j] + k;
    project_stretch_padded(items[i], q, coeff[items[i].set], lambda[i]);
  }
#endif
}

template <bool kLambda, Index kChains>
[[gnu::always_inline]] inline void interleaved_chains(const StretchConstraint<float>* items, const Index* begin,
                                                      Index common, float* q, const SolveCoefficients<float>* coeff,
                                                      float* lambda, bool reverse) {
  if (reverse) {
    for (Index k = common; k-- > 0;)
      for (Index g = 0; g < kChains; g += 4) interleaved_one<kLambda>(items, begin + g, k, q, coeff, lambda);
  } else {
    for (Index k = 0; k < common; ++k)
      for (Index g = 0; g < kChains; g += 4) interleaved_one<kLambda>(items, begin + g, k, q, coeff, lambda);
  }
}

template <bool kLambda>
[[gnu::always_inline]] inline void interleaved_body(const StretchConstraint<float>* items, const Index* begin,
                                                    Index chains, Index common, float* q,
                                                    const SolveCoefficients<float>* coeff, float* lambda, bool reverse) {
  if (chains == 8) interleaved_chains<kLambda, 8>(items, begin, common, q, coeff, lambda, reverse);
  else interleaved_chains<kLambda, 4>(items, begin, common, q, coeff, lambda, reverse);
}

void interleaved_default(const StretchConstraint<float>* items, const Index* begin, Index chains, Index common,
                         float* q, const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, bool reverse) {
  if (any_xpbd) interleaved_body<true>(items, begin, chains, common, q, coeff, lambda, reverse);
  else interleaved_body<false>(items, begin, chains, common, q, coeff, lambda, reverse);
}

void range_default(const StretchConstraint<float>* c, Index b, Index e, float* q,
                   const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, Index set) {
  range_either(c, b, e, q, coeff, lambda, any_xpbd, set);
}

// The same code compiled for AVX2 machines: the three-operand encoding saves the register copies SSE2 needs. The
// arithmetic is the same (no FMA), so both give the same bits. Chosen once by a run-time CPU check (not an ifunc:
// ifunc resolvers run before ThreadSanitizer's runtime is up).
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2")]] void range_avx2(const StretchConstraint<float>* c, Index b, Index e, float* q,
                                        const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, Index set) {
  range_either(c, b, e, q, coeff, lambda, any_xpbd, set);
}
[[gnu::target("avx2")]] void interleaved_avx2(const StretchConstraint<float>* items, const Index* begin, Index chains,
                                              Index common, float* q, const SolveCoefficients<float>* coeff,
                                              float* lambda, bool any_xpbd, bool reverse) {
  if (any_xpbd) interleaved_body<true>(items, begin, chains, common, q, coeff, lambda, reverse);
  else interleaved_body<false>(items, begin, chains, common, q, coeff, lambda, reverse);
}

bool use_avx2() { return avx2_enabled(); }  // the one CPU check (kernels_avx2.hpp)

// PBD_SIMD=sse2 in the environment keeps the SSE2 build on an AVX2 machine (tests run both builds this way).
RangeFn pick_range() { return use_avx2() ? range_avx2 : range_default; }
InterleavedFn pick_interleaved() { return use_avx2() ? interleaved_avx2 : interleaved_default; }
#else
RangeFn pick_range() { return range_default; }
InterleavedFn pick_interleaved() { return interleaved_default; }
#endif

}  // namespace

void project_stretch_range(const StretchConstraint<float>* c, Index b, Index e, float* q,
                           const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, Index set) {
  static const RangeFn range = pick_range();
  range(c, b, e, q, coeff, lambda, any_xpbd, set);
}

void project_stretch_interleaved(const StretchConstraint<float>* items, const Index* begin, Index chains, Index common,
                                 float* q, const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd,
                                 bool reverse) {
  assert(chains == 4 || chains == 8);
  static const InterleavedFn fn = pick_interleaved();
  fn(items, begin, chains, common, q, coeff, lambda, any_xpbd, reverse);
}

void project_stretch_interiors(const StretchConstraint<float>* items, const Index* offsets, Index first, Index last,
                               float* q, const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd,
                               bool reverse) {
  Index begin[kInterleavedChains], len[kInterleavedChains];
  auto one = [&](Index i) { project_stretch_padded(items[i], q, coeff[items[i].set], lambda[i]); };
  for (Index g = first; g < last;) {  // a group of 8 or 4 blocks (SIMD), or fewer (one by one)
    const Index left = last - g, m = left >= 8 ? 8 : left >= 4 ? 4 : left;
    Index common = ~Index(0), longest = 0;
    for (Index j = 0; j < m; ++j) {
      begin[j] = offsets[g + j];
      len[j] = offsets[g + j + 1] - begin[j];
      common = std::min(common, len[j]);
      longest = std::max(longest, len[j]);
    }
    if (m < 4) common = 0;
    if (reverse) {
      for (Index j = 0; j < m; ++j)
        for (Index k = len[j]; k-- > common;) one(begin[j] + k);
      if (common) project_stretch_interleaved(items, begin, m, common, q, coeff, lambda, any_xpbd, true);
    } else {
      if (common) project_stretch_interleaved(items, begin, m, common, q, coeff, lambda, any_xpbd, false);
      for (Index k = common; k < longest; ++k)
        for (Index j = 0; j < m; ++j)
          if (k < len[j]) one(begin[j] + k);
    }
    g += m;
  }
}

void pad_positions(const float* p, const float* w, Index b, Index e, float* q) {
  Index i = b;
#if defined(__SSE2__)
  for (; i + 4 <= e; i += 4) {  // four particles: 12 floats x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3, and 4 w
    const float* s = p + 3 * std::size_t(i);
    const __m128 a = _mm_loadu_ps(s), m = _mm_loadu_ps(s + 4), c = _mm_loadu_ps(s + 8);
    const __m128 ws = _mm_loadu_ps(w + i);
    float* t = q + 4 * std::size_t(i);
    const __m128 zw0 = _mm_shuffle_ps(a, ws, _MM_SHUFFLE(0, 0, 2, 2));  // z0 z0 w0 w0
    _mm_store_ps(t, _mm_shuffle_ps(a, zw0, _MM_SHUFFLE(2, 0, 1, 0)));  // x0 y0 z0 w0
    const __m128 xy1 = _mm_shuffle_ps(a, m, _MM_SHUFFLE(0, 0, 3, 3));  // x1 x1 y1 y1
    const __m128 zw1 = _mm_shuffle_ps(m, ws, _MM_SHUFFLE(1, 1, 1, 1));  // z1 z1 w1 w1
    _mm_store_ps(t + 4, _mm_shuffle_ps(xy1, zw1, _MM_SHUFFLE(2, 0, 2, 0)));  // x1 y1 z1 w1
    const __m128 zw2 = _mm_shuffle_ps(c, ws, _MM_SHUFFLE(2, 2, 0, 0));  // z2 z2 w2 w2
    _mm_store_ps(t + 8, _mm_shuffle_ps(m, zw2, _MM_SHUFFLE(2, 0, 3, 2)));  // x2 y2 z2 w2
    const __m128 zw3 = _mm_shuffle_ps(c, ws, _MM_SHUFFLE(3, 3, 3, 3));  // z3 z3 w3 w3
    _mm_store_ps(t + 12, _mm_shuffle_ps(c, zw3, _MM_SHUFFLE(2, 0, 2, 1)));  // x3 y3 z3 w3
  }
#endif
  for (; i < e; ++i) {
    for (int d = 0; d < 3; ++d) q[4 * std::size_t(i) + d] = p[3 * std::size_t(i) + d];
    q[4 * std::size_t(i) + 3] = w[i];
  }
}

void unpad_positions(const float* q, Index b, Index e, float* p) {
  Index i = b;
#if defined(__SSE2__)
  for (; i + 4 <= e; i += 4) {
    const float* s = q + 4 * std::size_t(i);
    const __m128 q0 = _mm_load_ps(s), q1 = _mm_load_ps(s + 4), q2 = _mm_load_ps(s + 8), q3 = _mm_load_ps(s + 12);
    float* t = p + 3 * std::size_t(i);
    const __m128 zx = _mm_shuffle_ps(q0, q1, _MM_SHUFFLE(0, 0, 2, 2));  // z0 z0 x1 x1
    _mm_storeu_ps(t, _mm_shuffle_ps(q0, zx, _MM_SHUFFLE(2, 0, 1, 0)));  // x0 y0 z0 x1
    const __m128 xy2 = _mm_shuffle_ps(q2, q2, _MM_SHUFFLE(1, 0, 1, 0));  // x2 y2 x2 y2
    _mm_storeu_ps(t + 4, _mm_shuffle_ps(q1, xy2, _MM_SHUFFLE(1, 0, 2, 1)));  // y1 z1 x2 y2
    const __m128 zx2 = _mm_shuffle_ps(q2, q3, _MM_SHUFFLE(0, 0, 2, 2));  // z2 z2 x3 x3
    _mm_storeu_ps(t + 8, _mm_shuffle_ps(zx2, q3, _MM_SHUFFLE(2, 1, 2, 0)));  // z2 x3 y3 z3
  }
#endif
  for (; i < e; ++i)
    for (int d = 0; d < 3; ++d) p[3 * std::size_t(i) + d] = q[4 * std::size_t(i) + d];
}

}  // namespace pbd::detail
