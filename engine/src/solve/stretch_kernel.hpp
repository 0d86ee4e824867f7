#pragma once
// Gauss-Seidel projection of one color's stretch constraints on padded positions, four at a time with SSE2
// (private). Padded positions hold x y z w per particle (w = inverse mass), 16-byte aligned, so a particle is one
// aligned load and one aligned store. Every lane does the operations of the scalar correction() in
// constraints/stretch.hpp in the same order with correctly rounded SSE arithmetic (no estimates), so positions and
// λ match project() bit for bit; the solver still cuts ranges at multiples of kStretchBlock from the color's start
// so that each constraint takes the same path whatever the thread count.
// Requires: no two constraints of a range share a movable particle (true within a color).
#include "pbd/constraints/stretch.hpp"
#include "pbd/detail/model.hpp"  // kMixedSets

#include "kernels.hpp"
#include "simd/wide.hpp"

namespace pbd::detail {


/// Constraints per SIMD block: parallel ranges of the stretch colors are cut at multiples of this.
inline constexpr Index kStretchBlock = 4;

/// True when the float stretch kernel runs on padded positions (an SSE2 target); otherwise every type, stretch
/// included, is projected by project() on the 3-per-particle positions.
#if defined(__SSE2__)
inline constexpr bool kPaddedStretch = true;
#else
inline constexpr bool kPaddedStretch = false;
#endif

/// Scalar projection of stretch constraint c on padded positions q (4 per particle, w in the fourth): the same
/// correction() as project() and the same writes.
inline void project_stretch_padded(const StretchConstraint<float>& c, float* q, SolveCoefficients<float> coeff,
                                   float& lambda) {
  float* qa = q + 4 * std::size_t(c.particles[0]);
  float* qb = q + 4 * std::size_t(c.particles[1]);
  const Vec3<float> pos[2] = {Vec3<float>(qa[0], qa[1], qa[2]), Vec3<float>(qb[0], qb[1], qb[2])};
  const float w[2] = {qa[3], qb[3]};
  Vec3<float> dp[2];
  float dlambda;
  if (!correction(c, pos, w, coeff, lambda, dp, dlambda)) return;
  if (coeff.alpha_tilde != 0.0f) lambda += dlambda;  // λ is kept only where it enters (projection.hpp)
  if (w[0] != 0.0f) Eigen::Map<Vec3<float>>(qa) += dp[0];
  if (w[1] != 0.0f) Eigen::Map<Vec3<float>>(qb) += dp[1];
}

#if defined(__SSE2__)
namespace sse {
using namespace wide;
// Particle at a += s_k · d (d has w-lane 0, so w is kept), as p += (w·s)·d in the scalar projection. Reloads the
// position (nothing else wrote it since) rather than keeping eight positions in registers.
template <int k> [[gnu::always_inline]] inline void move(float* a, FloatW s, FloatW d) {
  store(a, load(a) + broadcast<k>(s) * d);
}
}  // namespace sse

/// Four constraints c[0, 4) of one color on padded positions q, λ in lambda[0, 4): the scalar correction() of
/// constraints/stretch.hpp in four lanes, in the same order of operations, and only the writes the scalar
/// projection makes (movable particles of constraints that project; λ of lanes with α̃ ≠ 0). kLambda = false when
/// no set has α̃ ≠ 0: every λ is 0, so λ is neither read nor written. kOneSet: the four belong to one set, whose −k
/// and α̃ are given in every lane of neg_k1 and alpha1 (otherwise they are read from coeff per block and the last two
/// arguments are ignored).
/// The constraints are c[0..4) here; project_stretch_block4_of takes any four (c(j) is the j-th).
template <bool kLambda, bool kOneSet, class Get>
[[gnu::always_inline]] inline void project_stretch_block4_of(const Get& c, float* q,
                                                             const SolveCoefficients<float>* coeff, float* lambda,
                                                             wide::FloatW neg_k1, wide::FloatW alpha1) {
  using namespace sse;
  float* const qa[4] = {q + 4 * std::size_t(c(0).particles[0]), q + 4 * std::size_t(c(1).particles[0]),
                        q + 4 * std::size_t(c(2).particles[0]), q + 4 * std::size_t(c(3).particles[0])};
  float* const qb[4] = {q + 4 * std::size_t(c(0).particles[1]), q + 4 * std::size_t(c(1).particles[1]),
                        q + 4 * std::size_t(c(2).particles[1]), q + 4 * std::size_t(c(3).particles[1])};
  FloatW d[4], wa, wb;
  {
    const FloatW pa[4] = {load(qa[0]), load(qa[1]), load(qa[2]), load(qa[3])};
    const FloatW pb[4] = {load(qb[0]), load(qb[1]), load(qb[2]), load(qb[3])};
    wa = transpose_w(pa[0], pa[1], pa[2], pa[3]);  // inverse masses of the four particles a
    wb = transpose_w(pb[0], pb[1], pb[2], pb[3]);  // inverse masses of the four particles b
    for (int k = 0; k < 4; ++k) d[k] = xyz(pa[k] - pb[k]);  // d = p_a − p_b
  }
  const FloatW len2 = squared_norm(transpose_xyz(d[0], d[1], d[2], d[3]));
  FloatW neg_k = neg_k1, alpha = alpha1;
  if constexpr (!kOneSet) {
    const Index set = c(0).set;
    if (c(1).set == set && c(2).set == set && c(3).set == set) {
      neg_k = -splat(coeff[set].k);
      alpha = splat(coeff[set].alpha_tilde);
    } else {
      neg_k = -lanes(coeff[set].k, coeff[c(1).set].k, coeff[c(2).set].k, coeff[c(3).set].k);
      alpha = lanes(coeff[set].alpha_tilde, coeff[c(1).set].alpha_tilde, coeff[c(2).set].alpha_tilde,
                    coeff[c(3).set].alpha_tilde);
    }
  }
  const FloatW denom = alpha + wa + wb;
  // Lanes that project: a direction exists and the denominator is positive (false for NaN, as in the scalar test).
  const MaskW ok = (len2 > splat(tiny_squared<float>())) & (denom > zero());
  const int active = bits(ok);
  if (active == 0) return;
  const FloatW rest = lanes(c(0).rest, c(1).rest, c(2).rest, c(3).rest);
  const FloatW len = sqrt(len2);
  // Without λ (every α̃ is +0, every λ 0) the scalar's "− α̃·λ" subtracts +0, which changes no bit: left out.
  FloatW num = neg_k * (len - rest);
  FloatW lam = zero();
  if constexpr (kLambda) {
    lam = loadu(lambda);
    num = num - alpha * lam;
  }
  const FloatW s = num / (denom * len);
  if constexpr (kLambda) storeu(lambda, select(ok & (alpha != zero()), lam + s * len, lam));
  const FloatW sa = wa * s, sb = -wb * s;
  // A particle is written when its constraint projects and it is movable (w ≠ 0), as in project_into(). The usual
  // case, all eight, takes one test instead of eight.
  const MaskW pinned_a = wa == zero(), pinned_b = wb == zero();
  if ((active | bits(pinned_a | pinned_b) << 4) == 0xF) {
    move<0>(qa[0], sa, d[0]);
    move<0>(qb[0], sb, d[0]);
    move<1>(qa[1], sa, d[1]);
    move<1>(qb[1], sb, d[1]);
    move<2>(qa[2], sa, d[2]);
    move<2>(qb[2], sb, d[2]);
    move<3>(qa[3], sa, d[3]);
    move<3>(qb[3], sb, d[3]);
    return;
  }
  const int move_a = active & ~bits(pinned_a), move_b = active & ~bits(pinned_b);
  if (move_a & 1) move<0>(qa[0], sa, d[0]);
  if (move_b & 1) move<0>(qb[0], sb, d[0]);
  if (move_a & 2) move<1>(qa[1], sa, d[1]);
  if (move_b & 2) move<1>(qb[1], sb, d[1]);
  if (move_a & 4) move<2>(qa[2], sa, d[2]);
  if (move_b & 4) move<2>(qb[2], sb, d[2]);
  if (move_a & 8) move<3>(qa[3], sa, d[3]);
  if (move_b & 8) move<3>(qb[3], sb, d[3]);
}

template <bool kLambda, bool kOneSet>
[[gnu::always_inline]] inline void project_stretch_block4(const StretchConstraint<float>* c, float* q,
                                                          const SolveCoefficients<float>* coeff, float* lambda,
                                                          wide::FloatW neg_k1, wide::FloatW alpha1) {
  project_stretch_block4_of<kLambda, kOneSet>([c](int j) -> const StretchConstraint<float>& { return c[j]; }, q,
                                              coeff, lambda, neg_k1, alpha1);
}
#endif

/// Gauss-Seidel projection of stretch constraints c[b, e) of one color on padded positions q: blocks of
/// kStretchBlock counted from b with SIMD, the remainder scalar. Same result, bit for bit, as project() one by one.
/// any_xpbd = false promises that every set of the range has α̃ = +0 (coefficients() never gives −0): λ is then
/// never touched (nor fetched).
/// set: the set every constraint of the range belongs to (k and α̃ are then read once), or kMixedSets.
/// Compiled twice (stretch_kernel.cpp): for AVX2 machines (three-operand encoding) and for any x86-64; a CPU check
/// on first use picks one for the process, and both do the same arithmetic.
void project_stretch_range(const StretchConstraint<float>* c, Index b, Index e, float* q,
                           const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd, Index set);

/// Most blocks project_stretch_interleaved takes at once (two groups of the kernel's four lanes).
inline constexpr Index kInterleavedChains = 8;

/// The block schedule's interiors (sweep.hpp): the k-th stretch constraints of `chains` blocks (4 or 8),
/// items[begin[j] + k], k over [0, common) (backwards when reverse), four lanes at a time on padded positions q. The
/// blocks share no movable particle, so the lanes are independent and every block sees its own constraints in order: the
/// bits of project() one block after the other. λ at lambda[begin[j] + k] (touched only when any_xpbd).
void project_stretch_interleaved(const StretchConstraint<float>* items, const Index* begin, Index chains, Index common,
                                 float* q, const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd,
                                 bool reverse);

/// The block schedule's stretch interiors [first, last) (block b: items[offsets[b], offsets[b + 1])), stretch being
/// the only type, on padded positions q: in groups of eight or four blocks, the k-th constraints of four blocks at a
/// time (project_stretch_interleaved); each block's constraints beyond its group's shortest count, and blocks left
/// over from the groups, one by one, interleaved (backwards when reverse). The bits of the scalar interiors.
void project_stretch_interiors(const StretchConstraint<float>* items, const Index* offsets, Index first, Index last,
                               float* q, const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd,
                               bool reverse);

/// Float stretch: four lanes on padded positions (SSE2 targets), colors cut at multiples of kStretchBlock, and the
/// block schedule's interiors when stretch is the only type (kernels.hpp).
template <> struct Kernels<StretchConstraint<float>> {
  static constexpr bool kBuilt = kPaddedStretch;
  static constexpr bool kNeedsAvx2 = false;
  static constexpr Index kBlock = kStretchBlock;
  static constexpr auto range = &project_stretch_range;
  static constexpr auto interiors = &project_stretch_interiors;
  static constexpr Index kChains = kInterleavedChains;
};

/// Particles [b, e) from positions p (3 per particle) and inverse masses w into padded positions q (4 per particle).
void pad_positions(const float* p, const float* w, Index b, Index e, float* q);
/// Particles [b, e) from padded positions q back into p (3 per particle).
void unpad_positions(const float* q, Index b, Index e, float* p);

}  // namespace pbd::detail
