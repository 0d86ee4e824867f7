#pragma once
/// \file tet_fiber.hpp
/// A tet's fibers: the stretch of a tet along a fiber direction a0 (given in the rest shape), following its set's
/// stress–strain curve (material.hpp) as a stress in Pa, with a plastic strain that grows past yield and a rupture
/// strain at which it breaks. The fiber term of a fiber-reinforced soft tissue (a transversely isotropic material:
/// an isotropic matrix, the tet's other constraints, plus fibers along a0); alone, a bar of them is a bundle of
/// fibers whose stiffness is Young's modulus E.
///
/// With F = Ds·Dm⁻¹ (Ds, Dm: the edge matrices [p1 − p0, p2 − p0, p3 − p0] now and at rest) the fiber's stretch is
/// |F·a0| = |Σ_i b_i (p_i − p0)| with b = Dm⁻¹·a0 (|a0| = 1), and its total strain ε = |F·a0| − 1. Its constraint is
///   C = |F·a0| − (1 + ε_p),    ∇_i C = b_i n (i = 1..3),  ∇_0 C = −(b1 + b2 + b3) n,  n = F·a0 / |F·a0|,
/// a plastic strain ε_p meaning that the rest shape has grown by 1 + ε_p along a0 (and only along it). The energy
/// is V0·Ψ(e), e = C the elastic strain and Ψ′ = σ the curve's stress, so the force conjugate to C is V0·σ(e): the
/// fiber's own equation is fiber.hpp's with the rest length 1, Σ w|∇C|² in place of w0 + w1 and h² scaled by V0
/// (material_scale). So the set's curve is in Pa: its stiffness is E, its hardening Pa per unit plastic strain, and
/// the reading −λ/(h²·V0) is the fiber's stress σ (World::material_readings). Moved along the gradients every corner
/// moves along n, so F·a0 keeps its direction and the strain after a correction is the linear one Newton's method
/// solves for (fiber.hpp: fiber_newton).
///
/// In a set without a curve it is a stretch of the tet along a0 with the set's stiffness or compliance; as the
/// Neo-Hookean tet's, the compliance is per unit volume (Pa⁻¹, 1/E), each tet scaling it by 1/V0. It breaks
/// (rupture) as a fiber does, and takes the tet's other constraints with it (traits.hpp: breaks_with_fibers).
#include "pbd/constraints/fiber.hpp"
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/stiffness.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <string>

