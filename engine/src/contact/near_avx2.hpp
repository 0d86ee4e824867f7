#pragma once
// The AVX2 build of the particle contacts' pair test (private; particle_contacts.cpp): eight pairs at a time, the
// same operations in the same order as its scalar and SSE2 forms, so the same pairs. Compiled with -mavx2 and without
// FMA in a file of its own (near_avx2.cpp); call it only when avx2_enabled() (solve/kernels_avx2.hpp).
#include "pbd/types.hpp"

#include <cstdint>

namespace pbd::detail {

/// Bit k set when particle others[k] (k < count ≤ 64) comes within reach of particle a: movers holds eight floats per
/// particle, 16-byte aligned (x y z radius, then p x y z and the pinned flag); others[count, count + 8) must be valid
/// particles (they are tested and masked off). The test is particle_contacts.cpp's near_pair.
std::uint64_t near_bits_avx2(const float* movers, Index a, const Index* others, std::uint32_t count, float margin);

}  // namespace pbd::detail
