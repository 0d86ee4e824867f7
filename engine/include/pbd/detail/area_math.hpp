#pragma once
/// \file area_math.hpp
/// The triangle area projection's arithmetic (constraints/area.hpp), written once over a number type T (lane_math.hpp):
/// a scalar for the scalar projection, or the AVX2 kernel's lanes (engine/src/solve/kernels_avx2.cpp), which then
/// give the scalar bits. Guards are masks, so the lanes run straight through.
/// With u = p2 − p1, v = p3 − p1, a = u × v and r = 1/|a|: C = ½|a| − A0, ∇2 C = ½r (v × a), ∇3 C = ½r (a × u),
/// ∇1 C = −∇2 C − ∇3 C. Since a is normal to u and v, |∇2 C|² = ¼|v|², |∇3 C|² = ¼|u|² and |∇1 C|² = ¼|v − u|²: the
/// denominator needs no norm of a gradient, and there is one square root and one division before Δλ's.
#include "pbd/detail/lane_math.hpp"
#include "pbd/types.hpp"

#include <limits>

namespace pbd::detail::area {

using namespace lane;

/// One projection of C = ½|u × v| − A0 at corners p: w the inverse masses, neg_k −k, alpha α̃, lambda λ
/// (projection.hpp's correction()). Real: the precision whose guards apply (degenerate.hpp's degenerate_cross).
template <class Real, class T>
[[gnu::always_inline]] inline auto area_step(const V3<T> (&p)[3], const T (&w)[3], T rest, T neg_k, T alpha, T lambda) {
  using L = Lit<T>;
  constexpr Real sine = Real(64) * std::numeric_limits<Real>::epsilon();  // degenerate.hpp's parallel_sine
  constexpr Real tiny_c = tiny_squared<Real>(), sine2_c = sine * sine;     // folded here, never called at run time
  const V3<T> u = p[1] - p[0], v = p[2] - p[0];
  const V3<T> a = cross(u, v);
  const T a2 = norm2(a), u2 = norm2(u), v2 = norm2(v);
  auto ok = (a2 > L::of(tiny_c)) & (a2 > L::of(sine2_c) * u2 * v2);  // degenerate_cross: no normal
  const T len = sqrt(a2);
  const T half = L::of(0.5), quarter = L::of(0.25);
  const T half_r = half / len;
  const T C = half * len - rest;
  const V3<T> g1 = cross(v, a) * half_r, g2 = cross(a, u) * half_r;
  const V3<T> g0 = V3<T>{L::of(0.0), L::of(0.0), L::of(0.0)} - g1 - g2;
  const T denom = alpha + w[0] * (quarter * norm2(v - u)) + w[1] * (quarter * v2) + w[2] * (quarter * u2);
  Step<T, decltype(ok & (denom > denom)), 3> r;  // ok: the triangle gives a normal and the denominator is positive
  r.ok = ok & (denom > L::of(0.0));
  r.dlambda = (neg_k * C - alpha * lambda) / denom;
  r.dp[0] = g0 * (w[0] * r.dlambda);
  r.dp[1] = g1 * (w[1] * r.dlambda);
  r.dp[2] = g2 * (w[2] * r.dlambda);
  return r;
}

}  // namespace pbd::detail::area