namespace pbd {

/// Keeps a tet's stretch along its fiber direction at 1 + ε_p, by its set's curve when it has one.
template <class Real> struct TetFiberConstraint {
  static constexpr const char* kName = "tet_fiber";  ///< name in reports and on the command line
  static constexpr int kArity = 4;                   ///< particles per constraint
  static constexpr bool kInequality = false;         ///< an equality (a slack fiber's force law gives no force)
  static constexpr bool kTakesMaterial = true;       ///< may be in a set with a stress–strain curve (in Pa)
  static constexpr bool kBreaksWithFibers = true;    ///< torn with its tet (traits.hpp)
  static constexpr bool kColoredInteriors = true;    ///< block solver: interiors color by color (traits.hpp)
  static constexpr const char* kNoun = "tet fiber";                                   ///< the item in messages
  static constexpr std::array<const char*, 4> kParticleNames{"p0", "p1", "p2", "p3"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "tet_fibers";   ///< a tet body's key: {"direction": a0, curve or stiffness}
  static constexpr SceneForm kSceneForm = SceneForm::mesh;  ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;               ///< between four particles
  static constexpr const char* kForceUnit = "Pa";           ///< its reading is a stress (material_scale: V0)
  /// Its elastic strain |e| / (1 + ε_p), in percent.
  static constexpr Measure kMeasure{"tet_fiber_pct", "tet fiber strain", "%", 100.0};
  std::array<Index, 4> particles;  ///< the corners p0..p3, positively oriented at rest
  Index set;                       ///< constraint set (curve, stiffness or compliance) it belongs to
  Real volume;                     ///< rest volume V0 > 0, m³
  Vec3<Real> direction;            ///< fiber direction a0 in the rest shape (any length > 0; its unit vector is used)
  Vec3<Real> weights;              ///< b = Dm⁻¹·a0/|a0|, 1/m: F·a0 = Σ_i b_i (p_i − p0)
  Real plastic;                    ///< plastic strain ε_p ≥ 0: the rest shape has grown by 1 + ε_p along a0
  /// The rest values: V0 and b (default: measured from the current positions), a0 (default: the x axis) and ε_p
  /// (default 0).
  static constexpr auto fields() {
    return std::tuple{Field{"volume", "rest volume", &TetFiberConstraint::volume},
                      Field{"direction", "fiber direction", &TetFiberConstraint::direction, true},
                      Field{"weights", "fiber weights", &TetFiberConstraint::weights},
                      Field{"plastic", "plastic strain", &TetFiberConstraint::plastic, true}};
  }
};

namespace detail {
/// F·a0 = Σ_i b_i (p_i − p0) of tet fiber c at corners p.
template <class Real, class P> Eigen::Vector3d fiber_vector(const TetFiberConstraint<Real>& c, const P& p) {
  const Eigen::Vector3d b = c.weights.template cast<double>();
  return b.x() * (p(1) - p(0)) + b.y() * (p(2) - p(0)) + b.z() * (p(3) - p(0));
}
}  // namespace detail

/// C = |F·a0| − (1 + ε_p) and its gradients (file comment). F·a0 = 0 (no direction): returns false.
template <class Real>
inline bool evaluate(const TetFiberConstraint<Real>& c, const Vec3<Real> (&p)[4], Real& C, Vec3<Real> (&grad)[4]) {
  const Vec3<Real> f = c.weights.x() * (p[1] - p[0]) + c.weights.y() * (p[2] - p[0]) + c.weights.z() * (p[3] - p[0]);
  const Real len2 = f.squaredNorm();
  if (!(len2 > tiny_squared<Real>())) return false;
  const Real len = std::sqrt(len2);
  const Vec3<Real> n = f * (Real(1) / len);
  C = len - (Real(1) + c.plastic);
  grad[1] = c.weights.x() * n;
  grad[2] = c.weights.y() * n;
  grad[3] = c.weights.z() * n;
  grad[0] = -(c.weights.x() + c.weights.y() + c.weights.z()) * n;
  return true;
}

/// The correction: in a set with a curve, the fiber's own equation (fiber_newton with rest length 1, Σ w|∇C|² and
/// h²·V0); otherwise the projection with k and α̃/V0. False where F·a0 = 0 or nothing can move.
template <class Real>
inline bool correction(const TetFiberConstraint<Real>& c, const Vec3<Real> (&p)[4], const Real (&w)[4],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[4], Real& dlambda) {
  Real C;
  Vec3<Real> grad[4];
  if (!evaluate(c, p, C, grad)) return false;
  const Real s = c.weights.x() + c.weights.y() + c.weights.z();
  const Real wsum = w[0] * s * s + w[1] * c.weights.x() * c.weights.x() + w[2] * c.weights.y() * c.weights.y() +
                    w[3] * c.weights.z() * c.weights.z();
  if (coeff.material) {
    if (!(wsum > Real(0))) return false;
    const double len = double(C) + 1.0 + double(c.plastic);
    dlambda = Real(fiber_newton(*coeff.material, 1.0, double(c.plastic), len, double(wsum),
                                double(coeff.h2) * double(c.volume), double(lambda)));
  } else {
    const Real alpha = coeff.alpha_tilde / c.volume;
    const Real denom = alpha + wsum;
    if (!(denom > Real(0))) return false;
    dlambda = (-coeff.k * C - alpha * lambda) / denom;
  }
  for (int i = 0; i < 4; ++i) dp[i] = (w[i] * dlambda) * grad[i];
  return true;
}

/// Total strain |F·a0| − 1 at positions x (3 per particle), in double.
template <class Real> double material_strain(const TetFiberConstraint<Real>& c, const Real* x) {
  return detail::fiber_vector(c, [&](int i) {
           const Real* q = x + 3 * std::size_t(c.particles[std::size_t(i)]);
           return Eigen::Vector3d(double(q[0]), double(q[1]), double(q[2]));
         }).norm() - 1.0;
}

/// What its λ is scaled by: the force conjugate to its strain is V0·σ, so −λ/(h²·V0) is the stress σ in Pa.
template <class Real> double material_scale(const TetFiberConstraint<Real>& c) { return double(c.volume); }

/// Elastic strain ||F·a0| − (1 + ε_p)| / (1 + ε_p).
template <class Real> double violation(const TetFiberConstraint<Real>& c, const PositionsView<Real>& x) {
  const double len = detail::fiber_vector(c, [&](int i) { return detail::position_of<Real>(x, c.particles[std::size_t(i)]); }).norm();
  return detail::relative_error(len, 1.0 + double(c.plastic));
}

/// Defaults: V0 and b of the tet in x, a0 the x axis, ε_p = 0.
template <class Real, class X> const char* measure_rest(TetFiberConstraint<Real>& c, const X& x, FieldMask given) {
  if (!(given & 2u)) c.direction = Vec3<Real>::UnitX();
  if (!(given & 8u)) c.plastic = Real(0);
  const Real length = c.direction.norm();
  if (!(length > Real(0)) || !std::isfinite(length)) return "fiber direction must be finite and not zero";
  const auto& q = c.particles;
  Eigen::Matrix<Real, 3, 3> dm;
  dm << Vec3<Real>(x.col(q[1]) - x.col(q[0])), Vec3<Real>(x.col(q[2]) - x.col(q[0])),
      Vec3<Real>(x.col(q[3]) - x.col(q[0]));
  const Real det = dm.determinant();
  if (!(det > Real(0))) return "the tet is inverted or flat where it starts (its signed volume is not > 0)";
  if (!(given & 1u)) c.volume = det / Real(6);
  if (!(given & 4u)) c.weights = dm.inverse() * (c.direction / length);
  return nullptr;
}

/// V0 finite and > 0, a0 and b finite and not zero, ε_p finite and ≥ 0.
template <class Real> std::string rest_error(const TetFiberConstraint<Real>& c) {
  if (!std::isfinite(c.volume) || !(c.volume > Real(0)))
    return detail::message("rest volume must be finite and > 0 (the tet is inverted or flat), got ", c.volume);
  if (!c.direction.allFinite() || !(c.direction.squaredNorm() > Real(0))) return "fiber direction must be finite and not zero";
  if (!c.weights.allFinite() || !(c.weights.squaredNorm() > Real(0))) return "fiber weights must be finite and not all zero";
  if (!std::isfinite(c.plastic) || c.plastic < Real(0))
    return detail::message("plastic strain must be finite and >= 0, got ", c.plastic);
  return {};
}

}  // namespace pbd
