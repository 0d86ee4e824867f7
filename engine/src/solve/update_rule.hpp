#pragma once
// The update rule of the sweeps (private): how a projection's correction reaches the positions.
//   in place  Gauss-Seidel: each projection moves p at once (w: the inverse masses)
//   Jacobi    the built-in and user-defined constraints all read the same p and add their corrections to a delta
//             per particle, computed with split masses (Tonge et al. 2012): particle i, touched by n_i of them,
//             enters each with inverse mass n_i·w_i, so that p += ω·delta / n_i after the sweep applies exactly
//             w_i ∇C·(ω Δλ) per constraint and λ += ω Δλ tracks it (XPBD's λ then converges to Gauss-Seidel's, and
//             every correction conserves momentum)
// Volumes and contacts are projected in place under either rule (sweep.hpp).
#include "sweep_loops.hpp"

#include <algorithm>

namespace pbd::detail {

template <class Real> class UpdateRule {
public:
  UpdateRule(Update update, Real omega) : update_(update), omega_(omega) {}

  Update kind() const { return update_; }
  bool in_place() const { return update_ == Update::in_place; }

  /// The start of a sub-step: Jacobi's per-particle counts and split masses (Model::touch_count).
  void begin(const Model<Real>& m, Scratch<Real>& k) const {
    if (in_place()) return;
    const Index n = m.num_particles();
    const Real* w = m.inverse_mass.data();
    k.count_inv.resize(n);
    k.split_w.resize(n);
    for (Index i = 0; i < n; ++i) {
      const Index c = m.touch_count[i];
      k.count_inv[i] = c ? Real(1) / Real(c) : Real(0);
      k.split_w[i] = c ? w[i] * Real(c) : w[i];
    }
    k.delta.resize(3 * std::size_t(n));
  }

  /// The inverse masses the projections of the constraint types use.
  const Real* masses(const Model<Real>& m, const Scratch<Real>& k) const {
    return in_place() ? m.inverse_mass.data() : k.split_w.data();
  }
  /// Where they write: p itself, or the deltas (zeroed here, at the start of each sweep).
  Real* start_sweep(Real* p, Scratch<Real>& k) const {
    if (in_place()) return p;
    std::fill(k.delta.begin(), k.delta.end(), Real(0));
    return k.delta.data();
  }
  /// The factor λ moves by (ω under Jacobi).
  Real relax() const { return in_place() ? Real(1) : omega_; }

  /// After the constraint types: Jacobi applies p += ω·delta / count.
  void finish_sweep(Real* p, const Model<Real>& m, Scratch<Real>& k, SweepLoops<Real>& loops) const {
    if (in_place()) return;
    const Real* delta = k.delta.data();
    const Real* count_inv = k.count_inv.data();
    const Real omega = omega_;
    loops.range(0, m.num_particles(), loops.config(), loops.slots(1), [&](Index b, Index e) {
      for (Index i = b; i < e; ++i) {
        const Real s = omega * count_inv[i];
        for (int d = 0; d < 3; ++d) p[3 * std::size_t(i) + d] += s * delta[3 * std::size_t(i) + d];
      }
    });
  }

private:
  Update update_;
  Real omega_;
};

}  // namespace pbd::detail
