#pragma once
// Stretch projection over a range of constraints of ONE color, in blocks of kBlock: gather, a branch-free block
// computation the compiler vectorizes, scatter. Within a color no two constraints write the same particle, so
// a block gives exactly what one-by-one projection gives; each lane performs the same operations in the same order
// as project() + correction() for a StretchConstraint (same guards, same rounding: tests/engine/stretch_batch_test
// checks bitwise equality), so results do not depend on where blocks start. Private to the engine; used by the
// colored Gauss-Seidel sweep.
#include "pbd/constraints/stretch.hpp"
#include "pbd/stiffness.hpp"

#include <algorithm>
#include <cmath>

namespace pbd::detail {

template <class Real>
inline void project_stretch_range(const StretchConstraint<Real>* c, Index begin, Index end, Real* p, const Real* w,
                                  const SolveCoefficients<Real>* coeff, Real* lambda) {
  constexpr int kBlock = 16;
  alignas(64) Real dx[kBlock], dy[kBlock], dz[kBlock], w0[kBlock], w1[kBlock], rest[kBlock], k[kBlock], at[kBlock],
      lam[kBlock], ok[kBlock], inv[kBlock], s0[kBlock], s1[kBlock];
  for (Index first = begin; first < end; first += kBlock) {
    const int n = int(std::min<Index>(kBlock, end - first));
    const StretchConstraint<Real>* cb = c + first;
    for (int b = 0; b < n; ++b) {
      const Real* a = p + 3 * std::size_t(cb[b].particles[0]);
      const Real* q = p + 3 * std::size_t(cb[b].particles[1]);
      dx[b] = a[0] - q[0];
      dy[b] = a[1] - q[1];
      dz[b] = a[2] - q[2];
      w0[b] = w[cb[b].particles[0]];
      w1[b] = w[cb[b].particles[1]];
      rest[b] = cb[b].rest;
      const SolveCoefficients<Real> co = coeff[cb[b].set];
      k[b] = co.k;
      at[b] = co.alpha_tilde;
      lam[b] = lambda[first + b];
    }
    for (int b = n; b < kBlock; ++b) dx[b] = dy[b] = dz[b] = w0[b] = w1[b] = rest[b] = k[b] = at[b] = lam[b] = Real(0);
    // Branch-free: lanes whose gradient is undefined or whose denominator is not positive get dλ = 0 and ok = 0.
    for (int b = 0; b < kBlock; ++b) {
      const Real len2 = dx[b] * dx[b] + (dy[b] * dy[b] + dz[b] * dz[b]);  // Eigen's squaredNorm() order
      const bool valid = len2 > tiny_squared<Real>();
      const Real len = std::sqrt(valid ? len2 : Real(1));
      inv[b] = Real(1) / len;
      const Real C = len - rest[b];
      const Real denom = (at[b] + w0[b]) + w1[b];
      const bool good = valid && denom > Real(0);
      const Real dl = good ? (-k[b] * C - at[b] * lam[b]) / (good ? denom : Real(1)) : Real(0);
      ok[b] = good ? Real(1) : Real(0);
      lam[b] = lam[b] + dl;
      s0[b] = w0[b] * dl;  // dp0 = (w0 dλ)·(d·(1/|d|)), dp1 = −(w1 dλ)·(d·(1/|d|)), applied below
      s1[b] = w1[b] * dl;
    }
    for (int b = 0; b < n; ++b) {
      if (ok[b] == Real(0)) continue;
      lambda[first + b] = lam[b];
      if (w0[b] != Real(0)) {
        Real* a = p + 3 * std::size_t(cb[b].particles[0]);
        a[0] += s0[b] * (dx[b] * inv[b]);
        a[1] += s0[b] * (dy[b] * inv[b]);
        a[2] += s0[b] * (dz[b] * inv[b]);
      }
      if (w1[b] != Real(0)) {
        Real* q = p + 3 * std::size_t(cb[b].particles[1]);
        q[0] -= s1[b] * (dx[b] * inv[b]);
        q[1] -= s1[b] * (dy[b] * inv[b]);
        q[2] -= s1[b] * (dz[b] * inv[b]);
      }
    }
  }
}

}  // namespace pbd::detail
