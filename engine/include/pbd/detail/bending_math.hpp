#pragma once
/// \file bending_math.hpp
/// The dihedral bending projection's arithmetic (constraints/bending.hpp), written once over a number type T: a
/// scalar (float, double) for the scalar projection, or the float kernel's SIMD lanes (engine/src/solve/
/// bending_kernel.cpp). Both run the same operations in the same order, so the kernel gives the scalar bits. Guards
/// are masks (bool for a scalar) rather than early returns, so the lanes run straight through.
/// What a T needs: lane_math.hpp.
#include "pbd/detail/lane_math.hpp"
#include "pbd/types.hpp"

#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>

namespace pbd::detail::bend {

using namespace lane;  // V3, Lit and the scalar overloads

/// Coefficients of P, highest degree first, in asin(s) = s + s·(P(z)·z) with z = s², s in [0, 1/2].
/// float: Cephes' single-precision arcsine (Moshier). double: a degree-12 Chebyshev fit of (asin √z − √z)/z^{3/2}
/// on [0, 1/4] (mpmath, 50 digits; fit error 1.5e-17, so asin is within rounding, about 1 ulp).
template <class Real> struct AsinPoly;
template <> struct AsinPoly<float> {
  static constexpr double c[] = {4.2163199048e-2, 2.4181311049e-2, 4.5470025998e-2, 7.4953002686e-2, 1.6666752422e-1};
};
template <> struct AsinPoly<double> {
  static constexpr double c[] = {0.028757851367421566, -0.014851887071247204, 0.01740087944269402,
                                 0.005457506718640358, 0.01032281435018578,   0.011479177415184906,
                                 0.013971212973552933, 0.017352392720869973,  0.02237217294214989,
                                 0.030381944138531247, 0.04464285714635543,   0.07499999999998433,
                                 0.16666666666666669};
};

/// acos(x) for x in [−1, 1] in precision Real from the arcsine polynomial: with a = |x|, asin(a) = s + s·P(z)·z
/// with z = a², s = a for a ≤ 1/2, and z = (1 − a)/2, s = √z above (acos(a) = 2·asin(s) there). Within 1.25 ulp of
/// π of the true angle in float (std::acos: 0.5 ulp) and 2 ulp of π in double (tests/engine/bending_test.cpp).
/// Plain arithmetic (no table, no branch), so SIMD lanes and the scalar code agree.
template <class Real, class T> [[gnu::always_inline]] inline T acos_poly(T x) {
  using L = Lit<T>;
  const T one = L::of(1.0), half = L::of(0.5);
  const T a = abs(x);
  const auto big = a > half;
  const T z = select(big, half * (one - a), a * a);
  const T s = select(big, sqrt(z), a);
  constexpr auto& c = AsinPoly<Real>::c;
  T p = L::of(c[0]);
  for (std::size_t i = 1; i < std::size(c); ++i) p = p * z + L::of(c[i]);
  p = p * z;
  const T r = s + s * p;  // asin(s)
  const T two_r = r + r, pi = L::of(3.14159265358979323846), half_pi = L::of(1.57079632679489661923);
  const auto neg = x < L::of(0.0);
  return select(big, select(neg, pi - two_r, two_r), select(neg, half_pi + r, half_pi - r));
}

/// The constraint's value and gradient where ok (both triangles give a normal and the pair is off the kink).
template <class T, class M> struct BendingGradient {
  M ok;
  T C;
  V3<T> g[4];
};

/// C = acos(n1·n2) − φ0 and its gradient (constraints/bending.hpp gives the formulas) at corners p (p1, p2 the
/// shared edge). Real: the precision whose guards apply (float for the lanes).
template <class Real, class T>
[[gnu::always_inline]] inline auto bending_gradient(const V3<T> (&p)[4], T rest) {
  using L = Lit<T>;
  constexpr Real sine = Real(64) * std::numeric_limits<Real>::epsilon();  // degenerate.hpp's parallel_sine
  const V3<T> e = p[1] - p[0], u = p[2] - p[0], v = p[3] - p[0];
  const V3<T> a = cross(e, u), b = cross(e, v);
  const T la2 = norm2(a), lb2 = norm2(b), e2 = norm2(e);
  constexpr Real tiny_c = tiny_squared<Real>(), sine2_c = sine * sine;  // folded here, never called at run time
  const T tiny = L::of(tiny_c), sine2 = L::of(sine2_c);
  // degenerate_cross: either triangle's corners are collinear at this precision, or a cross product underflows
  auto ok = (la2 > tiny) & (la2 > sine2 * e2 * norm2(u)) & (lb2 > tiny) & (lb2 > sine2 * e2 * norm2(v));
  const T one = L::of(1.0);
  const T ra = one / sqrt(la2), rb = one / sqrt(lb2);
  const V3<T> n1 = a * ra, n2 = b * rb;
  const T d = max(L::of(-1.0), min(dot(n1, n2), one));
  const T s2 = one - d * d;
  ok = ok & (s2 > L::of(sine));  // off the kink at φ = 0 and φ = π (1 − d² ≤ 64 ε)
  const T scale = L::of(-1.0) / sqrt(s2);  // ∇C = −∇d / √(1 − d²)
  const V3<T> t1 = (n2 - n1 * d) * ra, t2 = (n1 - n2 * d) * rb;
  BendingGradient<T, decltype(ok)> r;
  r.ok = ok;
  r.g[2] = cross(t1, e) * scale;
  r.g[3] = cross(t2, e) * scale;
  r.g[1] = (cross(u, t1) + cross(v, t2)) * scale;
  r.g[0] = V3<T>{L::of(0.0), L::of(0.0), L::of(0.0)} - r.g[1] - r.g[2] - r.g[3];
  r.C = acos_poly<Real>(d) - rest;
  return r;
}

/// One projection: w the inverse masses, neg_k −k, alpha α̃, lambda λ (projection.hpp's correction()).
template <class Real, class T>
[[gnu::always_inline]] inline auto bending_step(const V3<T> (&p)[4], const T (&w)[4], T rest, T neg_k, T alpha,
                                                T lambda) {
  using L = Lit<T>;
  const auto grad = bending_gradient<Real>(p, rest);
  const V3<T>(&g)[4] = grad.g;
  const T denom = alpha + w[0] * norm2(g[0]) + w[1] * norm2(g[1]) + w[2] * norm2(g[2]) + w[3] * norm2(g[3]);
  Step<T, decltype(grad.ok & (denom > denom)), 4> r;  // ok: the gradient exists and the denominator is positive
  r.ok = grad.ok & (denom > L::of(0.0));
  r.dlambda = (neg_k * grad.C - alpha * lambda) / denom;
  for (int i = 0; i < 4; ++i) r.dp[i] = g[i] * (w[i] * r.dlambda);
  return r;
}

}  // namespace pbd::detail::bend
