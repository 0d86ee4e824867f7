#pragma once
/// \file shape_match.hpp
/// Shape matching (Müller, Heidelberger, Teschner, Gross 2005, "Meshless deformations based on shape matching") as
/// an XPBD constraint on an overlapping cluster of 8 particles: a particle and its 7 nearest neighbours
/// (pbd/io/shape_match_clusters.hpp makes them from a tet mesh).
///
/// The match. With weights μ_i ∝ m_i, the rest offsets q_i re-centred on their weighted mean (q̂_i) and the current
/// positions on theirs, c = Σ μ_i x_i / Σ μ_i (p̂_i = x_i − c), the rotation that best maps the rest shape onto the
/// current one, min over R of Σ μ_i |R q̂_i − p̂_i|², is the rotational part R of A_pq = Σ μ_i p̂_i q̂_iᵀ. The goal
/// positions are g_i = T q̂_i + c with
///   rigid mode (β = 0)   T = R
///   linear mode (β > 0)  T = β·A/∛det A + (1 − β)·R, A = A_pq·A_qq⁻¹ the best linear map (A_qq = Σ μ_i q̂_i q̂_iᵀ),
///                        scaled to keep the cluster's volume (Müller §4.2): a uniformly squeezed cluster would
///                        match its unscaled A exactly and never push back. ∛det A is held in [1/2, 2], so that a
///                        nearly flat cluster's goal is not a huge pancake of its own volume; where det A ≤ 0
///                        (inverted or flat) or A_qq is singular (a flat rest shape) the goal is the rigid one.
///
/// The constraint. C = sqrt(Σ μ_i |x_i − g_i|² / Σ μ_i), the cluster's mass-weighted RMS distance to its goals,
/// in m, with g held fixed during the projection as Müller does. In the rigid mode that is C's exact gradient: g
/// minimizes the same sum over rotations and translations, so its motion changes C only to second order. With
/// m_i = 1/w_i and M = Σ m_i the cluster's mass: ∇_i C = (m_i/M)(x_i − g_i)/C, w_i ∇_i C = (x_i − g_i)/(M C) and
/// Σ_i w_i |∇_i C|² = 1/M, so the XPBD step (projection.hpp's) is
///   Δλ = (−k·C − α̃·λ) / (1/M + α̃),   Δx_i = (x_i − g_i)·Δλ/(M C),
/// with α̃ = 0 Müller's update Δx_i = k (g_i − x_i). Why the weighted mean and not the paper's sum Σ m_i|x_i − g_i|²:
/// (1) C and the compliance have the units of the other types (m, and m/N): the cluster is a spring of stiffness
/// 1/α on its RMS distance, its force on particle i (m_i/M)(g_i − x_i)/α; (2) Jacobi's split masses (particle i
/// enters every constraint with n_i·w_i, engine/src/solve/update_rule.hpp) scale a cluster's weights alike where
/// its particles are in equally many clusters, and leave this C and ∇C unchanged, so Jacobi converges to
/// Gauss-Seidel's λ as it does for the other types; with the sum, Jacobi's clusters would be n_i times softer.
///
/// Masses. The weights come from the inverse masses the projection is given: μ_i = w_min/w_i (w_min the smallest
/// w_i > 0 of the cluster), in (0, 1], so no mass that could overflow is ever formed and C depends on the ratios
/// alone. A pinned particle (w = 0) takes part in the fit with the weight of the heaviest movable particle (μ = 1)
/// and is never moved. Why: a pin is an infinite mass, but weights large enough to mimic it would drown the movable
/// particles' share of A_pq in rounding (and the fit would turn about the pins alone); weight 0 would fit the
/// movable particles as if the pin were not there and pull them rigidly away from it. As the heaviest particle, a
/// clamped vertex counts in its neighbours' clusters where it is, as one particle among equals. The step still
/// takes 1/M (M with the pins' weights) as Σ w_i |∇_i C|², as if the pins moved too, so a movable particle never
/// overshoots its goal: with α̃ = 0 it moves by k (g_i − x_i), and the pins' share of C is left to the next
/// iterations, whose fit has moved towards them. A cluster with every particle pinned moves nothing.
///
/// Momentum. Σ μ_i q̂_i = 0, so Σ m_i Δx_i ∝ Σ μ_i (p̂_i − T q̂_i) = 0 for any T: both modes keep linear momentum.
/// The torque about c, Σ m_i p̂_i × Δx_i ∝ Σ μ_i p̂_i × T q̂_i, is the axial vector of the antisymmetric part of
/// T·A_pqᵀ; with A_pq = R S (S symmetric) R·A_pqᵀ = R S Rᵀ is symmetric, and so is A_pq A_qq⁻¹ A_pqᵀ: both modes
/// keep angular momentum too (to the polar decomposition's rounding; the paper claims it for the rigid mode only).
///
/// The rotation. R = U diag(1, 1, det UVᵀ) Vᵀ from the SVD A_pq = U Σ Vᵀ (Eigen's JacobiSVD: two-sided Jacobi
/// rotations, accurate at any rank, a pure function of A_pq, so the same bits on any thread count). A cluster that is
/// neither flat nor reflected (det A_pq > 0, well conditioned: nearly all of them) gets the same U Vᵀ, to rounding,
/// from a scaled Newton iteration for the polar factor, also a pure function of A_pq and far cheaper. Where det A_pq <
/// 0 (a reflected cluster) the SVD's is the best proper rotation (the axis of the smallest singular value flipped costs
/// least) and RᵀA_pq is still symmetric; a reflected cluster is pulled back through flat to its rest orientation. A
/// coplanar cluster (rank 2) gets the one best rotation, a collinear or collapsed one (rank 1, 0) one of the equally
/// good ones, never a NaN. The arithmetic is detail/shape_match_math.hpp's, written once for the scalar projection
/// and the AVX2 kernel's lanes (eight clusters at a time in float), so the kernel gives the scalar bits.
///
/// Memory: 8 particle indices (32 B), the set (4 B), 8 rest offsets (96 B in float) and β (4 B): 136 bytes per
/// constraint in float, 240 in double. A_qq⁻¹ is not stored: it depends on the masses, which measure_rest does not
/// see (it is given positions only), set_mass may change, a pin's weight depends on its cluster and Jacobi splits;
/// the linear mode forms it at each projection (a few hundred flops, little beside the SVD).
///
/// Cost: the rotation is most of a projection, the linear mode adds little (docs/performance.md has the figures).
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/detail/shape_match_math.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace pbd {

/// Pulls 8 particles towards the best rigid (β = 0) or blended linear (β > 0) image of their rest shape.
template <class Real> struct ShapeMatchConstraint {
  static constexpr const char* kName = "shape_match";  ///< name in reports and on the command line
  static constexpr int kArity = 8;                     ///< particles per constraint: a particle and 7 neighbours
  static constexpr bool kInequality = false;           ///< an equality
  static constexpr const char* kNoun = "shape-matching cluster";  ///< the item in messages
  static constexpr std::array<const char*, 8> kParticleNames{"p0", "p1", "p2", "p3",
                                                              "p4", "p5", "p6", "p7"};  ///< argument names (Python)
  static constexpr const char* kSceneKey = "shape_matching";  ///< a tet body's key: one cluster per vertex
  static constexpr SceneForm kSceneForm = SceneForm::mesh;    ///< made by the body's generator
  static constexpr bool kTiesToWorld = false;                 ///< between eight particles
  /// Its violation is the RMS distance of the particles to their rigid goals (equal weights), in m, shown in mm.
  static constexpr Measure kMeasure{"shape_mm", "shape-matching distance", "mm", 1000.0};
  std::array<Index, 8> particles;  ///< the cluster
  Index set;                       ///< constraint set (stiffness) it belongs to
  Vec3<Real> q0;                   ///< rest offset of particle 0 from the cluster's rest centre, m
  Vec3<Real> q1;                   ///< rest offset of particle 1, m
  Vec3<Real> q2;                   ///< rest offset of particle 2, m
  Vec3<Real> q3;                   ///< rest offset of particle 3, m
  Vec3<Real> q4;                   ///< rest offset of particle 4, m
  Vec3<Real> q5;                   ///< rest offset of particle 5, m
  Vec3<Real> q6;                   ///< rest offset of particle 6, m
  Vec3<Real> q7;                   ///< rest offset of particle 7, m
  Real beta;                       ///< β in [0, 1]: 0 the rigid mode, > 0 the linear mode blended in

  /// The rest offsets as member pointers, q0..q7. They may be taken from any common point: the projection re-centres
  /// them on their mass-weighted mean (the measured ones are taken from the particles' centroid).
  static constexpr std::array<Vec3<Real> ShapeMatchConstraint::*, 8> offsets() {
    using S = ShapeMatchConstraint;
    return {&S::q0, &S::q1, &S::q2, &S::q3, &S::q4, &S::q5, &S::q6, &S::q7};
  }
  /// The rest values: the offsets (default: measured where the particles are) and β (default 0; a scene may give it).
  static constexpr auto fields() {
    using S = ShapeMatchConstraint;
    return std::tuple{Field{"q0", "rest offset 0", &S::q0}, Field{"q1", "rest offset 1", &S::q1},
                      Field{"q2", "rest offset 2", &S::q2}, Field{"q3", "rest offset 3", &S::q3},
                      Field{"q4", "rest offset 4", &S::q4}, Field{"q5", "rest offset 5", &S::q5},
                      Field{"q6", "rest offset 6", &S::q6}, Field{"q7", "rest offset 7", &S::q7},
                      Field{"beta", "linear-mode blend beta", &S::beta, true}};
  }
};

static_assert(sizeof(ShapeMatchConstraint<float>) == 136, "the memory the header's comment states");

namespace detail::shape_match {

template <class Real> using Mat3 = Eigen::Matrix<Real, 3, 3>;

template <class Real> math::M3<Real> to_m3(const Mat3<Real>& a) {
  return {{{a(0, 0), a(0, 1), a(0, 2)}, {a(1, 0), a(1, 1), a(1, 2)}, {a(2, 0), a(2, 1), a(2, 2)}}};
}
template <class Real> Mat3<Real> to_mat(const math::M3<Real>& a) {
  Mat3<Real> m;
  m << a.r[0].x, a.r[0].y, a.r[0].z, a.r[1].x, a.r[1].y, a.r[1].z, a.r[2].x, a.r[2].y, a.r[2].z;
  return m;
}
template <class Real> lane::V3<Real> to_v3(const Vec3<Real>& v) { return {v.x(), v.y(), v.z()}; }

/// The polar factor of a by Newton's iteration (shape_match_math.hpp's polar: where a is well conditioned with
/// det a > 0, within 12 steps); fills r and returns true, else false (a flat, reflected or badly conditioned a).
template <class Real> bool newton_polar(const Mat3<Real>& a, Mat3<Real>& r) {
  math::M3<Real> out{};
  if (!math::polar<Real>(to_m3(a), out)) return false;
  r = to_mat(out);
  return true;
}

/// The rotation nearest to a (3 × 3, by rows; Frobenius) by the SVD: U diag(1, 1, det UVᵀ) Vᵀ from a = U Σ Vᵀ (the
/// file comment says why), into r, for the clusters Newton's iteration does not take. Out of line
/// (engine/src/shape_match_svd.cpp), so that the scalar projection and the AVX2 kernel run the one same copy.
template <class Real> void svd_rotation(const Real (&a)[9], Real (&r)[9]);
extern template void svd_rotation(const float (&)[9], float (&)[9]);
extern template void svd_rotation(const double (&)[9], double (&)[9]);

/// The scalar projection's fallback (shape_match_math.hpp's match): the SVD's rotation where Newton's did not
/// converge.
struct SvdFallback {
  template <class Real> void operator()(const math::M3<Real>& a, math::M3<Real>& r, bool done) const {
    if (done) return;
    const Real in[9] = {a.r[0].x, a.r[0].y, a.r[0].z, a.r[1].x, a.r[1].y, a.r[1].z, a.r[2].x, a.r[2].y, a.r[2].z};
    Real out[9];
    svd_rotation(in, out);
    r = {{{out[0], out[1], out[2]}, {out[3], out[4], out[5]}, {out[6], out[7], out[8]}}};
  }
};

/// Whether a second-moment matrix (symmetric, positive semi-definite) spans space well enough to invert:
/// det > 10⁻⁶·(tr/3)³, about a thinnest extent above 10⁻³ of the cluster's size.
template <class Real> bool spans_space(const Mat3<Real>& moments) {
  const Real t = moments.trace() / Real(3);
  return t > Real(0) && moments.determinant() > Real(1e-6) * t * t * t;
}

/// Σ μ_i q_i q_iᵀ.
template <class Real> Mat3<Real> second_moments(const Vec3<Real> (&q)[8], const Real (&mu)[8]) {
  Mat3<Real> m = Mat3<Real>::Zero();
  for (int i = 0; i < 8; ++i) m.noalias() += (mu[i] * q[i]) * q[i].transpose();
  return m;
}

/// The rest offsets of c, q0..q7, in precision To.
template <class To, class Real> void rest_offsets(const ShapeMatchConstraint<Real>& c, Vec3<To> (&q)[8]) {
  constexpr auto members = ShapeMatchConstraint<Real>::offsets();
  for (int i = 0; i < 8; ++i) q[i] = (c.*members[i]).template cast<To>();
}

}  // namespace detail::shape_match

/// The XPBD step of the file comment (shape_match_math.hpp, which the AVX2 kernel shares, so its bits): weights
/// μ_i = w_min/w_i (pins: 1), the match, then with s = Δλ/(M C) = (−k − α̃λ/C)/(1 + α̃M): Δx_i = s·(x_i − g_i),
/// Δλ = s·M·C. False (nothing moves) when every particle is pinned or the cluster is at its goals (C² below
/// tiny_squared).
template <class Real>
inline bool correction(const ShapeMatchConstraint<Real>& c, const Vec3<Real> (&p)[8], const Real (&w)[8],
                       SolveCoefficients<Real> coeff, Real lambda, Vec3<Real> (&dp)[8], Real& dlambda) {
  using detail::shape_match::to_v3;
  constexpr auto members = ShapeMatchConstraint<Real>::offsets();
  detail::lane::V3<Real> x[8], rest[8];
  for (int i = 0; i < 8; ++i) {
    x[i] = to_v3(p[i]);
    rest[i] = to_v3(c.*members[i]);
  }
  const auto r = detail::shape_match::math::shape_match_step<Real>(x, w, rest, c.beta, -coeff.k, coeff.alpha_tilde,
                                                                   lambda, detail::shape_match::SvdFallback{});
  if (!r.ok) return false;
  for (int i = 0; i < 8; ++i) dp[i] = Vec3<Real>(r.dp[i].x, r.dp[i].y, r.dp[i].z);
  dlambda = r.dlambda;
  return true;
}

/// RMS distance of the particles to their goals in the rigid mode, equal weights (a violation sees positions, not
/// masses): 0 exactly when the cluster is a rotated and moved copy of its rest shape, in m.
template <class Real> double violation(const ShapeMatchConstraint<Real>& c, const PositionsView<Real>& x) {
  Vec3<double> rest[8];
  detail::shape_match::rest_offsets(c, rest);
  detail::lane::V3<double> q[8], p[8];
  double mu[8];
  for (int i = 0; i < 8; ++i) {
    q[i] = detail::shape_match::to_v3(rest[i]);
    p[i] = detail::shape_match::to_v3(Vec3<double>(detail::position_of<Real>(x, c.particles[i])));
    mu[i] = 1.0;
  }
  return std::sqrt(detail::shape_match::math::match<double>(q, p, mu, 0.0, detail::shape_match::SvdFallback{}).c2);
}

/// Defaults: each offset from the particles' centroid where they are, β = 0 (the rigid mode).
template <class Real, class X>
const char* measure_rest(ShapeMatchConstraint<Real>& c, const X& x, FieldMask given) {
  const Vec3<Real> first = x.col(c.particles[0]);
  Vec3<Real> mean = Vec3<Real>::Zero();
  for (Index i : c.particles) mean += Vec3<Real>(x.col(i)) - first;
  mean /= Real(8);
  constexpr auto members = ShapeMatchConstraint<Real>::offsets();
  for (int i = 0; i < 8; ++i)
    if (!(given & (FieldMask(1) << i))) c.*members[i] = (Vec3<Real>(x.col(c.particles[i])) - first) - mean;
  if (!(given & (FieldMask(1) << 8))) c.beta = Real(0);
  return nullptr;
}

/// Offsets finite and not all equal (a rest shape with no extent), β in [0, 1]; the linear mode (β > 0) needs a
/// rest shape that spans space (A_qq invertible; equal weights here, the projection checks again with its own).
template <class Real> std::string rest_error(const ShapeMatchConstraint<Real>& c) {
  Vec3<Real> q[8];
  detail::shape_match::rest_offsets(c, q);
  Vec3<Real> mean = Vec3<Real>::Zero();
  for (int i = 0; i < 8; ++i) {
    if (!q[i].allFinite()) return detail::message("rest offset ", i, " is not finite");
    mean += q[i] / Real(8);
  }
  if (!std::isfinite(c.beta) || !(c.beta >= Real(0) && c.beta <= Real(1)))
    return detail::message("beta must be in [0, 1], got ", c.beta);
  Real extent = Real(0);
  for (auto& qi : q) {
    qi -= mean;
    extent += qi.squaredNorm();
  }
  if (!(extent > tiny_squared<Real>())) return "the rest offsets are all equal (the cluster has no extent)";
  const Real ones[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  if (c.beta > Real(0) && !detail::shape_match::spans_space(detail::shape_match::second_moments(q, ones)))
    return "beta > 0 (the linear mode) needs a rest shape that spans space; these rest offsets are (nearly) coplanar";
  return {};
}

}  // namespace pbd
