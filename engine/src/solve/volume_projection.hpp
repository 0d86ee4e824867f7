#pragma once
// The volume projection shared by every solver (private). One constraint at a time, in two parallel phases over
// fixed blocks of kVolumeBlock rows:
//   0. per row: p_i − o (stored, turned for elementwise cross products);
//   A. per row: ∇_i C = Σ_ring (p_j − o) × (p_k − o) (stored), and per block the partial sums
//      Σ (p_i − o)·∇_i C (= 3 · 6V), Σ w_i|∇_i C|², Σ w_i|p_i − o|⁴ (for the collapse guard);
//   then, on one thread, the block sums in block order, C = Σ(p − o)·∇C / 3 − target (the target within a factor
//   kVolumeStep of the volume) and Δλ;
//   B. per row: out_i += w_i ∇_i C Δλ (pinned rows never written).
// o is the constraint's first particle, read before any write. `run(begin, end, body)` runs body over a block
// range, serially or in parallel: the arithmetic per block and the order of the final sum do not depend on it.
#include "pbd/constraints/degenerate.hpp"
#include "pbd/constraints/volume.hpp"

#include <algorithm>
#include <cstring>

namespace pbd::detail {

/// Four Reals as one vector of the compiler's (GCC and Clang vector extensions): elementwise arithmetic, each lane
/// rounded as the scalar operation is.
template <class Real> struct Lanes4;
template <> struct Lanes4<float> {
  typedef float type __attribute__((vector_size(16)));
};
template <> struct Lanes4<double> {
  typedef double type __attribute__((vector_size(32)));
};

/// The largest ratio between the volume and the target one projection aims at (see project_volume).
inline constexpr int kVolumeStep = 2;

template <class Real, class Run>
void project_volume(const VolumeConstraints<Real>& v, Index index, const Real* p, Real* out, const Real* w,
                    SolveCoefficients<Real> coeff, Real target, Real& lambda, VolumeScratch<Real>& s, Run&& run) {
  const VolumeConstraint<Real>& c = v.items[index];
  const Index r0 = c.row_begin, rows = c.row_end - c.row_begin;
  if (rows == 0) return;
  const Index blocks = (rows + kVolumeBlock - 1) / kVolumeBlock;
  if (s.grad.size() < 3 * std::size_t(rows)) s.grad.resize(3 * std::size_t(rows));
  if (s.partial.size() < 3 * std::size_t(blocks)) s.partial.resize(3 * std::size_t(blocks));
  using V = Vec3<Real>;
  auto at = [p](Index i) { return Eigen::Map<const V>(p + 3 * std::size_t(i)); };
  const V o = at(v.particles[r0]);
  Real* grad = s.grad.data();
  Real* partial = s.partial.data();
  // 0. d_r = p − o once per row, stored turned twice, so that a ring's cross products are elementwise:
  //    (a × b)_c = a_{c+1} b_{c+2} − a_{c+2} b_{c+1} = ayzx_c · bzxy_c − azxy_c · byzx_c (the same operations as Eigen's
  //    cross on a − o and b − o, in the same order, so the same bits, and lanes the compiler vectorizes)
  if (s.turned.size() < 8 * std::size_t(rows)) s.turned.resize(8 * std::size_t(rows));
  Real* turned = s.turned.data();
  run(Index(0), blocks, [&](Index b0, Index b1) {
    const Index end = std::min<Index>(rows, b1 * kVolumeBlock);
    for (Index r = b0 * kVolumeBlock; r < end; ++r) {
      const V d = at(v.particles[r0 + r]) - o;
      Real* t = turned + 8 * std::size_t(r);
      t[0] = d.y(), t[1] = d.z(), t[2] = d.x(), t[3] = Real(0);
      t[4] = d.z(), t[5] = d.x(), t[6] = d.y(), t[7] = Real(0);
    }
  });
  const std::array<Index, 2>* ring_rows = v.ring_rows.data();
  run(Index(0), blocks, [&](Index b0, Index b1) {
    for (Index b = b0; b < b1; ++b) {
      Real pg = 0, wgg = 0, wr4 = 0;
      const Index end = std::min<Index>(rows, (b + 1) * kVolumeBlock);
      for (Index r = b * kVolumeBlock; r < end; ++r) {
        const Index row = r0 + r;
        using L = typename Lanes4<Real>::type;
        L gc = {};
        for (Index k = v.ring_offsets[row]; k < v.ring_offsets[row + 1]; ++k) {
          const Real* a = turned + 8 * std::size_t(ring_rows[k][0]);
          const Real* c = turned + 8 * std::size_t(ring_rows[k][1]);
          L a0, a1, c0, c1;
          std::memcpy(&a0, a, sizeof(L));
          std::memcpy(&a1, a + 4, sizeof(L));
          std::memcpy(&c0, c, sizeof(L));
          std::memcpy(&c1, c + 4, sizeof(L));
          gc += a0 * c1 - a1 * c0;
        }
        const V g(gc[0], gc[1], gc[2]);
        Eigen::Map<V>(grad + 3 * std::size_t(r)) = g;
        const Index i = v.particles[row];
        const Real* t = turned + 8 * std::size_t(r);
        const V d(t[2], t[0], t[1]);
        const Real d2 = d.squaredNorm();
        pg += d.dot(g);
        wgg += w[i] * g.squaredNorm();
        wr4 += w[i] * d2 * d2;
      }
      partial[3 * b] = pg;
      partial[3 * b + 1] = wgg;
      partial[3 * b + 2] = wr4;
    }
  });
  Real pg = 0, wgg = 0, wr4 = 0;
  for (Index b = 0; b < blocks; ++b) {
    pg += partial[3 * b];
    wgg += partial[3 * b + 1];
    wr4 += partial[3 * b + 2];
  }
  // Guards: all pinned (both sums 0) or collapsed to a line or a point (gradients vanish against the mesh's size).
  const Real sine = parallel_sine<Real>();
  if (!(wgg > sine * sine * wr4)) return;
  const Real denom = wgg + coeff.alpha_tilde;
  // A target far from the volume (a pressure jump, a rest volume given far from the mesh's) is approached at most
  // kVolumeStep-fold per projection: the step is linear in the volume, which is cubic in the positions, so one
  // step of a hundredfold would overshoot by the cube and the next could turn the mesh inside out. Within the ratio
  // (every gradual schedule) the target is used as it is, to the bit. An inverted mesh is pushed to its target.
  const Real volume = pg / Real(3);
  const Real aim = volume > Real(0) ? std::clamp(target, volume / kVolumeStep, volume * kVolumeStep) : target;
  const Real C = volume - aim;
  const Real dlambda = (-coeff.k * C - coeff.alpha_tilde * lambda) / denom;
  if (!std::isfinite(dlambda)) return;
  if (coeff.alpha_tilde != Real(0)) lambda += dlambda;  // λ is kept only where it enters (projection.hpp)
  run(Index(0), blocks, [&](Index b0, Index b1) {
    for (Index b = b0; b < b1; ++b) {
      const Index end = std::min<Index>(rows, (b + 1) * kVolumeBlock);
      for (Index r = b * kVolumeBlock; r < end; ++r) {
        const Index i = v.particles[r0 + r];
        if (w[i] == Real(0)) continue;
        Eigen::Map<V>(out + 3 * std::size_t(i)) += (w[i] * dlambda) * Eigen::Map<const V>(grad + 3 * std::size_t(r));
      }
    }
  });
}

}  // namespace pbd::detail
