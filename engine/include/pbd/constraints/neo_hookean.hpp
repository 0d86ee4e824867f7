#pragma once
/// \file neo_hookean.hpp
/// A Neo-Hookean tet in XPBD (Macklin & Müller 2021, "A Constraint-based Formulation of Stable Neo-Hookean
/// Materials"): per tet, the energy V0·Ψ with Ψ = μ/2·(tr FᵀF − 3) + λ/2·(det F − γ)², γ = 1 + μ/λ, written as two
/// constraints on the deformation gradient F = Ds·Dm⁻¹ (Ds, Dm: the edge matrices [p1 − p0, p2 − p0, p3 − p0] now and
/// at rest):
///   deviatoric   C_D = |F| (Frobenius),  compliance α_D = 1 / (μ V0)
///   hydrostatic  C_H = det F − γ,        compliance α_H = 1 / (λ V0)
/// Why two constraints and one coupled solve: at rest the deviatoric part pulls the tet towards F = 0 and the
/// hydrostatic part pushes it back out (γ > 1 is what balances them there), with parallel gradients. Projected one
/// after the other, each undoes the other and Gauss-Seidel crawls; solved together as a 2 × 2 system per tet, the
/// rest state is a fixed point and the step converges like a single constraint. So the type carries two multipliers
/// (kMultipliers) and its own correction. det F changes sign with the tet, so an inverted tet is pushed back out
/// (stable under inversion), and the energy has no log or 1/J term to blow up at J ≤ 0.
///
/// The set's compliance is 1/μ (Pa⁻¹); the tet scales it by 1/V0 and keeps ratio = μ/λ for the hydrostatic part.
/// Linearized at rest this Ψ is linear elasticity with Lamé constants μ and λ − μ, so young_poisson below gives
/// λ = λ_Lamé + μ: a small-strain bar then bends and stretches as Young's modulus E and Poisson's ratio ν say.
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/detail/neo_hookean_math.hpp"
#include "pbd/error.hpp"
#include "pbd/stiffness.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <string>

