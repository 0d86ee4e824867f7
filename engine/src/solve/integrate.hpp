#pragma once
// Steps 1–2 and 5 of a sub-step (private, solver.hpp): the per-particle passes around the solve. Each is a function of
// a particle range, one particle at a time, so any cut of [0, n) gives the same bits: a parallel loop (run_range)
// and a team's shared loop (team.hpp) both call them.
#include "pbd/step_params.hpp"
#include "pbd/types.hpp"

#include <algorithm>
#include <cstddef>
#include <type_traits>

namespace pbd::detail {

/// Steps 1–2 over particles [b, e): damping, gravity, the external force f (N, 3 per particle; nullptr: none),
/// then p = x + h·v. Pinned particles (w = 0) keep v = 0.
template <class Real> struct Predict {
  Real h;              ///< sub-step (s)
  Real keep;           ///< velocity kept by damping over h: max(0, 1 − damping·h)
  bool damp;           ///< damping > 0
  Real hg[3];          ///< h·g (m/s)
  const Real* w;       ///< inverse masses (1/kg)
  const Real* x;       ///< positions at the sub-step's start (m)
  Real* v;             ///< velocities (m/s), updated
  const Real* f;       ///< external forces (N) or nullptr
  Real* p;             ///< predicted positions (m), written (3 per particle)
  Real* q = nullptr;   ///< or, when set, the padded copy written instead (x y z w per particle, w the inverse mass)

  Predict(const StepParams<Real>& params, Real h_, const Real* w_, const Real* x_, Real* v_, const Real* f_, Real* p_)
      : h(h_), keep(std::max(Real(0), Real(1) - params.damping * h_)), damp(params.damping > Real(0)),
        hg{h_ * params.gravity[0], h_ * params.gravity[1], h_ * params.gravity[2]}, w(w_), x(x_), v(v_), f(f_), p(p_) {}

  void operator()(Index b, Index e) const {
    // One loop per case (damping, external forces), each without a branch per component, so that the compiler can
    // vectorize it; every case does the operations of the general one, so the bits do not depend on which runs.
    if (q) with_force(b, e, std::true_type{});
    else with_force(b, e, std::false_type{});
  }

private:
  template <class Padded> void with_force(Index b, Index e, Padded) const {
    using yes = std::true_type;
    using no = std::false_type;
    if (damp && f) run(b, e, yes{}, yes{}, Padded{});
    else if (damp) run(b, e, yes{}, no{}, Padded{});
    else if (f) run(b, e, no{}, yes{}, Padded{});
    else run(b, e, no{}, no{}, Padded{});
  }
  template <class Damp, class Force, class Padded> void run(Index b, Index e, Damp, Force, Padded) const {
    for (Index i = b; i < e; ++i) {
      const bool pinned = w[i] == Real(0);  // pinned particles keep their velocity (0 unless a host set one)
      for (int d = 0; d < 3; ++d) {
        const std::size_t j = 3 * std::size_t(i) + d;
        Real vd = v[j];
        // Damp first: damping then acts on the motion only, and a body at rest feels the whole of g and f.
        if constexpr (Damp::value) vd *= keep;
        vd += hg[d];
        if constexpr (Force::value) vd += h * (w[i] * f[j]);  // external force: a = w·f
        vd = pinned ? v[j] : vd;
        v[j] = vd;
        if constexpr (Padded::value) q[4 * std::size_t(i) + d] = x[j] + h * vd;
        else p[j] = x[j] + h * vd;
      }
      if constexpr (Padded::value) q[4 * std::size_t(i) + 3] = w[i];
    }
  }
};

/// Step 5 over particles [b, e) (without the free bodies' correction, free_bodies.hpp): v = (p − x)/h, computed as
/// v += (p − p̂)/h with p̂ = x + h·v the prediction (the same operations as in Predict, so the same bits). Equal in
/// exact arithmetic, but in floating point a velocity no constraint changed keeps all its digits instead of being
/// rounded to a multiple of ulp(x)/h, which would let a slow body (v·damping·h under half an ulp of x per step) keep
/// its speed for ever and crawl. The caller then makes p the positions.
template <class Real> void update_velocities(Real h, const Real* x, const Real* p, Real* v, Index b, Index e) {
  for (std::size_t j = 3 * std::size_t(b); j < 3 * std::size_t(e); ++j) {
    const Real predicted = x[j] + h * v[j];
    v[j] += (p[j] - predicted) / h;
  }
}

/// update_velocities with the solved positions in the padded copy q (x y z w per particle): copies them into p
/// (exactly, as unpadding does) and updates v from them, in one pass.
template <class Real>
void update_velocities_from_padded(Real h, const Real* x, const Real* q, Real* p, Real* v, Index b, Index e) {
  for (Index i = b; i < e; ++i)
    for (int d = 0; d < 3; ++d) {
      const std::size_t j = 3 * std::size_t(i) + d;
      const Real solved = q[4 * std::size_t(i) + d];
      p[j] = solved;
      const Real predicted = x[j] + h * v[j];
      v[j] += (solved - predicted) / h;
    }
}

}  // namespace pbd::detail
