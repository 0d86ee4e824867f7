#pragma once
// The CPU check (private): whether the AVX2 builds (solve/kernels_avx2.*, contact/near_avx2.*) may run. Every SIMD
// path asks this one function, so one environment variable (PBD_SIMD=sse2) switches the whole engine to its SSE2
// forms, which give the same bits.

namespace pbd::detail {

/// True when the CPU has AVX2 and the environment does not ask for SSE2 alone (PBD_SIMD=sse2); checked once.
bool avx2_enabled();

}  // namespace pbd::detail