namespace pbd {

/// Lamé parameters of the Neo-Hookean energy above.
struct NeoHookeanMaterial {
  double mu = 0.0;      ///< shear modulus μ, Pa
  double lambda = 0.0;  ///< the hydrostatic modulus λ of Ψ (λ_Lamé + μ), Pa
  /// The set's compliance 1/μ, Pa⁻¹.
  double compliance() const { return 1.0 / mu; }
  /// μ/λ, each tet's `ratio`.
  double ratio() const { return mu / lambda; }
};

/// The material of Young's modulus E > 0 (Pa) and Poisson's ratio ν in (−1, 0.5): μ = E / (2(1 + ν)),
/// λ = λ_Lamé + μ = E / (2(1 + ν)(1 − 2ν)). Throws pbd::Error naming the bad value.
inline NeoHookeanMaterial young_poisson(double young, double poisson) {
  if (!std::isfinite(young) || !(young > 0.0))
    throw Error(detail::message("young: Young's modulus must be finite and > 0 Pa, got ", young));
  if (!(poisson > -1.0 && poisson < 0.5))
    throw Error(detail::message("poisson: Poisson's ratio must be in (-1, 0.5), got ", poisson));
  const double mu = young / (2.0 * (1.0 + poisson));
  return {mu, young / (2.0 * (1.0 + poisson) * (1.0 - 2.0 * poisson))};
}

/// Keeps a tet's deformation gradient where the Neo-Hookean energy of its set's μ and its own μ/λ is balanced.
template <class Real> struct NeoHookeanConstraint {
  static constexpr const char* kName = "neo_hookean";  ///< name in reports and on the command line
  static constexpr int kArity = 4;                     ///< particles per constraint
  static constexpr bool kInequality = false;           ///< an equality
  static constexpr int kMultipliers = 2;               ///< λ_D, λ_H: the coupled solve above
  static constexpr bool kBreaksWithFibers = true;      ///< torn when a fiber along an edge breaks (traits.hpp)
  static constexpr bool kColoredInteriors = true;      ///< block solver: interiors color by color (traits.hpp)
  static constexpr const char* kNoun = "Neo-Hookean tet";                            ///< the item in messages
  static constexpr std::array<const char*, 4> kParticleNames{"p0", "p1", "p2", "p3"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "neo_hookean";   ///< a tet body's key: {"young": E, "poisson": ν}
  static constexpr SceneForm kSceneForm = SceneForm::mesh;  ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;               ///< between four particles
  /// Its violation is the Green strain |½(FᵀF − I)| (Frobenius), in percent: how far the tet is from its rest shape.
  static constexpr Measure kMeasure{"strain_pct", "strain", "%", 100.0};
  std::array<Index, 4> particles;  ///< the corners p0..p3, positively oriented at rest
  Index set;                       ///< constraint set: its compliance is 1/μ
  Real volume;                     ///< rest volume V0 > 0, m³
  Vec3<Real> inv_rest0;            ///< column 0 of Dm⁻¹, 1/m
  Vec3<Real> inv_rest1;            ///< column 1 of Dm⁻¹, 1/m
  Vec3<Real> inv_rest2;            ///< column 2 of Dm⁻¹, 1/m
  Real ratio;                      ///< μ/λ ≥ 0 (γ = 1 + ratio; 0: incompressible)
  /// The rest values: V0 and Dm⁻¹ (default: measured from the current positions) and μ/λ (always given).
  static constexpr auto fields() {
    return std::tuple{Field{"volume", "rest volume", &NeoHookeanConstraint::volume},
                      Field{"inv_rest0", "inverse rest shape column 0", &NeoHookeanConstraint::inv_rest0},
                      Field{"inv_rest1", "inverse rest shape column 1", &NeoHookeanConstraint::inv_rest1},
                      Field{"inv_rest2", "inverse rest shape column 2", &NeoHookeanConstraint::inv_rest2},
                      Field{"ratio", "ratio mu/lambda", &NeoHookeanConstraint::ratio, true, true}};
  }
};

namespace detail {
/// F = Ds·Dm⁻¹ of tet c at corners p.
template <class Real> Eigen::Matrix<Real, 3, 3> deformation_gradient(const NeoHookeanConstraint<Real>& c,
                                                                    const Vec3<Real> (&p)[4]) {
  Eigen::Matrix<Real, 3, 3> ds, inv;
  ds << p[1] - p[0], p[2] - p[0], p[3] - p[0];
  inv << c.inv_rest0, c.inv_rest1, c.inv_rest2;
  return ds * inv;
}
}  // namespace detail

/// The coupled XPBD step of the two constraints (file comment): with g_D, g_H the position gradients
/// (∂C/∂F·Dm⁻ᵀ for p1..p3, minus their sum for p0; ∂C_D/∂F = F/|F|, ∂C_H/∂F = cof F), α̃ = α/h² of the set over V0,
/// solves [g_D·W·g_D + α̃_D, g_D·W·g_H; g_H·W·g_D, g_H·W·g_H + α̃_H]·Δλ = −[C_D + α̃_D λ_D, C_H + α̃_H λ_H] and moves
/// p_i by w_i(g_Di Δλ_D + g_Hi Δλ_H). False (nothing moves) when the set has no compliance (α̃ = 0: the two
/// constraints cannot both hold), F = 0 (no direction), or the system is singular (all corners pinned).
/// The arithmetic is detail/neo_hookean_math.hpp's, which the AVX2 kernel shares (so it gives these bits).
template <class Real>
inline bool correction(const NeoHookeanConstraint<Real>& c, const Vec3<Real> (&p)[4], const Real (&w)[4],
                       SolveCoefficients<Real> coeff, const Real* lambda, Vec3<Real> (&dp)[4], Real (&dlambda)[2]) {
  if (!(coeff.alpha_tilde > Real(0))) return false;  // the step's own guard too: skips its arithmetic
  using V = detail::lane::V3<Real>;
  const V q[4] = {{p[0].x(), p[0].y(), p[0].z()}, {p[1].x(), p[1].y(), p[1].z()},
                  {p[2].x(), p[2].y(), p[2].z()}, {p[3].x(), p[3].y(), p[3].z()}};
  const detail::neo_hookean::TetRest<Real> rest{{{c.inv_rest0.x(), c.inv_rest0.y(), c.inv_rest0.z()},
                                                 {c.inv_rest1.x(), c.inv_rest1.y(), c.inv_rest1.z()},
                                                 {c.inv_rest2.x(), c.inv_rest2.y(), c.inv_rest2.z()}},
                                                c.volume,
                                                c.ratio};
  const auto r = detail::neo_hookean::neo_hookean_step<Real>(q, w, rest, coeff.alpha_tilde, lambda[0], lambda[1]);
  if (!r.ok) return false;
  dlambda[0] = r.dlambda[0];
  dlambda[1] = r.dlambda[1];
  for (int i = 0; i < 4; ++i) dp[i] = Vec3<Real>(r.dp[i].x, r.dp[i].y, r.dp[i].z);
  return true;
}

/// Green strain |½(FᵀF − I)|.
template <class Real> double violation(const NeoHookeanConstraint<Real>& c, const PositionsView<Real>& x) {
  const auto d = convert_constraint<double>(c);
  const Vec3<double> p[4] = {detail::position_of<Real>(x, c.particles[0]), detail::position_of<Real>(x, c.particles[1]),
                             detail::position_of<Real>(x, c.particles[2]), detail::position_of<Real>(x, c.particles[3])};
  const Eigen::Matrix3d F = detail::deformation_gradient(d, p);
  return 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity()).norm();
}

/// Defaults: V0 and Dm⁻¹ of the tet in x; μ/λ has no default.
template <class Real, class X> const char* measure_rest(NeoHookeanConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & (1u << 4))) return "ratio mu/lambda must be given (young_poisson gives it from E and nu)";
  const auto& q = c.particles;
  Eigen::Matrix<Real, 3, 3> dm;
  dm << Vec3<Real>(x.col(q[1]) - x.col(q[0])), Vec3<Real>(x.col(q[2]) - x.col(q[0])),
      Vec3<Real>(x.col(q[3]) - x.col(q[0]));
  const Real det = dm.determinant();
  if (!(det > Real(0))) return "the tet is inverted or flat where it starts (its signed volume is not > 0)";
  const Eigen::Matrix<Real, 3, 3> inv = dm.inverse();
  if (!(given & 1u)) c.volume = det / Real(6);
  if (!(given & 2u)) c.inv_rest0 = inv.col(0);
  if (!(given & 4u)) c.inv_rest1 = inv.col(1);
  if (!(given & 8u)) c.inv_rest2 = inv.col(2);
  return nullptr;
}

/// V0 finite and > 0, Dm⁻¹ finite, μ/λ finite and ≥ 0.
template <class Real> std::string rest_error(const NeoHookeanConstraint<Real>& c) {
  if (!std::isfinite(c.volume) || !(c.volume > Real(0)))
    return detail::message("rest volume must be finite and > 0 (the tet is inverted or flat), got ", c.volume);
  if (!c.inv_rest0.allFinite() || !c.inv_rest1.allFinite() || !c.inv_rest2.allFinite())
    return "inverse rest shape is not finite";
  if (!std::isfinite(c.ratio) || c.ratio < Real(0)) return detail::message("ratio mu/lambda must be finite and >= 0, got ", c.ratio);
  return {};
}

}  // namespace pbd
