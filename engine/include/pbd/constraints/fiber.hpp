#pragma once
/// \file fiber.hpp
/// Fiber constraint: a stretch constraint that follows its set's stress–strain curve (material.hpp), with a
/// plastic strain that grows past yield and a rupture strain at which it breaks. In a set without a curve it is a
/// stretch constraint (C = |p0 − p1| − L0·(1 + ε_p)) with the set's stiffness or compliance.
///
/// What a step does with fibers (engine/src/solve/solver.hpp): each projection is the force-law one of
/// material.hpp; after each sub-step's sweeps the plastic strains flow (engine/src/fibers.hpp); after the step the
/// fibers strained to their rupture strain break and leave the model (World::last_breaks), with the tets holding
/// both their ends (traits.hpp: breaks_with_fibers), and surfaces tear along them. The plastic strain is a
/// rest value, so a world described with its fibers (pbd::io) is rebuilt with the rest lengths they have grown to.
#include "pbd/constraints/traits.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"

#include <array>
#include <cmath>

namespace pbd {

/// Keeps two particles at rest distance `rest`·(1 + `plastic`), by its set's curve when it has one.
template <class Real> struct FiberConstraint {
  static constexpr const char* kName = "fiber";  ///< name in reports and on the command line
  static constexpr int kArity = 2;               ///< particles per constraint
  static constexpr bool kInequality = false;     ///< an equality (a slack fiber's force law gives no force)
  static constexpr bool kUnitGradients = true;   ///< |∇_i C| = 1
  static constexpr bool kTakesMaterial = true;   ///< may be in a set with a stress–strain curve
  static constexpr const char* kNoun = "fiber";                          ///< the item in error messages
  static constexpr std::array<const char*, 2> kParticleNames{"a", "b"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "fibers";  ///< {"particles": [[a, b], ...], "rest", "plastic", stiffness}
  static constexpr SceneForm kSceneForm = SceneForm::listed;  ///< one fiber per listed pair
  static constexpr bool kTiesToWorld = false;                 ///< between two particles
  static constexpr const char* kForceUnit = "N";              ///< its reading is a tension (material_scale: 1)
  /// Its elastic strain |l − L|/L (L the plastic rest length), in percent.
  static constexpr Measure kMeasure{"fiber_pct", "fiber strain", "%", 100.0};
  std::array<Index, 2> particles;  ///< the two particles
  Index set;                       ///< constraint set (stiffness or curve) it belongs to
  Real rest;                       ///< rest length L0 > 0, m: strains are measured from it
  Real plastic;                    ///< plastic strain ε_p ≥ 0: the rest length has grown to L0·(1 + ε_p)
  /// The rest values: the rest length (default: the particles' current distance) and the plastic strain (default 0).
  static constexpr auto fields() {
    return std::tuple{Field{"rest", "rest length", &FiberConstraint::rest, true},
                      Field{"plastic", "plastic strain", &FiberConstraint::plastic, true}};
  }
  /// The rest length it has grown to, m.
  Real plastic_rest() const { return rest * (Real(1) + plastic); }
};

/// C = |p0 − p1| − L0·(1 + ε_p), ∇0 C = n = (p0 − p1)/|p0 − p1|, ∇1 C = −n. Coincident particles: returns false.
template <class Real>
inline bool evaluate(const FiberConstraint<Real>& c, const Vec3<Real> (&p)[2], Real& C, Vec3<Real> (&grad)[2]) {
  const Vec3<Real> d = p[0] - p[1];
  const Real len2 = d.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real len = std::sqrt(len2);
  C = len - c.plastic_rest();
  grad[0] = d * (Real(1) / len);
  grad[1] = -grad[0];
  return true;
}

/// The fiber's own equation in a set with a curve (material.hpp): the Δλ with r(λ0 + Δλ) = 0, where
/// r(λ) = h²·F(e(λ)) + λ and e(λ) = (l + Σw·(λ − λ0))/L0 − 1 − ε_p is the elastic strain once the two particles
/// have moved by Δλ along the fiber. By Newton's method from λ0, up to kFiberNewtonSteps steps: r is increasing and
/// convex, so after the first step the iterates come down to the root from above, and a step that starts and ends
/// on the linear part is exact (then it stops).
inline double fiber_newton(const Material& m, double rest, double plastic, double len, double wsum, double h2,
                           double lambda0) {
  constexpr int kFiberNewtonSteps = 8;
  auto strain = [&](double lambda) { return (len + wsum * (lambda - lambda0)) / rest - 1.0 - plastic; };
  double lambda = lambda0;
  double e = strain(lambda);
  for (int i = 0; i < kFiberNewtonSteps; ++i) {
    const double step = (h2 * m.force(e) + lambda) / (1.0 + h2 * wsum * m.slope(e) / rest);
    lambda -= step;
    const double before = e;
    e = strain(lambda);
    const bool linear = before >= m.toe_strain && e >= m.toe_strain && before > 0.0;
    if (linear || !(std::abs(step) > 1e-12 * std::abs(lambda))) break;
  }
  return lambda - lambda0;
}

/// The correction: in a set with a curve, the solution of the fiber's own equation (fiber_newton; its first
/// Newton step is the force-law projection of material.hpp); otherwise the stretch projection with k and α̃.
template <class Real>
inline bool correction(const FiberConstraint<Real>& c, const Vec3<Real> (&p)[2], const Real (&w)[2],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[2], Real& dlambda) {
  const Vec3<Real> d = p[0] - p[1];
  const Real len2 = d.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real wsum = w[0] + w[1];
  const Real len = std::sqrt(len2);
  if (coeff.material) {
    if (!(wsum > Real(0))) return false;
    dlambda = Real(fiber_newton(*coeff.material, double(c.rest), double(c.plastic), double(len), double(wsum),
                                double(coeff.h2), double(lambda)));
  } else {
    const Real denom = coeff.alpha_tilde + wsum;
    if (!(denom > Real(0))) return false;
    dlambda = (-coeff.k * (len - c.plastic_rest()) - coeff.alpha_tilde * lambda) / denom;
  }
  const Vec3<Real> n = d * (Real(1) / len);
  dp[0] = (w[0] * dlambda) * n;
  dp[1] = (-w[1] * dlambda) * n;
  return true;
}

/// Total strain |p0 − p1| / L0 − 1 at positions x (3 per particle), in double.
template <class Real> double material_strain(const FiberConstraint<Real>& c, const Real* x) {
  const Real* a = x + 3 * std::size_t(c.particles[0]);
  const Real* b = x + 3 * std::size_t(c.particles[1]);
  const double dx = double(a[0]) - double(b[0]), dy = double(a[1]) - double(b[1]), dz = double(a[2]) - double(b[2]);
  return std::sqrt(dx * dx + dy * dy + dz * dz) / double(c.rest) - 1.0;
}

/// What its λ is scaled by: 1, so −λ/h² is its tension in N.
template <class Real> double material_scale(const FiberConstraint<Real>&) { return 1.0; }

/// Elastic strain |l − L|/L, L = L0·(1 + ε_p).
template <class Real> double violation(const FiberConstraint<Real>& c, const PositionsView<Real>& x) {
  return detail::relative_error((detail::position_of<Real>(x, c.particles[0]) -
                                 detail::position_of<Real>(x, c.particles[1])).norm(),
                                double(c.plastic_rest()));
}

/// Defaults: the rest length is the particles' distance in positions x, the plastic strain 0.
template <class Real, class X> const char* measure_rest(FiberConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 2u)) c.plastic = Real(0);
  if (given & 1u) return nullptr;
  c.rest = (x.col(c.particles[0]) - x.col(c.particles[1])).norm();
  if (!(c.rest > Real(0))) return "the particles coincide, so the rest length (strains are measured from it) is 0";
  return nullptr;
}

/// A rest length is finite and > 0, a plastic strain finite and ≥ 0.
template <class Real> std::string rest_error(const FiberConstraint<Real>& c) {
  if (!std::isfinite(c.rest) || !(c.rest > Real(0)))
    return detail::message("rest length must be finite and > 0, got ", c.rest);
  if (!std::isfinite(c.plastic) || c.plastic < Real(0))
    return detail::message("plastic strain must be finite and >= 0, got ", c.plastic);
  return {};
}

}  // namespace pbd
