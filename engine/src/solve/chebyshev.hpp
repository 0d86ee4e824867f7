#pragma once
// Chebyshev semi-iterative acceleration of a sub-step's sweeps (private; Wang 2015, "A Chebyshev Semi-Iterative
// Approach for Accelerating Projective and Position-based Dynamics"). Around sweep k, which turns q_k into q̂:
//   before(k)  q_k is kept (positions, and the XPBD λ when some set is compliant)
//   after(k)   d_k = |q̂ − q_k|² is measured (summed over fixed blocks of particles in block order: the same bits on
//              any thread count); then, from sweep `delay` on and except at the last sweep (so that the volumes and
//              contacts keep the last word), q_{k+1} = ω·(q̂ − q_{k−1}) + q_{k−1}, λ likewise (λ moves with the
//              positions it produced, so XPBD's λ keeps matching them), with ω = 2/(2 − ρ²) first, then
//              ω ← 4/(4 − ρ²ω).
// ρ is the spectral radius of one sweep, given by the user or estimated by the first sub-step that needs it: that
// sub-step sweeps plain and measures the rate at which its changes shrink over its second half, ρ² = (d_{K−1} /
// d_{K/2})^{1/(K−1−K/2)} (a power iteration on the sweep's error: the slowest mode takes over, and its rate is ρ),
// capped at max_rho; solve() keeps it in the world's State (an output, not a parameter), so later sub-steps and
// copies of the world use the same ρ and the same bits. The guard: a sweep whose change exceeds diverge² times the smallest
// change of the sub-step so far (the iteration is diverging, e.g. ρ given too large) ends the acceleration for the
// rest of the sub-step; the sweeps go on plain from where they are.
#include "parallel_range.hpp"
#include "pbd/step_params.hpp"
#include "pbd/detail/model.hpp"
#include "scratch.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace pbd::detail {

