#pragma once
/// \file lane_math.hpp
/// What the projections written once over a number type T need (bending_math.hpp, area_math.hpp): T is a scalar
/// (float, double) for the scalar projection or a SIMD kernel's lanes, and both run the same operations in the same
/// order, so the kernels give the scalar bits. A T needs + − × ÷, sqrt, min, max, abs, select(mask, a, b),
/// comparisons > and < giving a mask, masks combined with &, and Lit<T>::of(constant). Scalars get these here; the
/// kernels give their lanes theirs (found by argument-dependent lookup) and specialize Lit.
#include <cmath>

namespace pbd::detail::lane {

/// A constant in a T (specialized by the SIMD kernel for its lanes).
template <class T> struct Lit {
  static T of(double v) { return T(v); }
};

// The scalar overloads (the lanes' own are found by argument-dependent lookup).
template <class S> [[gnu::always_inline]] inline S select(bool m, S a, S b) { return m ? a : b; }
[[gnu::always_inline]] inline float sqrt(float a) { return std::sqrt(a); }
[[gnu::always_inline]] inline double sqrt(double a) { return std::sqrt(a); }
/// No lane set (the lanes': no bit of their mask).
[[gnu::always_inline]] inline bool none(bool m) { return !m; }
[[gnu::always_inline]] inline float abs(float a) { return std::abs(a); }
[[gnu::always_inline]] inline double abs(double a) { return std::abs(a); }
/// std::min and std::max (the lanes': minps and maxps, the same for numbers).
template <class S> [[gnu::always_inline]] inline S min(S a, S b) { return b < a ? b : a; }
template <class S> [[gnu::always_inline]] inline S max(S a, S b) { return a < b ? b : a; }

/// Three coordinates, each a T.
template <class T> struct V3 {
  T x, y, z;
};
template <class T> [[gnu::always_inline]] inline V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T> [[gnu::always_inline]] inline V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T> [[gnu::always_inline]] inline V3<T> operator*(const V3<T>& a, T s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T> [[gnu::always_inline]] inline V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> [[gnu::always_inline]] inline T dot(const V3<T>& a, const V3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T> [[gnu::always_inline]] inline T norm2(const V3<T>& a) { return dot(a, a); }

/// One single-multiplier projection's result (bending_math.hpp, area_math.hpp, tet_volume_math.hpp), meaningful
/// where ok (a mask, or a bool for scalars): Δλ and the Δp_i of its N corners.
template <class T, class M, int N> struct Step {
  M ok;
  T dlambda;
  V3<T> dp[N];
};

}  // namespace pbd::detail::lane
