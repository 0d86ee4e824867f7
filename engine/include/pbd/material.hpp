#pragma once
/// \file material.hpp
/// A fiber's stress–strain curve: a toe where the fibers straighten, a linear part, yielding with hardening, and
/// rupture (the seed document's tissue fibers). A property of a constraint set (Stiffness::material); the fiber
/// constraints of such a set (constraints/fiber.hpp) follow it.
///
/// Strains are engineering strains of the fiber's rest length L0: total ε = l/L0 − 1 for a fiber of length l,
/// plastic ε_p (the rest length has grown to L0·(1 + ε_p)), elastic e = ε − ε_p. The force, in N, is a function of
/// the elastic strain alone:
///   e ≤ 0            F = 0                          slack: a fiber carries no compression
///   0 < e < ε_toe    F = k·e² / (2·ε_toe)           the toe: the stiffness grows linearly from 0 to k
///   e ≥ ε_toe        F = k·(e − ε_toe / 2)          the linear part, k in N per unit strain (E·A for a fiber of
///                                                  Young's modulus E and cross-section A)
/// F and its slope are continuous. Yield: F may not exceed F_y + H·ε_p, with F_y = F(ε_y) and H ≥ 0 the hardening
/// in N per unit plastic strain; past it the rest length grows (plastic flow) until F is back on the limit. So a
/// fiber pulled from rest follows the elastic curve up to ε_y and then F_y + k·H/(k + H)·(ε − ε_y); unloaded, it
/// goes back along the elastic curve shifted by ε_p, and is slack from ε = ε_p down. It breaks when its total
/// strain reaches ε_r (rupture_strain).
///
/// Why a force law rather than a compliance: XPBD's implicit step asks for the multiplier λ with λ = −h²·F(C(x))
/// (h the sub-step; C = l − L0·(1 + ε_p)). Linearizing that in Newton's way gives the projection
///   Δλ = −(h²·F + λ) / (1 + h²·F′·Σ w_i |∇C_i|²),    F′ = dF/dl,
/// which for a linear F = C/α is XPBD's Δλ = (−C − α̃λ)/(Σw + α̃): the compliance becomes the strain-dependent
/// tangent one, 1/F′. Written this way a slack fiber (F = F′ = 0) has no division by zero, and the force a fiber
/// carries after a step is −λ/h² (World::fibers). One such step is not enough at the slack end: from a fiber gone
/// slack it returns all of λ at once (Δλ = −λ), which moves the particles apart by h²·F′·Σw times the strain the
/// tension held, and a stiff cloth of fibers swept many times blew up from it. So each projection takes Newton
/// steps on the fiber's own equation until it holds (fiber.hpp: fiber_newton); the equation is increasing and
/// convex in λ, so they converge, and on the linear part one step is exact, as above.
#include <cmath>
#include <limits>
#include <string>

namespace pbd {

/// A fiber's stress–strain curve (the file comment), in SI units.
struct Material {
  static constexpr double kNever = std::numeric_limits<double>::infinity();  ///< a strain never reached
  double stiffness = 0.0;         ///< k > 0, N per unit strain: the linear part's slope (E·A)
  double toe_strain = 0.0;        ///< ε_toe ≥ 0: where the toe ends (0: linear from the start)
  double yield_strain = kNever;   ///< ε_y ≥ ε_toe: the elastic strain at which it yields (kNever: never)
  double hardening = 0.0;         ///< H ≥ 0, N per unit plastic strain: how the yield force grows as it flows
  double rupture_strain = kNever; ///< ε_r > 0: the total strain at which it breaks (kNever: never)

  /// Force in N at elastic strain e.
  double force(double e) const {
    if (!(e > 0.0)) return 0.0;
    if (e < toe_strain) return stiffness * e * e / (2.0 * toe_strain);
    return stiffness * (e - 0.5 * toe_strain);
  }
  /// dF/de in N at elastic strain e.
  double slope(double e) const {
    if (!(e > 0.0)) return 0.0;
    return e < toe_strain ? stiffness * e / toe_strain : stiffness;
  }
  /// Elastic energy per unit rest length, in J/m (∫F de from 0 to e).
  double energy(double e) const {
    if (!(e > 0.0)) return 0.0;
    if (e < toe_strain) return stiffness * e * e * e / (6.0 * toe_strain);
    const double t = toe_strain;
    return stiffness * (t * t / 6.0 + 0.5 * (e * e - t * t) - 0.5 * t * (e - t));
  }
  /// The force at which a fiber of plastic strain ε_p yields: F(ε_y) + H·ε_p.
  double yield_force(double plastic) const { return force(yield_strain) + hardening * plastic; }
  /// The plastic strain after a fiber of plastic strain `plastic` is held at total strain `strain`: unchanged
  /// unless the force would exceed the yield force, else grown until it is on it (the yield lies on the linear
  /// part, ε_y ≥ ε_toe, so the return is exact).
  double plastic_after(double strain, double plastic) const {
    if (!(yield_strain < kNever)) return plastic;
    const double excess = force(strain - plastic) - yield_force(plastic);
    return excess > 0.0 ? plastic + excess / (stiffness + hardening) : plastic;
  }
  /// The force along the curve of a fiber pulled monotonically from rest to total strain ε (what a quasi-static
  /// tension test measures): the elastic curve up to ε_y, then F_y + k·H/(k + H)·(ε − ε_y).
  double loading_force(double strain) const {
    if (!(strain > yield_strain)) return force(strain);
    return force(yield_strain) + stiffness * hardening / (stiffness + hardening) * (strain - yield_strain);
  }
  /// Why the curve is invalid ("stiffness must be ..."), or "" when it is valid.
  std::string error() const;
};

}  // namespace pbd
