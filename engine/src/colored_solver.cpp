#include "pbd/colored_solver.hpp"

#include "parallel_range.hpp"
#include "pbd/constraints/projection.hpp"
#include "stretch_block.hpp"
#include "volume_projection.hpp"

#include <algorithm>

namespace pbd {
namespace {

using detail::run_blocks;
using detail::run_range;


}  // namespace

template <class Real>
void ColoredSolver<Real>::build(const ConstraintArrays<Real>& constraints, const VectorX<Real>& w,
                                const coloring::Options& options, CustomTypes<Real>& custom) {
  colored_ = color_constraints(constraints, w, options);
  fixed_ = pinned_flags(w);
  for (const auto& t : custom.types()) t->color(fixed_, options);
  num_particles_ = Index(w.size());
  count_static(custom);
  partitioners_.clear();
  built_ = true;
}

template <class Real>
bool ColoredSolver<Real>::up_to_date(const ConstraintArrays<Real>& constraints, const CustomTypes<Real>& custom,
                                     Index num_particles) const {
  if (!built_ || num_particles != num_particles_ || constraints.volume.size() != colored_.volume.size()) return false;
  bool same = true;
  colored_.zip(constraints, [&](const auto& items, const auto& arr) {
    same = same && arr.color.size() == items.size();
  });
  for (const auto& t : custom.types()) same = same && t->colored_up_to_date();
  return same;
}

template <class Real>
void ColoredSolver<Real>::update(const ConstraintArrays<Real>& constraints, const VectorX<Real>& w,
                                 const coloring::Options& options, CustomTypes<Real>& custom) {
  if (!built_) return build(constraints, w, options, custom);
  for (Index i = num_particles_; i < Index(w.size()); ++i) fixed_.push_back(w[i] == Real(0));  // added particles
  const auto& fixed = fixed_;
  num_particles_ = Index(w.size());
  static_count_.resize(num_particles_, 0);  // particles added since: nothing touches them yet
  bool ok = true;
  colored_.zip(constraints, [&](const auto& items, auto& arr) {
    const std::size_t first = arr.color.size();
    if (!ok || first == items.size()) return;
    ok = color_appended(arr, items, fixed);
    for (std::size_t i = first; ok && i < items.size(); ++i)
      for (Index k : items[i].particles) ++static_count_[k];
  });
  bool custom_changed = false;
  for (const auto& t : custom.types())
    if (ok && !t->colored_up_to_date()) {
      ok = t->color_appended(fixed);
      custom_changed = true;
    }
  if (!ok) return build(constraints, w, options, custom);
  if (colored_.volume.size() != constraints.volume.size()) {
    colored_.volume = constraints.volume;  // each volume constraint is its own color: nothing to color
    custom_changed = true;
  }
  if (custom_changed) {
    count_static(custom);
  } else {  // appended stretch constraints changed only the tail colors (they may have joined a color of another set)
    const auto& s = colored_.stretch;
    note_stretch_sets(std::min(s.tail_color, s.num_colors()));
  }
}

template <class Real> void ColoredSolver<Real>::count_static(const CustomTypes<Real>& custom) {
  static_count_.assign(num_particles_, 0);
  colored_.for_each([&](const auto& a) {
    for (const auto& c : a.items)
      for (Index k : c.particles) ++static_count_[k];
  });
  for (Index k : colored_.volume.particles) ++static_count_[k];
  for (const auto& t : custom.types()) t->count_particles(static_count_);
  note_stretch_sets();
}

template <class Real> void ColoredSolver<Real>::note_stretch_sets(Index first) {
  if constexpr (std::is_same_v<Real, float> && detail::kPaddedStretch) {  // only the float kernel reads them
    const auto& a = colored_.stretch;
    stretch_sets_.resize(a.num_colors(), detail::kMixedSets);
    for (Index c = first; c < a.num_colors(); ++c) {
      const auto b = a.items.begin() + a.offsets[c], e = a.items.begin() + a.offsets[c + 1];
      const bool one = b != e && std::all_of(b, e, [&](const auto& x) { return x.set == b->set; });
      stretch_sets_[c] = one ? b->set : detail::kMixedSets;
    }
  }
}

template <class Real>
void ColoredSolver<Real>::begin_substep(std::vector<CollisionConstraint<Real>>& collisions, double time,
                                        CustomTypes<Real>& custom) {
  for (const auto& t : custom.types()) t->reset_lambda();
  counts_ready_ = false;
  padded_current_ = false;
  volume_.set_targets(colored_.volume, time);
  // Collisions arrive particle by particle; the k-th collision of a particle gets color k (stable counting sort).
  const Index n = Index(collisions.size());
  collision_offsets_.assign({0, n});
  if (n > 1) {
    std::vector<Index> slot(n, 0);
    Index max_slot = 0;
    for (Index i = 1; i < n; ++i)
      if (collisions[i].particles[0] == collisions[i - 1].particles[0]) max_slot = std::max(max_slot, slot[i] = slot[i - 1] + 1);
    if (max_slot > 0) {
      collision_offsets_.assign(max_slot + 2, 0);
      for (Index s : slot) ++collision_offsets_[s + 1];
      for (Index s = 0; s <= max_slot; ++s) collision_offsets_[s + 1] += collision_offsets_[s];
      std::vector<Index> next(collision_offsets_.begin(), collision_offsets_.end() - 1);
      collision_scratch_.resize(n);
      for (Index i = 0; i < n; ++i) collision_scratch_[next[slot[i]]++] = collisions[i];
      collisions.swap(collision_scratch_);
    }
  }
  // λ changes only where α̃ ≠ 0 (projection.hpp): after sub-steps whose sweeps had no such set, every λ is still 0
  // and the (serial) reset can be skipped.
  if (lambda_written_ || !lambda_.sized_for(colored_, collisions.size())) lambda_.reset(colored_, collisions.size());
  lambda_written_ = false;
}

template <class Real> bool ColoredSolver<Real>::note_compliance(std::span<const SolveCoefficients<Real>> coeff) {
  const bool any = std::ranges::any_of(coeff, [](const auto& s) { return s.alpha_tilde != Real(0); });
  lambda_written_ = lambda_written_ || any;
  return any;
}

template <class Real>
void ColoredSolver<Real>::sweep_gauss_seidel(std::span<const CollisionConstraint<Real>> collisions,
                                             std::span<const SolveCoefficients<Real>> coeff, Real* p, const Real* w,
                                             bool parallel, const ParallelConfig& config,
                                             CustomTypes<Real>& custom) {
  std::size_t part = 0;
  const bool any_xpbd = note_compliance(coeff);
  // When stretch is all this sweep projects, the positions may stay padded until end_substep().
  const bool stretch_only = colored_.anchor.items.empty() && colored_.bending.items.empty() &&
                            colored_.area.items.empty() && colored_.volume.size() == 0 && custom.types().empty() &&
                            collisions.empty();
  lambda_.zip(colored_, [&](const auto& array, std::vector<Real>& lam) {
    using Constraint = typename std::decay_t<decltype(array)>::value_type;
    if constexpr (std::is_same_v<Constraint, StretchConstraint<float>> && detail::kPaddedStretch) {
      if (array.num_colors() > 0)
        project_stretch_colors(array, lam.data(), p, w, coeff.data(), any_xpbd, stretch_only, parallel, config, part);
    } else {
      for (Index c = 0; c < array.num_colors(); ++c)
        run_range(array.offsets[c], array.offsets[c + 1], parallel, config, partitioners_[part++],
                  [&](Index b, Index e) {
                    for (Index i = b; i < e; ++i)
                      project(array.items[i], p, w, coefficients_of(array.items[i], coeff.data()), lam[i]);
                  });
    }
  });
  for (const auto& t : custom.types())  // one virtual call per color range, never per constraint
    for (Index c = 0; c < t->num_colors(); ++c)
      run_range(t->color_begin(c), t->color_begin(c + 1), parallel, config, partitioners_[part++],
                [&](Index b, Index e) { t->project_colored(b, e, p, w, coeff.data()); });
  project_volumes(p, p, w, coeff, parallel, config, part);
  const SolveCoefficients<Real> hard{Real(1), Real(0)};
  for (Index c = 0; c < collision_colors(); ++c)
    run_range(collision_offsets_[c], collision_offsets_[c + 1], parallel, config, partitioners_[part++],
              [&](Index b, Index e) {
                for (Index i = b; i < e; ++i) project(collisions[i], p, w, hard, lambda_.collision[i]);
              });
}

template <class Real>
void ColoredSolver<Real>::sweep_jacobi(std::span<const CollisionConstraint<Real>> collisions,
                                       std::span<const SolveCoefficients<Real>> coeff, Real* p, const Real* w,
                                       Real omega, bool parallel, const ParallelConfig& config,
                                       CustomTypes<Real>& custom) {
  end_substep(p, parallel, config);  // Jacobi reads p: bring it up to date if Gauss-Seidel sweeps left it padded
  const Index n = num_particles_;
  if (count_inv_.size() != n || delta_.size() != 3 * std::size_t(n)) {
    count_inv_.resize(n);
    delta_.resize(3 * std::size_t(n));
  }
  // Constraints touching each particle in this sub-step (persistent ones plus its collisions).
  if (!counts_ready_) {  // once per sub-step, not per sweep: only the sub-step's collisions change the counts
    count_.assign(static_count_.begin(), static_count_.end());
    for (const auto& c : collisions) ++count_[c.particles[0]];
    for (Index i = 0; i < n; ++i) count_inv_[i] = count_[i] ? Real(1) / Real(count_[i]) : Real(0);
    counts_ready_ = true;
  }
  std::fill(delta_.begin(), delta_.end(), Real(0));
  Real* delta = delta_.data();
  note_compliance(coeff);
  std::size_t part = 0;
  lambda_.zip(colored_, [&](const auto& array, std::vector<Real>& lam) {
    for (Index c = 0; c < array.num_colors(); ++c)
      run_range(array.offsets[c], array.offsets[c + 1], parallel, config, partitioners_[part++], [&](Index b, Index e) {
        for (Index i = b; i < e; ++i)
          accumulate(array.items[i], p, w, coefficients_of(array.items[i], coeff.data()), lam[i], delta);
      });
  });
  for (const auto& t : custom.types())
    for (Index c = 0; c < t->num_colors(); ++c)
      run_range(t->color_begin(c), t->color_begin(c + 1), parallel, config, partitioners_[part++],
                [&](Index b, Index e) { t->accumulate_colored(b, e, p, w, coeff.data(), delta); });
  project_volumes(p, delta, w, coeff, parallel, config, part);
  const SolveCoefficients<Real> hard{Real(1), Real(0)};
  for (Index c = 0; c < collision_colors(); ++c)
    run_range(collision_offsets_[c], collision_offsets_[c + 1], parallel, config, partitioners_[part++],
              [&](Index b, Index e) {
                for (Index i = b; i < e; ++i) accumulate(collisions[i], p, w, hard, lambda_.collision[i], delta);
              });
  run_range(0, n, parallel, config, partitioners_[part], [&](Index b, Index e) {
    for (Index i = b; i < e; ++i) {
      const Real s = omega * count_inv_[i];
      for (int d = 0; d < 3; ++d) p[3 * std::size_t(i) + d] += s * delta[3 * std::size_t(i) + d];
    }
  });
}

template <class Real>
void ColoredSolver<Real>::project_stretch_colors(const ColoredArray<StretchConstraint<Real>>& array, Real* lam,
                                                 Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                                                 bool any_xpbd, bool keep_padded, bool parallel,
                                                 const ParallelConfig& config, std::size_t& part) {
  if constexpr (std::is_same_v<Real, float>) {
    // Project every stretch color on padded positions (x y z w): one aligned load and store per particle in the
    // kernel instead of three of each plus w. Copied in unless the last sweep left them there, copied back unless
    // keep_padded (then end_substep() copies them back). Partitioner slots are the same whichever copies run.
    const Index n = num_particles_;
    const std::size_t pad_slot = part++;
    unpad_slot_ = part++;
    if (!padded_current_) {
      padded_.resize(4, n);
      float* q = padded_.data();
      run_range(0, n, parallel, config, partitioners_[pad_slot],
                [&](Index b, Index e) { detail::pad_positions(p, w, b, e, q); });
    }
    float* q = padded_.data();
    const bool sets_known = stretch_sets_.size() == std::size_t(array.num_colors());
    for (Index c = 0; c < array.num_colors(); ++c) {
      const Index set = sets_known ? stretch_sets_[c] : detail::kMixedSets;
      run_blocks(array.offsets[c], array.offsets[c + 1], detail::kStretchBlock, parallel, config,
                 partitioners_[part++], [&](Index b, Index e) {
                   detail::project_stretch_range(array.items.data(), b, e, q, coeff, lam, any_xpbd, set);
                 });
    }
    padded_current_ = true;
    if (!keep_padded) unpad(p, parallel, config);
  }
}

template <class Real> void ColoredSolver<Real>::unpad(Real* p, bool parallel, const ParallelConfig& config) {
  if constexpr (std::is_same_v<Real, float>) {
    const float* q = padded_.data();
    run_range(0, num_particles_, parallel, config, partitioners_[unpad_slot_],
              [&](Index b, Index e) { detail::unpad_positions(q, b, e, p); });
  }
  padded_current_ = false;
}

template <class Real> void ColoredSolver<Real>::end_substep(Real* p, bool parallel, const ParallelConfig& config) {
  if (padded_current_) unpad(p, parallel, config);
}

template <class Real>
void ColoredSolver<Real>::project_volumes(const Real* p, Real* out, const Real* w,
                                          std::span<const SolveCoefficients<Real>> coeff, bool parallel,
                                          const ParallelConfig& config, std::size_t& part) {
  // Each volume constraint is its own color; its blocks are the parallel items (a block is kVolumeBlock rows, so
  // the inline threshold and grain are scaled down to blocks).
  const ParallelConfig blocks = detail::per_block(config, kVolumeBlock);
  const VolumeConstraints<Real>& v = colored_.volume;
  for (Index i = 0; i < Index(v.size()); ++i) {
    tbb::affinity_partitioner& ap = partitioners_[part++];
    auto run = [&](Index b, Index e, const auto& body) { run_range(b, e, parallel, blocks, ap, body); };
    detail::project_volume(v, i, p, out, w, coeff[v.items[i].set], volume_.target[i], lambda_.volume[i], volume_, run);
  }
}

template class ColoredSolver<float>;
template class ColoredSolver<double>;

}  // namespace pbd
