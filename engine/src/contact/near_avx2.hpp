#pragma once
// The AVX2 build of the particle contacts' walk over a dense grid and of its pair test (private;
// walk.cpp, pair_test.hpp): eight candidates at a time, the same operations in the same order as the scalar and SSE2
// forms, so the same pairs. Compiled with -mavx2 and without FMA in a file of its own (near_avx2.cpp); call these
// only when avx2_enabled() (simd/cpu.hpp).
#include "pbd/types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace pbd::detail {

/// A joined row's first groups of four compared with every candidate; the rest only when a near candidate is left
/// unmatched (pair_test.hpp, joined_bits).
constexpr std::ptrdiff_t kJoinedFirstGroups = 2;

/// Bit k set when particle others[k] (k < count ≤ 64) comes within reach of particle a: movers holds eight floats per
/// particle, 16-byte aligned (x y z radius, then p x y z and the pinned flag); others[count, count + 8) must be valid
/// particles (they are tested and masked off). The test is pair_test.hpp's near_pair.
std::uint64_t near_bits_avx2(const float* movers, Index a, const Index* others, std::uint32_t count, float margin);

/// A dense grid's entries as the walk reads them (particle_contacts.hpp, phases 3 and 4).
struct DenseWalk {
  const std::int32_t* cx = nullptr;        ///< per entry, then 8 more (the largest int): its cell along x
  const Index* pid = nullptr;              ///< per entry, then 8 more: its particle
  const Index* start = nullptr;            ///< per bucket + 1: its first entry; a bucket is one row (y, z)
  std::array<Index, 4> row_step{};         ///< bucket of the rows (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1)
                                           ///< minus the row's own
  const float* movers = nullptr;           ///< as near_bits_avx2's
  float margin = 0;                        ///< m
  const Index* joined = nullptr;           ///< rows of joined particles (ParticleGrid::joined), nullptr: none
  const Index* joined_offsets = nullptr;   ///< where each particle's row starts
};

/// Receives `count` near pairs, pairs[2k] (the walked entry's particle) and pairs[2k + 1] (the other).
using NearSink = void (*)(void* context, const Index* pairs, std::size_t count);

/// Pairs each entry of buckets [first, last) with the entries after it in its own cell and the next along x, and with
/// those of its neighbouring rows in cells x − 1 to x + 1, as the generic walk does, and hands `sink` each pair that
/// comes within reach and is not joined by a constraint.
void walk_dense_avx2(const DenseWalk& w, Index first, Index last, NearSink sink, void* context);

}  // namespace pbd::detail
