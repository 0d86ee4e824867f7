#pragma once
// Gauss-Seidel projection of one color's dihedral bending constraints on padded positions (x y z w per particle,
// stretch_kernel.hpp), four at a time with SSE (private). The lanes run detail/bending_math.hpp, the arithmetic
// the scalar projection runs, so positions and λ match project() bit for bit; ranges are cut at multiples of
// kBendingBlock from the color's start all the same, as for stretch.
// Requires: no two constraints of a range share a movable particle (true within a color; pinned corners may be
// shared, they are never written).
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/stiffness.hpp"
#include "kernels.hpp"

namespace pbd::detail {

/// Constraints per SIMD block (the widest: eight float lanes under AVX2): parallel ranges of the bending and
/// stretch colors are cut at multiples of this from each color's start.
inline constexpr Index kBendingBlock = 8;

/// Gauss-Seidel projection of bending constraints c[b, e) of one color on padded positions q: blocks of
/// kBendingBlock counted from b with SIMD, the remainder scalar. Same result, bit for bit, as project() one by one.
/// any_xpbd = false promises that every set of the range has α̃ = +0: λ is then neither read nor written.
/// On AVX2 machines eight at a time (kernels_avx2.hpp), else four (SSE2; PBD_SIMD=sse2 keeps these).
void project_bending_range(const BendingConstraint<float>* c, Index b, Index e, float* q,
                           const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);

/// Float bending: four lanes with SSE2, eight with AVX2, on padded positions, colors cut at multiples of kBendingBlock
/// (kernels.hpp). Built where the float stretch kernel is (SSE2 targets).
template <> struct Kernels<BendingConstraint<float>> {
#if defined(__SSE2__)
  static constexpr bool kBuilt = true;
#else
  static constexpr bool kBuilt = false;
#endif
  static constexpr bool kNeedsAvx2 = false;
  static constexpr Index kBlock = kBendingBlock;
  static constexpr auto range = &project_bending_range;
};

/// Particles [b, e) between positions p (3 per particle) with inverse masses w and padded positions q, in double
/// (float: stretch_kernel.hpp); double runs on padded positions only with the AVX2 kernels (kernels_avx2.hpp).
void pad_positions(const double* p, const double* w, Index b, Index e, double* q);
void unpad_positions(const double* q, Index b, Index e, double* p);

}  // namespace pbd::detail
