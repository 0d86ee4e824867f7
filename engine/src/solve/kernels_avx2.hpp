#pragma once
// The SIMD kernels' AVX2 builds (private): eight float lanes or four double lanes of the arithmetic the scalar
// projections run (bending_math.hpp, area_math.hpp, tet_volume_math.hpp, neo_hookean_math.hpp; stretch.hpp's correction), on padded positions
// (x y z w per particle), so they give project()'s bits. Compiled with -mavx2 and without FMA in a file of their own (kernels_avx2.cpp); call
// them only when avx2_enabled(). Ranges: constraints c[b, e) of one color, the remainder past the last full block
// projected one at a time.
#include "pbd/constraints/area.hpp"
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/neo_hookean.hpp"
#include "pbd/constraints/shape_match.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/constraints/tet_volume.hpp"
#include "pbd/detail/model.hpp"  // kMixedSets
#include "pbd/stiffness.hpp"
#include "bending_kernel.hpp"  // kBendingBlock
#include "kernels.hpp"
#include "simd/cpu.hpp"  // avx2_enabled

namespace pbd::detail {

/// Bending on padded positions q: eight constraints at a time in float, four in double.
void project_bending_range_avx2(const BendingConstraint<float>* c, Index b, Index e, float* q,
                                const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);
void project_bending_range_avx2(const BendingConstraint<double>* c, Index b, Index e, double* q,
                                const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd);
/// Triangle area on padded positions q: eight constraints at a time in float, four in double (area_math.hpp).
void project_area_range_avx2(const AreaConstraint<float>* c, Index b, Index e, float* q,
                             const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);
void project_area_range_avx2(const AreaConstraint<double>* c, Index b, Index e, double* q,
                             const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd);
/// Neo-Hookean tets on padded positions q: eight at a time in float, four in double (neo_hookean_math.hpp); λ holds
/// two values per tet (λ_D, λ_H at 2i, 2i + 1). A tet moves only where its set has α̃ > 0, so with any_xpbd = false
/// (every α̃ is +0) nothing moves and the range returns at once.
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<float>* c, Index b, Index e, float* q,
                                    const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);
void project_neo_hookean_range_avx2(const NeoHookeanConstraint<double>* c, Index b, Index e, double* q,
                                    const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd);
/// Stretch on padded positions q in double, four at a time (set: the set every constraint of the range belongs to,
/// or kMixedSets). Float keeps stretch_kernel.hpp's four lanes: eight, with their 128-bit gathers and scatters, take
/// more instructions than they save (docs/performance.md).
void project_stretch_range_avx2(const StretchConstraint<double>* c, Index b, Index e, double* q,
                                const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd, Index set);

/// Tet volume on padded positions q: eight constraints at a time in float, four in double (tet_volume_math.hpp).
void project_tet_volume_range_avx2(const TetVolumeConstraint<float>* c, Index b, Index e, float* q,
                                   const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);
void project_tet_volume_range_avx2(const TetVolumeConstraint<double>* c, Index b, Index e, double* q,
                                   const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd);

/// Shape matching on padded positions q: eight clusters at a time in float, four in double (shape_match_math.hpp).
void project_shape_match_range_avx2(const ShapeMatchConstraint<float>* c, Index b, Index e, float* q,
                                    const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd);
void project_shape_match_range_avx2(const ShapeMatchConstraint<double>* c, Index b, Index e, double* q,
                                    const SolveCoefficients<double>* coeff, double* lambda, bool any_xpbd);

/// One constraint on padded positions, scalar (the kernels' remainders; compiled for any x86-64).
void project_padded_one(const BendingConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda);
void project_padded_one(const BendingConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda);
void project_padded_one(const StretchConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda);
void project_padded_one(const AreaConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda);
void project_padded_one(const AreaConstraint<double>& c, double* q, SolveCoefficients<double> coeff, double& lambda);
void project_padded_one(const TetVolumeConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda);
void project_padded_one(const TetVolumeConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda);
void project_padded_one(const ShapeMatchConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda);
void project_padded_one(const ShapeMatchConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda);
/// A Neo-Hookean tet: lambda points at its two λ.
void project_padded_one(const NeoHookeanConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float* lambda);
void project_padded_one(const NeoHookeanConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double* lambda);

/// The AVX2 kernels (kernels.hpp): double bending and stretch, area, tet volume and Neo-Hookean in both precisions, on padded
/// positions, colors cut at multiples of kBendingBlock; only when avx2_enabled().
template <class Real> struct Avx2Kernel {
  static constexpr bool kBuilt = true;
  static constexpr bool kNeedsAvx2 = true;
  static constexpr Index kBlock = kBendingBlock;
};
template <> struct Kernels<BendingConstraint<double>> : Avx2Kernel<double> {
  static constexpr void (*range)(const BendingConstraint<double>*, Index, Index, double*,
                                 const SolveCoefficients<double>*, double*, bool) = &project_bending_range_avx2;
};
template <> struct Kernels<StretchConstraint<double>> : Avx2Kernel<double> {
  static constexpr auto range = &project_stretch_range_avx2;
};
template <> struct Kernels<AreaConstraint<float>> : Avx2Kernel<float> {
  static constexpr void (*range)(const AreaConstraint<float>*, Index, Index, float*, const SolveCoefficients<float>*,
                                 float*, bool) = &project_area_range_avx2;
};
template <> struct Kernels<AreaConstraint<double>> : Avx2Kernel<double> {
  static constexpr void (*range)(const AreaConstraint<double>*, Index, Index, double*,
                                 const SolveCoefficients<double>*, double*, bool) = &project_area_range_avx2;
};
template <> struct Kernels<TetVolumeConstraint<float>> : Avx2Kernel<float> {
  static constexpr void (*range)(const TetVolumeConstraint<float>*, Index, Index, float*,
                                 const SolveCoefficients<float>*, float*, bool) = &project_tet_volume_range_avx2;
};
template <> struct Kernels<TetVolumeConstraint<double>> : Avx2Kernel<double> {
  static constexpr void (*range)(const TetVolumeConstraint<double>*, Index, Index, double*,
                                 const SolveCoefficients<double>*, double*, bool) = &project_tet_volume_range_avx2;
};
template <> struct Kernels<ShapeMatchConstraint<float>> : Avx2Kernel<float> {
  static constexpr void (*range)(const ShapeMatchConstraint<float>*, Index, Index, float*,
                                 const SolveCoefficients<float>*, float*, bool) = &project_shape_match_range_avx2;
};
template <> struct Kernels<ShapeMatchConstraint<double>> : Avx2Kernel<double> {
  static constexpr void (*range)(const ShapeMatchConstraint<double>*, Index, Index, double*,
                                 const SolveCoefficients<double>*, double*, bool) = &project_shape_match_range_avx2;
};
template <> struct Kernels<NeoHookeanConstraint<float>> : Avx2Kernel<float> {
  static constexpr void (*range)(const NeoHookeanConstraint<float>*, Index, Index, float*,
                                 const SolveCoefficients<float>*, float*, bool) = &project_neo_hookean_range_avx2;
};
template <> struct Kernels<NeoHookeanConstraint<double>> : Avx2Kernel<double> {
  static constexpr void (*range)(const NeoHookeanConstraint<double>*, Index, Index, double*,
                                 const SolveCoefficients<double>*, double*, bool) = &project_neo_hookean_range_avx2;
};

}  // namespace pbd::detail