template <class Real> class ChebyshevAccelerator {
public:
  /// Particles per block of the change's sum (the sum's shape is fixed by this alone).
  static constexpr Index kSumBlock = 2048;

  ChebyshevAccelerator(const Chebyshev<Real>& params, int iterations, Index particles, State<Real>& state,
                       Scratch<Real>& scratch, bool parallel, const ParallelConfig& config)
      : c_(params), iterations_(iterations), n_(particles), s_(state), k_(scratch), parallel_(parallel),
        config_(config), rho_(params.rho) {
    k_.cheb_prev.resize(3 * std::size_t(n_));
    k_.cheb_cur.resize(3 * std::size_t(n_));
    k_.cheb_sums.resize(std::size_t((n_ + kSumBlock - 1) / kSumBlock));
  }

  /// Before sweep k: keeps q_k (and λ_k where λ moves).
  void before(int k, const Real* p) {
    if (rho_ == Real(0) && k != iterations_ / 2 && k != iterations_ - 1) return;  // estimating: two changes suffice
    if (k == 0) gather_lambda();  // λ arrays are sized by now (Sweeper::begin)
    run_range(0, 3 * n_, parallel_, config_, k_.cheb_partitioners[0], [&](Index b, Index e) {
      std::copy(p + b, p + e, k_.cheb_cur.data() + b);
    });
    if (s_.lambda_dirty) {
      std::size_t at = 0;
      for (std::span<Real> l : lambda_) {
        std::copy(l.begin(), l.end(), k_.cheb_lambda_cur.begin() + at);
        at += l.size();
      }
    }
  }

  /// After sweep k (p holds q̂): measures the change, guards, extrapolates (or, estimating, records the change).
  void after(int k, Real* p) {
    const double d = change(p);
    if (rho_ == Real(0)) {  // estimating: plain sweeps
      if (k == iterations_ / 2) d_half_ = d;
      if (k == iterations_ - 1 && d_half_ > 0.0 && d > 0.0 && std::isfinite(d)) {
        const double r2 = std::pow(d / d_half_, 1.0 / double(iterations_ - 1 - iterations_ / 2));
        estimate_ = Real(std::min(std::sqrt(r2), double(c_.max_rho)));
      }
      return;
    }
    if (!std::isfinite(d) || (k > 0 && d > double(c_.diverge) * double(c_.diverge) * d_min_)) {
      if (active_) fell_back_ = true;
      active_ = false;
    }
    if (k == 0 || d < d_min_) d_min_ = d;
    if (active_ && k >= c_.delay && k < iterations_ - 1) {
      const Real r2 = rho_ * rho_;
      omega_ = k == c_.delay ? Real(2) / (Real(2) - r2) : Real(4) / (Real(4) - r2 * omega_);
      extrapolate(p);
    }
    std::swap(k_.cheb_prev, k_.cheb_cur);  // q_k is q_{k−1} of the next sweep
    std::swap(k_.cheb_lambda_prev, k_.cheb_lambda_cur);
  }

  bool fell_back() const { return fell_back_; }  ///< the guard stopped the acceleration in this sub-step
  /// ρ measured by an estimating sub-step (0: none, e.g. nothing moved).
  Real estimate() const { return estimate_; }

private:
  // Every λ array of the sub-step, in a fixed order; the flat copies sized to match.
  void gather_lambda() {
    lambda_.clear();
    if (!s_.lambda_dirty) return;
    for (auto& l : s_.lambda) lambda_.emplace_back(l);  // every type's, in for_each_type's order
    lambda_.emplace_back(s_.volume_lambda);
    lambda_.emplace_back(k_.collision_lambda);
    lambda_.emplace_back(k_.particle_contact_lambda);
    std::size_t total = 0;
    for (std::span<Real> l : lambda_) total += l.size();
    k_.cheb_lambda_cur.resize(total);
    k_.cheb_lambda_prev.resize(total);
  }

  // |p − q_k|², in double, over fixed blocks of particles summed in block order.
  double change(const Real* p) {
    const Real* q = k_.cheb_cur.data();
    const Index blocks = Index(k_.cheb_sums.size());
    run_range(0, blocks, parallel_, per_block(config_, kSumBlock), k_.cheb_partitioners[1], [&](Index b, Index e) {
      for (Index blk = b; blk < e; ++blk) {
        double sum = 0.0;
        const std::size_t end = 3 * std::size_t(std::min(n_, (blk + 1) * kSumBlock));
        for (std::size_t j = 3 * std::size_t(blk) * kSumBlock; j < end; ++j) {
          const double diff = double(p[j]) - double(q[j]);
          sum += diff * diff;
        }
        k_.cheb_sums[blk] = sum;
      }
    });
    double total = 0.0;
    for (double s : k_.cheb_sums) total += s;
    return total;
  }

  // q_{k+1} = ω (q̂ − q_{k−1}) + q_{k−1}, positions and λ.
  void extrapolate(Real* p) {
    const Real* prev = k_.cheb_prev.data();
    const Real w = omega_;
    run_range(0, 3 * n_, parallel_, config_, k_.cheb_partitioners[2], [&](Index b, Index e) {
      for (Index j = b; j < e; ++j) p[j] = w * (p[j] - prev[j]) + prev[j];
    });
    if (!s_.lambda_dirty) return;
    std::size_t at = 0;
    for (std::span<Real> l : lambda_) {
      const Real* lp = k_.cheb_lambda_prev.data() + at;
      for (std::size_t j = 0; j < l.size(); ++j) l[j] = w * (l[j] - lp[j]) + lp[j];
      at += l.size();
    }
  }

  const Chebyshev<Real>& c_;
  int iterations_;
  Index n_;
  State<Real>& s_;
  Scratch<Real>& k_;
  bool parallel_;
  const ParallelConfig& config_;
  Real rho_;
  Real omega_ = 1;
  double d_min_ = 0.0, d_half_ = 0.0;
  Real estimate_ = 0;
  bool active_ = true, fell_back_ = false;
  std::vector<std::span<Real>> lambda_;
};

}  // namespace pbd::detail
