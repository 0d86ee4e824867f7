#include "bending_kernel.hpp"

#include "kernels_avx2.hpp"
#include "simd/wide.hpp"

#include <cstdlib>
#include <cstring>

#if defined(__SSE2__)
namespace pbd::detail::lane {
/// A constant in every lane (bending_math.hpp's Lit): float(v), as the scalar float code converts it.
template <> struct Lit<wide::FloatW> {
  static wide::FloatW of(double v) { return wide::splat(float(v)); }
};
}  // namespace pbd::detail::lane
#endif

namespace pbd::detail {

namespace {

// One constraint on padded positions: project()'s correction and writes (lambda: its first λ, of multipliers<C>()).
template <class C, class Real>
[[gnu::always_inline]] inline void project_one(const C& c, Real* q, SolveCoefficients<Real> coeff, Real* lambda) {
  constexpr int n = C::kArity;
  Vec3<Real> pos[n];
  Real w[n];
  for (int i = 0; i < n; ++i) {
    const Real* at = q + 4 * std::size_t(c.particles[i]);
    pos[i] = Vec3<Real>(at[0], at[1], at[2]);
    w[i] = at[3];
  }
  Vec3<Real> dp[n];
  if constexpr (multipliers<C>() > 1) {  // its own coupled correction (projection.hpp)
    Real dlambda[multipliers<C>()];
    if (!correction(c, pos, w, coeff, static_cast<const Real*>(lambda), dp, dlambda)) return;
    if (coeff.alpha_tilde != Real(0))
      for (int k = 0; k < multipliers<C>(); ++k) lambda[k] += dlambda[k];
  } else {
    Real dlambda;
    if (!correction(c, pos, w, coeff, *lambda, dp, dlambda)) return;
    if (coeff.alpha_tilde != Real(0)) *lambda += dlambda;  // λ is kept only where it enters (projection.hpp)
  }
  for (int i = 0; i < n; ++i)
    if (w[i] != Real(0)) Eigen::Map<Vec3<Real>>(q + 4 * std::size_t(c.particles[i])) += dp[i];
}

#if defined(__SSE2__)
// Four constraints c[0, 4) in four lanes: gather each corner of the four (one aligned load per particle, then a
// transpose), the shared arithmetic, then only the writes the scalar projection makes (movable corners of lanes
// that project; λ of lanes with α̃ ≠ 0). kLambda = false: every α̃ is +0 and every λ 0, so λ is neither read nor
// written (the scalar "− α̃·λ" then subtracts +0, which changes no bit).
template <bool kLambda>
[[gnu::always_inline]] inline void block4(const BendingConstraint<float>* c, float* q,
                                          const SolveCoefficients<float>* coeff, float* lambda) {
  using namespace wide;
  float* at[4][4];  // [corner][lane]
  bend::V3<FloatW> p[4];
  FloatW w[4];
  for (int i = 0; i < 4; ++i) {
    FloatW v[4];
    for (int j = 0; j < 4; ++j) {
      at[i][j] = q + 4 * std::size_t(c[j].particles[i]);
      v[j] = load(at[i][j]);
    }
    const Vec3W t = transpose_xyz(v[0], v[1], v[2], v[3]);
    p[i] = {t.x, t.y, t.z};
    w[i] = transpose_w(v[0], v[1], v[2], v[3]);
  }
  FloatW k, alpha = zero();
  const Index set = c[0].set;
  if (c[1].set == set && c[2].set == set && c[3].set == set) {
    k = splat(coeff[set].k);
    if constexpr (kLambda) alpha = splat(coeff[set].alpha_tilde);
  } else {
    k = lanes(coeff[set].k, coeff[c[1].set].k, coeff[c[2].set].k, coeff[c[3].set].k);
    if constexpr (kLambda)
      alpha = lanes(coeff[set].alpha_tilde, coeff[c[1].set].alpha_tilde, coeff[c[2].set].alpha_tilde,
                    coeff[c[3].set].alpha_tilde);
  }
  const FloatW lam = kLambda ? loadu(lambda) : zero();
  const FloatW rest = lanes(c[0].rest, c[1].rest, c[2].rest, c[3].rest);
  const auto r = bend::bending_step<float>(p, w, rest, -k, alpha, lam);
  const int active = bits(r.ok);
  if (active == 0) return;
  if constexpr (kLambda) storeu(lambda, select(r.ok & (alpha != zero()), lam + r.dlambda, lam));
  for (int i = 0; i < 4; ++i) {
    FloatW d[4];
    transpose_points({r.dp[i].x, r.dp[i].y, r.dp[i].z}, d);
    const int moves = active & ~bits(w[i] == zero());
    if (moves == 0xF) {
      for (int j = 0; j < 4; ++j) store(at[i][j], load(at[i][j]) + d[j]);
    } else {
      for (int j = 0; j < 4; ++j)
        if (moves >> j & 1) store(at[i][j], load(at[i][j]) + d[j]);
    }
  }
}
#endif

template <bool kLambda>
[[gnu::always_inline]] inline void range_body(const BendingConstraint<float>* c, Index b, Index e, float* q,
                                              const SolveCoefficients<float>* coeff, float* lambda) {
#if defined(__SSE2__)
  for (; b + 4 <= e; b += 4) block4<kLambda>(c + b, q, coeff, lambda + b);
#endif
  for (; b < e; ++b) project_one(c[b], q, coeff[c[b].set], lambda + b);
}

void range_default(const BendingConstraint<float>* c, Index b, Index e, float* q,
                   const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (any_xpbd) range_body<true>(c, b, e, q, coeff, lambda);
  else range_body<false>(c, b, e, q, coeff, lambda);
}

}  // namespace

void project_padded_one(const BendingConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const BendingConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const StretchConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const AreaConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const AreaConstraint<double>& c, double* q, SolveCoefficients<double> coeff, double& lambda) {
  project_one(c, q, coeff, &lambda);
}

void project_padded_one(const TetVolumeConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const TetVolumeConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const ShapeMatchConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const ShapeMatchConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double& lambda) {
  project_one(c, q, coeff, &lambda);
}
void project_padded_one(const NeoHookeanConstraint<float>& c, float* q, SolveCoefficients<float> coeff, float* lambda) {
  project_one(c, q, coeff, lambda);
}
void project_padded_one(const NeoHookeanConstraint<double>& c, double* q, SolveCoefficients<double> coeff,
                        double* lambda) {
  project_one(c, q, coeff, lambda);
}

void project_bending_range(const BendingConstraint<float>* c, Index b, Index e, float* q,
                           const SolveCoefficients<float>* coeff, float* lambda, bool any_xpbd) {
  if (avx2_enabled()) project_bending_range_avx2(c, b, e, q, coeff, lambda, any_xpbd);
  else range_default(c, b, e, q, coeff, lambda, any_xpbd);
}

void pad_positions(const double* p, const double* w, Index b, Index e, double* q) {
  for (Index i = b; i < e; ++i) {
    for (int d = 0; d < 3; ++d) q[4 * std::size_t(i) + d] = p[3 * std::size_t(i) + d];
    q[4 * std::size_t(i) + 3] = w[i];
  }
}
void unpad_positions(const double* q, Index b, Index e, double* p) {
  for (Index i = b; i < e; ++i)
    for (int d = 0; d < 3; ++d) p[3 * std::size_t(i) + d] = q[4 * std::size_t(i) + d];
}

}  // namespace pbd::detail
