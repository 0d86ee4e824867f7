#pragma once
/// \file tet_volume_math.hpp
/// The tet volume projection's arithmetic (constraints/tet_volume.hpp), written once over a number type T
/// (lane_math.hpp): a scalar for the scalar projection, or the AVX2 kernel's lanes (engine/src/solve/
/// kernels_avx2.cpp), which then give the scalar bits. Guards are masks, so the lanes run straight through.
/// With a = p1 − p0, b = p2 − p0, d = p3 − p0: ∇1 C = (b × d)/6, ∇2 C = (d × a)/6, ∇3 C = (a × b)/6,
/// ∇0 C = −∇1 C − ∇2 C − ∇3 C and C = ∇3 C · d − V0 (the signed volume less the rest volume); no square root, one
/// division.
#include "pbd/detail/lane_math.hpp"
#include "pbd/types.hpp"

namespace pbd::detail::tet_volume {

using namespace lane;

/// One projection of C = V − V0 at corners p: w the inverse masses, neg_k −k, alpha α̃, lambda λ (projection.hpp's
/// correction(): Δλ = (−k·C − α̃·λ) / (α̃ + Σ_i w_i |∇_i C|²), Δp_i = ∇_i C · w_i Δλ). A tet collapsed onto a line
/// has no gradient: with α̃ = 0 its denominator is 0 and it moves nothing.
template <class Real, class T>
[[gnu::always_inline]] inline auto tet_volume_step(const V3<T> (&p)[4], const T (&w)[4], T rest, T neg_k, T alpha,
                                                   T lambda) {
  using L = Lit<T>;
  const T zero = L::of(0.0), sixth = L::of(1.0 / 6.0);
  const V3<T> a = p[1] - p[0], b = p[2] - p[0], d = p[3] - p[0];
  V3<T> g[4];
  g[1] = cross(b, d) * sixth;
  g[2] = cross(d, a) * sixth;
  g[3] = cross(a, b) * sixth;
  g[0] = V3<T>{zero, zero, zero} - g[1] - g[2] - g[3];
  const T C = dot(g[3], d) - rest;
  const T denom = alpha + w[0] * norm2(g[0]) + w[1] * norm2(g[1]) + w[2] * norm2(g[2]) + w[3] * norm2(g[3]);
  Step<T, decltype(denom > zero), 4> r;  // ok: the denominator is positive
  r.ok = denom > zero;
  r.dlambda = (neg_k * C - alpha * lambda) / denom;
  for (int i = 0; i < 4; ++i) r.dp[i] = g[i] * (w[i] * r.dlambda);
  return r;
}

}  // namespace pbd::detail::tet_volume
