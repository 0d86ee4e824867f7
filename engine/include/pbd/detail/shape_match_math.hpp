#pragma once
/// \file shape_match_math.hpp
/// The shape-matching projection's arithmetic (constraints/shape_match.hpp), written once over a number type T
/// (lane_math.hpp): a scalar for the scalar projection, or the AVX2 kernel's lanes (engine/src/solve/
/// kernels_avx2.cpp), which then give the scalar bits. Guards are masks, so the lanes run straight through; the two
/// steps that are not lane arithmetic: the SVD for a cluster Newton's iteration does not take (the caller's
/// `fallback`, lane by lane) and the cube root of the linear mode (cube_root, out of line; the kernel calls it lane
/// by lane: libm's cbrt, inlined or vectorized differently in the AVX2 file, gave other bits).
/// Matrices are 3 × 3, stored by rows; the inverse transpose of x is its cofactor matrix (rows: the cross products
/// of x's other two rows) over det x.
#include "pbd/detail/lane_math.hpp"
#include "pbd/types.hpp"

#include <cmath>
#include <limits>

namespace pbd::detail::shape_match::math {

using namespace lane;

/// A 3 × 3 matrix in T, by rows.
template <class T> struct M3 {
  V3<T> r[3];
};

/// ∛x by libm, compiled once (engine/src/shape_match_svd.cpp) for the scalar projection and the kernel's lanes.
float cube_root(float x);
double cube_root(double x);

template <class T> [[gnu::always_inline]] inline T norm2(const M3<T>& m) {
  return lane::norm2(m.r[0]) + lane::norm2(m.r[1]) + lane::norm2(m.r[2]);
}
template <class T> [[gnu::always_inline]] inline M3<T> cofactors(const M3<T>& m) {
  return {{cross(m.r[1], m.r[2]), cross(m.r[2], m.r[0]), cross(m.r[0], m.r[1])}};
}
template <class T> [[gnu::always_inline]] inline T det(const M3<T>& m) { return dot(m.r[0], cross(m.r[1], m.r[2])); }
template <class T> [[gnu::always_inline]] inline V3<T> over(const V3<T>& v, T s) { return {v.x / s, v.y / s, v.z / s}; }
template <class T> [[gnu::always_inline]] inline M3<T> over(const M3<T>& m, T s) {
  return {{over(m.r[0], s), over(m.r[1], s), over(m.r[2], s)}};
}
template <class T> [[gnu::always_inline]] inline M3<T> operator-(const M3<T>& a, const M3<T>& b) {
  return {{a.r[0] - b.r[0], a.r[1] - b.r[1], a.r[2] - b.r[2]}};
}
/// m v.
template <class T> [[gnu::always_inline]] inline V3<T> times(const M3<T>& m, const V3<T>& v) {
  return {dot(m.r[0], v), dot(m.r[1], v), dot(m.r[2], v)};
}
/// a b.
template <class T> [[gnu::always_inline]] inline M3<T> times(const M3<T>& a, const M3<T>& b) {
  M3<T> out;
  for (int i = 0; i < 3; ++i) out.r[i] = b.r[0] * a.r[i].x + b.r[1] * a.r[i].y + b.r[2] * a.r[i].z;
  return out;
}
template <class M, class T> [[gnu::always_inline]] inline V3<T> select3(M m, const V3<T>& a, const V3<T>& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class M, class T> [[gnu::always_inline]] inline M3<T> select3(M m, const M3<T>& a, const M3<T>& b) {
  return {{select3(m, a.r[0], b.r[0]), select3(m, a.r[1], b.r[1]), select3(m, a.r[2], b.r[2])}};
}
/// Each entry: f(a_ij, b_ij).
template <class T, class F> [[gnu::always_inline]] inline M3<T> each(const M3<T>& a, const M3<T>& b, const F& f) {
  M3<T> out;
  for (int i = 0; i < 3; ++i) out.r[i] = {f(a.r[i].x, b.r[i].x), f(a.r[i].y, b.r[i].y), f(a.r[i].z, b.r[i].z)};
  return out;
}

/// The polar factor of a by Newton's iteration X ← ½(γX + X⁻ᵀ/γ), scaled by γ = (‖X⁻¹‖/‖X‖)^½ (Higham), where a is
/// well conditioned with det a > 0 (det a over 1/50 of that of a rotation of the same size): it converges in a few
/// steps to the SVD's U Vᵀ. Sets r where a lane converged (a step moved X by under a few roundings, within 12
/// steps) and returns those lanes; the others' r is untouched. A converged lane's X stays as it was.
template <class Real, class T> [[gnu::always_inline]] inline auto polar(const M3<T>& a, M3<T>& r) {
  using L = Lit<T>;
  const Real root3 = std::sqrt(Real(3)), tol = Real(16) * std::numeric_limits<Real>::epsilon();
  const T half = L::of(0.5), still = L::of(double(tol * tol * Real(3)));
  const T size = sqrt(norm2(a)) / L::of(double(root3));  // a rotation's Frobenius norm is √3
  auto run = det(a) > L::of(0.02) * size * size * size;
  auto done = run & (size < size);  // no lane yet
  M3<T> x = over(a, size);
  for (int k = 0; k < 12 && !none(run); ++k) {
    const M3<T> cof = cofactors(x);
    const M3<T> inv_t = over(cof, dot(x.r[0], cof.r[0]));
    const T gamma = sqrt(sqrt(norm2(inv_t) / norm2(x)));
    const M3<T> next = each(x, inv_t, [&](T xi, T ii) { return half * (gamma * xi + ii / gamma); });
    const T moved = norm2(next - x);
    x = select3(run, next, x);
    const auto now = run & (still > moved);
    r = select3(now, x, r);
    done = done | now;
    run = run & (moved > still);  // converged, or NaN: stop (the latter not done)
  }
  return done;
}

/// Σ μ_i q_i q_iᵀ.
template <class T> [[gnu::always_inline]] inline M3<T> second_moments(const V3<T> (&q)[8], const T (&mu)[8]) {
  M3<T> m;
  for (int k = 0; k < 3; ++k) {
    const auto of = [&](int i) { return k == 0 ? q[i].x : k == 1 ? q[i].y : q[i].z; };
    m.r[k] = q[0] * (mu[0] * of(0));
    for (int i = 1; i < 8; ++i) m.r[k] = m.r[k] + q[i] * (mu[i] * of(i));
  }
  return m;
}

/// The goal matrix T of shape_match.hpp from A_pq, its rotation r and the centred rest offsets q̂ with their weights:
/// where β > 0, the rest shape spans space (det A_qq > 10⁻⁶·(tr/3)³) and A = A_pq·A_qq⁻¹ has det A > 0,
/// β·A/∛clamp(det A, 1/8, 8) + (1 − β)·r; elsewhere r.
template <class Real, class T>
[[gnu::always_inline]] inline M3<T> goal_matrix(const M3<T>& apq, const M3<T>& r, const V3<T> (&q)[8],
                                                const T (&mu)[8], T beta) {
  using L = Lit<T>;
  const T zero = L::of(0.0), one = L::of(1.0);
  const auto linear = beta > zero;
  if (none(linear)) return r;
  const M3<T> aqq = second_moments(q, mu);
  const T t = (aqq.r[0].x + aqq.r[1].y + aqq.r[2].z) / L::of(3.0), d = det(aqq);
  const auto spans = (t > zero) & (d > L::of(1e-6) * t * t * t);
  const M3<T> a = times(apq, over(cofactors(aqq), d));  // A_qq is symmetric: its cofactors are its adjugate
  const T da = det(a);
  const auto use = linear & spans & (da > zero);
  if (none(use)) return r;
  const M3<T> scaled = over(a, cube_root(max(L::of(0.125), min(da, L::of(8.0)))));
  const T rest = one - beta;
  const M3<T> blend = each(scaled, r, [&](T s, T ri) { return beta * s + rest * ri; });
  return select3(use, blend, r);
}

/// A cluster matched: d_i = x_i − g_i and C² = Σ μ_i |d_i|² / Σ μ_i; total = Σ μ_i.
template <class T> struct Match {
  V3<T> d[8];
  T c2;
  T total;
};

/// Matches rest offsets `rest` (from any common point) to positions x with weights mu (> 0) in mode beta, centred
/// on x[0] (shape_match.hpp's match). fallback(apq, r, polar_done) sets r where Newton's iteration did not.
template <class Real, class T, class Fallback>
[[gnu::always_inline]] inline Match<T> match(const V3<T> (&rest)[8], const V3<T> (&x)[8], const T (&mu)[8], T beta,
                                             const Fallback& fallback) {
  Match<T> m;
  V3<T> rel[8];
  for (int i = 0; i < 8; ++i) rel[i] = x[i] - x[0];
  m.total = mu[0];
  V3<T> pm = rel[0] * mu[0], qm = rest[0] * mu[0];
  for (int i = 1; i < 8; ++i) {
    m.total = m.total + mu[i];
    pm = pm + rel[i] * mu[i];
    qm = qm + rest[i] * mu[i];
  }
  pm = over(pm, m.total);
  qm = over(qm, m.total);
  V3<T> p[8], q[8];
  M3<T> apq;
  for (int i = 0; i < 8; ++i) {
    p[i] = rel[i] - pm;
    q[i] = rest[i] - qm;
  }
  const auto of = [&](int i, int k) { return k == 0 ? p[i].x : k == 1 ? p[i].y : p[i].z; };
  for (int k = 0; k < 3; ++k) {
    apq.r[k] = q[0] * (mu[0] * of(0, k));
    for (int i = 1; i < 8; ++i) apq.r[k] = apq.r[k] + q[i] * (mu[i] * of(i, k));
  }
  M3<T> r = apq;
  const auto done = polar<Real>(apq, r);
  fallback(apq, r, done);
  const M3<T> t = goal_matrix<Real>(apq, r, q, mu, beta);
  for (int i = 0; i < 8; ++i) m.d[i] = p[i] - times(t, q[i]);
  T sum = mu[0] * lane::norm2(m.d[0]);
  for (int i = 1; i < 8; ++i) sum = sum + mu[i] * lane::norm2(m.d[i]);
  m.c2 = sum / m.total;
  return m;
}

/// The XPBD step of shape_match.hpp at positions x with inverse masses w: weights μ_i = w_min/w_i (pins: 1), the
/// match, then s = (−k − α̃λ/C)/(1 + α̃M), Δx_i = s·d_i and Δλ = s·M·C. ok where some particle moves and C² is above
/// tiny_squared.
template <class Real, class T, class Fallback>
[[gnu::always_inline]] inline auto shape_match_step(const V3<T> (&x)[8], const T (&w)[8], const V3<T> (&rest)[8],
                                                    T beta, T neg_k, T alpha, T lambda, const Fallback& fallback) {
  using L = Lit<T>;
  constexpr Real tiny_c = tiny_squared<Real>();  // folded here, never called at run time
  const T zero = L::of(0.0), one = L::of(1.0), inf = L::of(double(std::numeric_limits<Real>::infinity()));
  T w_min = inf;
  for (int i = 0; i < 8; ++i) w_min = select(w[i] > zero, min(w_min, w[i]), w_min);
  T mu[8];
  for (int i = 0; i < 8; ++i) mu[i] = select(w[i] > zero, w_min / w[i], one);
  const Match<T> m = match<Real>(rest, x, mu, beta, fallback);
  const T C = sqrt(m.c2), mass = m.total / w_min;
  const T s = (neg_k - alpha * lambda / C) / (one + alpha * mass);
  Step<T, decltype(w_min < inf), 8> out;
  out.ok = (w_min < inf) & (m.c2 > L::of(tiny_c));
  for (int i = 0; i < 8; ++i) out.dp[i] = m.d[i] * s;
  out.dlambda = s * mass * C;
  return out;
}

}  // namespace pbd::detail::shape_match::math
