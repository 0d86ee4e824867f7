#pragma once
/// \file stiffness.hpp
/// How strongly a constraint set acts: PBD stiffness k, its iteration-independent form, XPBD compliance, or a
/// fiber's stress–strain curve (material.hpp).
#include "pbd/material.hpp"
#include "pbd/types.hpp"

#include <cmath>

namespace pbd {

/// The formulation of one constraint set.
enum class StiffnessMode : std::uint8_t {
  pbd,                        ///< each projection is scaled by k (Müller et al. 2006)
  pbd_iteration_independent,  ///< scaled by k' = 1 − (1 − k)^(1/iterations): k is what a whole step achieves
  xpbd,                       ///< compliance α ≥ 0, λ accumulated per constraint within a (sub)step (Macklin et al. 2016)
  material,                   ///< XPBD with a force law (material.hpp): only fiber constraints take it
};

/// Stiffness of one constraint set; every constraint of the set shares it.
struct Stiffness {
  StiffnessMode mode = StiffnessMode::pbd;  ///< formulation
  double k = 1.0;                           ///< PBD stiffness in [0, 1] (pbd modes only)
  double compliance = 0.0;                  ///< XPBD compliance α ≥ 0, inverse stiffness in SI units (xpbd only)
  Material material{};                      ///< the fibers' stress–strain curve (material only)

  static Stiffness pbd_k(double k) { return {StiffnessMode::pbd, k, 0.0}; }                      ///< PBD with k
  static Stiffness iteration_independent(double k) { return {StiffnessMode::pbd_iteration_independent, k, 0.0}; }  ///< k'
  static Stiffness xpbd_compliance(double a) { return {StiffnessMode::xpbd, 1.0, a}; }          ///< XPBD with α
  static Stiffness fiber(const Material& m) { return {StiffnessMode::material, 1.0, 0.0, m}; }    ///< a material
  /// Its stress–strain curve, or nullptr when it has none (not a material set).
  const Material* curve() const { return mode == StiffnessMode::material ? &material : nullptr; }
};

/// Per-(sub)step coefficients of one constraint set as the projection uses them:
/// Δλ = (−k·C − α̃·λ) / (Σ w|∇C|² + α̃), Δp_i = w_i ∇_i C Δλ. PBD: α̃ = 0; XPBD: k = 1, α̃ = α / h².
/// A material set's: the fiber projection (constraints/fiber.hpp) reads the curve and h² instead, and α̃ is 1/(h²·k)
/// (its linear part's), which only says that λ is accumulated.
template <class Real> struct SolveCoefficients {
  Real k = 1;                         ///< scale of the correction
  Real alpha_tilde = 0;               ///< time-scaled compliance α / h²
  const Material* material = nullptr; ///< a material set's curve (its Stiffness's), else none
  Real h2 = 0;                        ///< a material set's h², s²
};

/// The coefficients of `s` for a (sub)step of length h with `iterations` sweeps.
template <class Real> SolveCoefficients<Real> coefficients(const Stiffness& s, double h, int iterations) {
  switch (s.mode) {
    case StiffnessMode::pbd: return {Real(s.k), Real(0)};
    case StiffnessMode::pbd_iteration_independent: {
      const double n = iterations > 0 ? iterations : 1;
      return {Real(1.0 - std::pow(1.0 - s.k, 1.0 / n)), Real(0)};
    }
    // + 0 turns a compliance of −0 into α̃ = +0: with α̃ = +0 and λ = 0, "− α̃·λ" leaves every value as it is, so
    // kernels may leave it out (engine/src/solve/stretch_kernel.hpp) and still match the scalar projection bit for bit.
    case StiffnessMode::xpbd: return {Real(1), Real(s.compliance / (h * h)) + Real(0)};
    case StiffnessMode::material: return {Real(1), Real(1.0 / (h * h * s.material.stiffness)), &s.material, Real(h * h)};
  }
  return {};
}

}  // namespace pbd
