#pragma once
// Which SIMD kernel projects a constraint type on padded positions (private). The one template a type's kernel
// file specializes (stretch_kernel.hpp, bending_kernel.hpp, kernels_avx2.hpp), so that choosing a kernel needs no
// edit of the sweeps nor of the constraint's header; a type without a specialization is projected by the generic
// projection (project_into, through its TypeStore). The sweeps read the specializations through one table
// (kernel_table.hpp).
//
// A specialization Kernels<C> declares (constants and pointers to out-of-line functions only: kernels_avx2.hpp is
// also included by the file built for AVX2, which must instantiate no inline function the rest of the engine uses):
//   kBuilt      this build has the kernel (e.g. SSE2 targets only)
//   kNeedsAvx2  it runs only when avx2_enabled() (a CPU check)
//   kBlock      ranges of a color are cut at multiples of this many constraints from the color's start
//   range       f(items, b, e, q, coeff, lambda, any_xpbd[, set]): constraints [b, e) of one color on padded
//               positions q; with the trailing `set` (the set all the color's constraints share, or kMixedSets:
//               Model::color_sets is then kept for the type)
//   optional, for the block schedule's interiors when the type is the only one with constraints:
//   interiors   f(items, offsets, first, last, q, coeff, lambda, any_xpbd, reverse): block interiors [first, last)
//   kChains     most blocks a task of interiors takes
// Every kernel gives the bits of the scalar projection (each lane does its operations, correctly rounded, no FMA).
#include "pbd/types.hpp"

namespace pbd::detail {

/// The SIMD kernels of constraint type C: none unless a kernel file specializes it (the file comment).
template <class C> struct Kernels {
  static constexpr bool kBuilt = false;  ///< no kernel: the generic projection
};

}  // namespace pbd::detail
