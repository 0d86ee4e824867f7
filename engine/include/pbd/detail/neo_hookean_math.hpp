#pragma once
/// \file neo_hookean_math.hpp
/// The Neo-Hookean tet's coupled projection (constraints/neo_hookean.hpp), written once over a number type T
/// (lane_math.hpp): a scalar for the scalar projection, or the AVX2 kernel's lanes (engine/src/solve/
/// kernels_avx2.cpp), which then give the scalar bits. Guards are masks, so the lanes run straight through.
/// Written out in coordinates, with no matrix temporaries: with e_k = p_k − p0 and r_j the columns of Dm⁻¹,
///   F_j = e1 r_j.x + e2 r_j.y + e3 r_j.z          (the columns of F = Ds·Dm⁻¹)
///   f_i = F·m_i for i = 1..3                      (m_i: row i of Dm⁻¹), f0 = −Σ f_i
///   h_i = s·(e_{i+1} × e_{i+2}), s = det Dm⁻¹     (indices mod 3 over 1..3), h0 = −Σ h_i
///   det F = s·(e1·(e2 × e3))
/// so the position gradients are ∇_i C_D = f_i/|F| and ∇_i C_H = h_i: ∇_i det F = cof F·m_i, and cof F =
/// cof Ds·cof Dm⁻¹ = s·cof Ds·Dmᵀ, whose columns times m_i leave s times the columns of cof Ds, the edges' cross
/// products (fewer operations than cof F itself, and the same for any Dm⁻¹ given). The 2 × 2 system of the
/// coupled step is solved by Cramer's rule with one division by its determinant; |F| enters as one reciprocal. In
/// all: one square root and three divisions (α̃/V0, 1/|F|, 1/det) per tet.
#include "pbd/detail/lane_math.hpp"
#include "pbd/types.hpp"

namespace pbd::detail::neo_hookean {

using namespace lane;

/// A tet's rest values in T: the columns of Dm⁻¹, V0 and μ/λ.
template <class T> struct TetRest {
  V3<T> inv[3];
  T volume;
  T ratio;
};

/// One projection's result where ok (the set has compliance, F ≠ 0 and the 2 × 2 system is positive definite):
/// Δλ_D, Δλ_H and Δp_i.
template <class T, class M> struct NeoHookeanStep {
  M ok;
  T dlambda[2];
  V3<T> dp[4];
};

/// Row i of the matrix with columns r: (r0[i], r1[i], r2[i]).
template <class T> [[gnu::always_inline]] inline V3<T> row(const V3<T> (&r)[3], int i) {
  if (i == 0) return {r[0].x, r[1].x, r[2].x};
  if (i == 1) return {r[0].y, r[1].y, r[2].y};
  return {r[0].z, r[1].z, r[2].z};
}

/// The matrix with columns c times the vector m: c0 m.x + c1 m.y + c2 m.z.
template <class T> [[gnu::always_inline]] inline V3<T> times(const V3<T> (&c)[3], const V3<T>& m) {
  return c[0] * m.x + c[1] * m.y + c[2] * m.z;
}

/// The file comment's f from the matrix with columns c = F: c·m_i for p_i, i = 1..3 (m_i the rows of Dm⁻¹ inv),
/// and 0 minus their sum for p0.
template <class T> [[gnu::always_inline]] inline void corner_gradients(const V3<T> (&c)[3], const V3<T> (&inv)[3],
                                                                      T zero, V3<T> (&g)[4]) {
  for (int i = 1; i < 4; ++i) g[i] = times(c, row(inv, i - 1));
  g[0] = V3<T>{zero, zero, zero} - g[1] - g[2] - g[3];
}

/// Σ_i w_i (u_i·v_i), p0's term first.
template <class T> [[gnu::always_inline]] inline T weighted_dot(const T (&w)[4], const V3<T> (&u)[4], const V3<T> (&v)[4]) {
  return w[0] * dot(u[0], v[0]) + w[1] * dot(u[1], v[1]) + w[2] * dot(u[2], v[2]) + w[3] * dot(u[3], v[3]);
}

/// One coupled step of C_D = |F| and C_H = det F − (1 + μ/λ) at corners p (neo_hookean.hpp's correction()): w the
/// inverse masses, alpha the set's α̃, lambda_d and lambda_h the tet's λ. Real: the precision whose guard applies.
template <class Real, class T>
[[gnu::always_inline]] inline auto neo_hookean_step(const V3<T> (&p)[4], const T (&w)[4], const TetRest<T>& rest,
                                                    T alpha, T lambda_d, T lambda_h) {
  using L = Lit<T>;
  constexpr Real tiny_c = tiny_squared<Real>();  // folded here, never called at run time
  const T one = L::of(1.0), zero = L::of(0.0);
  const V3<T> e[3] = {p[1] - p[0], p[2] - p[0], p[3] - p[0]};
  const V3<T> F[3] = {times(e, rest.inv[0]), times(e, rest.inv[1]), times(e, rest.inv[2])};
  const T n2 = norm2(F[0]) + norm2(F[1]) + norm2(F[2]);
  V3<T> f[4], h[4];
  corner_gradients(F, rest.inv, zero, f);
  const T s_rest = dot(rest.inv[0], cross(rest.inv[1], rest.inv[2]));  // det Dm⁻¹
  h[1] = cross(e[1], e[2]);
  const T J = dot(e[0], h[1]) * s_rest;
  h[1] = h[1] * s_rest;
  h[2] = cross(e[2], e[0]) * s_rest;
  h[3] = cross(e[0], e[1]) * s_rest;
  h[0] = V3<T>{zero, zero, zero} - h[1] - h[2] - h[3];
  const T norm = sqrt(n2), inv_norm = one / norm;
  const T alpha_d = alpha / rest.volume, alpha_h = rest.ratio * alpha_d;
  const T a = weighted_dot(w, f, f) * (inv_norm * inv_norm) + alpha_d;
  const T b = weighted_dot(w, f, h) * inv_norm;
  const T d = weighted_dot(w, h, h) + alpha_h;
  const T det = a * d - b * b;
  const T rd = -norm - alpha_d * lambda_d;
  const T rh = (one + rest.ratio - J) - alpha_h * lambda_h;
  const T inv_det = one / det;
  NeoHookeanStep<T, decltype((alpha > zero) & (n2 > zero))> r;
  r.ok = (alpha > zero) & (n2 > L::of(tiny_c)) & (det > zero);
  r.dlambda[0] = (d * rd - b * rh) * inv_det;
  r.dlambda[1] = (a * rh - b * rd) * inv_det;
  const T s = r.dlambda[0] * inv_norm;
  for (int i = 0; i < 4; ++i) r.dp[i] = (f[i] * s + h[i] * r.dlambda[1]) * w[i];
  return r;
}

}  // namespace pbd::detail::neo_hookean
