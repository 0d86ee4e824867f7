#pragma once
// The one sweep driver (private): every solver is a schedule × an update rule over the same projection functions.
//   schedule  insertion: every constraint in the order the user added it (the serial reference)
//             colors:    color after color; within a color no two constraints write the same movable particle, so a
//                        color's constraints run in parallel (tbb::parallel_for) or one after the other with the
//                        same bits
//             blocks:    the blocks' interiors first, in one parallel loop over the blocks: a task projects its
//                        block's constraints of every type (types in solver order, each in insertion order), and no
//                        two blocks share a movable particle, so any number of threads gives the same bits; then
//                        the constraints that cross blocks, color after color as above (block_layout.hpp)
//   update    in place:  Gauss-Seidel, each projection moves p at once
//             Jacobi:    the built-in and user-defined constraints all read the same p and add their corrections to
//                        a delta per particle, computed with split masses (Tonge et al. 2012): particle i, touched
//                        by n_i of them, enters each with inverse mass n_i·w_i, so that p += ω·delta / n_i after
//                        the sweep applies exactly w_i ∇C·(ω Δλ) per constraint and λ += ω Δλ tracks it (XPBD's λ
//                        then converges to Gauss-Seidel's, and every correction conserves momentum)
//   order     forward:   every sub-step visits each type in insertion or color order
//             symmetric: odd sub-steps visit each type backwards, colors reversed too (a color's constraints
//                        share no particle, so their own order never matters); a sub-step's number comes from the
//                        world's time (solver.hpp), so a copy of the world taken at any step sweeps the same way
// A sweep visits, in this order: the built-in types (constraint_types.hpp), the user-defined types (in the order
// first added), the volume constraints, then the sub-step's collisions and particle contacts. The volumes and the
// contacts are projected in place under every update (Jacobi after applying its deltas; the colored ones color by
// color): a volume is one constraint, parallel within itself, and contacts are inequalities whose friction reads
// the positions they leave; so every sweep ends with the volumes and then the contacts holding. The
// SIMD kernels on padded positions (x y z w per particle) are how the colors schedule projects stretch, bending and
// area colors in place (float: stretch_kernel.hpp, bending_kernel.hpp; double, and area in both, with AVX2:
// kernels_avx2.hpp); they give the scalar projection's bits. The positions are padded before the first such color and copied back before
// anything that reads p (another type, user types, volumes, contacts) and at the sub-step's end.
// Threads: Gauss-Seidel sweeps of the built-in types (no volume, no user type) run all of a sub-step's sweeps on one
// team of threads (team.hpp: one fork/join per sub-step, a barrier per shared loop; every loop gives the same bits
// however it is cut). Under the colors schedule each member takes, in every color, the constraints of its share of
// the particles (Model::particle_cuts); under the block schedule, the same blocks every sweep and, in each boundary
// color, the constraints filed under its blocks (block_layout.hpp sorts them so). Either way most cache lines stay
// with one thread. Otherwise each loop forks and joins (run_range).
#include "parallel_range.hpp"
#include "pbd/constraints/projection.hpp"
#include "scratch.hpp"
#include "bending_kernel.hpp"
#include "kernels_avx2.hpp"
#include "stretch_kernel.hpp"
#include "team.hpp"
#include "volume_projection.hpp"

#include <algorithm>
#include <cassert>

namespace pbd::detail {

enum class Schedule { insertion, colors, blocks };  // which order a sweep visits the constraints in

/// One sub-step's sweeps over a model: begin(), sweep() × iterations, end().
template <class Real> class Sweeper {
public:
  /// reverse: this sub-step sweeps each type backwards (SweepOrder::symmetric on an odd sub-step; not for Jacobi).
  Sweeper(Model<Real>& model, State<Real>& state, Scratch<Real>& scratch, Schedule schedule, Update update,
          bool reverse, bool parallel, const ParallelConfig& config)
      : m_(model), s_(state), k_(scratch), schedule_(schedule), update_(update),
        reverse_(reverse && update == Update::in_place), parallel_(parallel), config_(config) {}

  /// Starts a sub-step at `time` (s): volume targets, λ reset (only if some λ may be non-zero), Jacobi's counts and
  /// split masses.
  void begin(double time) {
    k_.volume.set_targets(m_.volume.table, time);
    const std::size_t collisions = k_.collisions.size();
    bool sized = s_.volume_lambda.size() == m_.volume.table.size() && s_.lambda.size() == m_.num_types();
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) { sized = sized && s_.lambda[t].size() == type.size(); });
#ifndef NDEBUG
    if (!s_.lambda_dirty && sized)  // debug builds: λ is zero wherever no sweep had α̃ ≠ 0 since the last reset
      for (const auto& l : s_.lambda) assert(std::ranges::all_of(l, [](Real x) { return x == Real(0); }));
#endif
    if (s_.lambda_dirty || !sized) {
      s_.lambda.resize(m_.num_types());
      for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) { s_.lambda[t].assign(type.size(), Real(0)); });
      s_.volume_lambda.assign(m_.volume.table.size(), Real(0));
    }
    // Contacts' λ count the projections that moved them (collision.hpp, particle_contact.hpp): reset every sub-step.
    k_.collision_lambda.assign(collisions, Real(0));
    k_.particle_contact_lambda.assign(k_.particle_contacts.size(), Real(0));
    s_.lambda_dirty = std::ranges::any_of(k_.coeff, [](const auto& c) { return c.alpha_tilde != Real(0); });
    if (update_ == Update::jacobi) {
      const Index n = m_.num_particles();
      const Real* w = m_.inverse_mass.data();
      k_.count_inv.resize(n);
      k_.split_w.resize(n);
      for (Index i = 0; i < n; ++i) {
        const Index c = m_.touch_count[i];
        k_.count_inv[i] = c ? Real(1) / Real(c) : Real(0);
        k_.split_w[i] = c ? w[i] * Real(c) : w[i];
      }
      k_.delta.resize(3 * std::size_t(n));
    }
    padded_ = false;
    // (with fewer blocks than the kernel's four lanes, they are not filled: scalar, without the padding)
    padded_blocks_ = std::is_same_v<Real, float> && kPaddedStretch && schedule_ == Schedule::blocks &&
                     update_ == Update::in_place && m_.user.empty() && m_.num_blocks >= 4;
    for_each_store(m_.stores, [&](const auto& st, auto i) { padded_blocks_ = padded_blocks_ && (i == 0 || st.empty()); });
    // Only types the SIMD kernels project on padded positions (padded_kernel): the positions may stay padded from
    // one sweep to the next.
    double_kernels_ = std::is_same_v<Real, double> && avx2_enabled();
    stay_padded_ = update_ == Update::in_place && schedule_ != Schedule::insertion;
    for_each_store(m_.stores, [&](const auto& st, auto) {
      using C = typename std::remove_cvref_t<decltype(st)>::value_type;
      stay_padded_ = stay_padded_ && (st.empty() || padded_kernel<C>());
    });
    stay_padded_ = stay_padded_ && m_.user.empty() && m_.volume.table.empty() && collisions == 0 &&
                   k_.particle_contacts.empty() && keep_padded;
    interior_items_ = count_interior_items();
    bool any_padded = false;  // sized here, never by a team's members
    for_each_store(m_.stores, [&](const auto& st, auto) {
      using C = typename std::remove_cvref_t<decltype(st)>::value_type;
      any_padded = any_padded || (!st.empty() && padded_kernel<C>());
    });
    if (any_padded) k_.padded.resize(m_.num_particles());
    share_interiors_ = shares_interiors();
    team_ready_ = team_possible();
  }

  /// Whether the sweeps would run on a team once begin() ran (team_ready()), without changing anything: a team
  /// (team.hpp) for Gauss-Seidel in place with the built-in types and contacts only (user types may fork inside,
  /// volumes reduce with loops of their own), only when some loop is large enough to share, and under the block
  /// schedule only when the interiors are shared (else sharing the boundary alone moves its cache lines between the
  /// threads every sweep: 0.78× on the 30² cloth's 3 blocks).
  bool team_possible() const {
    if (!parallel_ || schedule_ == Schedule::insertion || update_ != Update::in_place || !m_.user.empty() ||
        !m_.volume.table.empty() || tbb::this_task_arena::max_concurrency() <= 1)
      return false;
    const bool share = shares_interiors();
    if (schedule_ == Schedule::blocks && !share) return false;
    std::size_t largest = share ? count_interior_items() : 0;
    for_each_store(m_.stores, [&](const auto& st, auto) {
      for (Index c = st.sequential; c < st.num_colors(); ++c) largest = std::max<std::size_t>(largest, st.offsets[c + 1] - st.offsets[c]);
    });
    return largest >= team_share_below(config_);
  }

  /// The sweeps may run on a team (Team::run, then join() on each member's own copy of this sweeper).
  bool team_ready() const { return team_ready_; }
  /// Runs this sweeper's loops as `member` of a team (nullptr: on its own again).
  void join(Team::Member* member) { team_ = member; }
  /// A team forms only when some loop has at least this many items (ParallelConfig::inline_below, the loops a fork
  /// would take): sharing small loops moves their cache lines between the threads (the 30² cloth's colors, about
  /// 430 constraints, ran 0.65× on 2 threads).
  static std::size_t team_share_below(const ParallelConfig& cfg) { return std::max<std::size_t>(1, cfg.inline_below); }
  /// Within a team, a loop is shared when each member gets at least ParallelConfig::min_grain items (and always at
  /// team_share_below): a barrier costs about 0.3 µs here, while a color of 800 bending constraints run by member 0
  /// alone keeps the others waiting about 5 µs (the last two bending colors of the 100² cloth, every sweep).
  static std::size_t team_loop_share_below(const ParallelConfig& cfg, int members) {
    return std::max<std::size_t>(1, std::min(cfg.inline_below, cfg.min_grain * std::size_t(members)));
  }

  /// One sweep over every constraint, updating p (3 per particle).
  void sweep(Real* p) {
    if (update_ == Update::jacobi) sweep_with<false, false>(p);
    else if (reverse_) sweep_with<true, true>(p);
    else sweep_with<true, false>(p);
  }

  /// Whether every sweep keeps the positions in the padded copy (scratch.padded, sized by begin()) from the first
  /// type to the end: a caller may then write that copy itself (adopt_padded) and read the result from it.
  bool stays_padded() const { return stay_padded_ && k_.padded.size() == m_.num_particles(); }
  /// The caller wrote every particle's predicted position and inverse mass into scratch.padded (stays_padded()):
  /// the sweeps start from it, and p is not read.
  void adopt_padded() {
    assert(stays_padded());
    padded_ = true;
  }
  /// Whether the solved positions are in scratch.padded rather than p (until end() copies them back).
  bool padded() const { return padded_; }

  /// Ends the sub-step's sweeps: p holds the solved positions afterwards.
  void end(Real* p) {
    if (padded_) unpad(p);
  }

  // Constraints in the blocks' interiors (block schedule; 0 otherwise).
  std::size_t count_interior_items() const {
    std::size_t n = 0;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t) {
      n += type.num_blocks() ? type.color_begin(type.num_blocks()) : 0;
    });
    return n;
  }
  // The interiors are shared only with at least two blocks per thread (fewer, and the threads mostly trade cache
  // lines: 3 blocks of a 30² cloth ran 0.75× on 2 threads against 1).
  bool shares_interiors() const {
    const Index threads = Index(std::max(1, tbb::this_task_arena::max_concurrency()));
    return parallel_ && m_.num_blocks >= 2 * threads;
  }

  /// Whether constraints of type C are projected by a SIMD kernel on padded positions in this sub-step's sweeps:
  /// float stretch under the colors schedule or with padded blocks, float bending under the colors schedule,
  /// double stretch and bending under the colors schedule when the AVX2 kernels run, and area (float and double)
  /// under the colors schedule when the AVX2 kernels run (area_math.hpp).
  template <class C> bool padded_kernel() const {
    if (update_ != Update::in_place) return false;
    if constexpr (std::is_same_v<Real, float> && kPaddedStretch) {
      if constexpr (std::is_same_v<C, StretchConstraint<float>>) return schedule_ == Schedule::colors || padded_blocks_;
      if constexpr (std::is_same_v<C, BendingConstraint<float>>) return schedule_ == Schedule::colors;
    }
    if constexpr (std::is_same_v<C, StretchConstraint<double>> || std::is_same_v<C, BendingConstraint<double>>)
      return schedule_ == Schedule::colors && double_kernels_;
    if constexpr (std::is_same_v<C, AreaConstraint<Real>>) return schedule_ == Schedule::colors && avx2_enabled();
    return false;
  }

  /// Jacobi's over-relaxation factor ω.
  Real omega = 1;
  /// The SIMD kernels may leave the positions padded between sweeps when they project every type there is (false:
  /// p holds the positions after every sweep, as Chebyshev acceleration needs).
  bool keep_padded = true;

private:
  // kInPlace: Gauss-Seidel, every projection writes p itself (known at compile time, so the compiler knows the
  // writes and reads are of one array); otherwise Jacobi, the projections add to the deltas with split masses.
  // kReverse: each type's constraints backwards (the types keep their order).
  template <bool kInPlace, bool kReverse> void sweep_with(Real* p) {
    const Real* w = kInPlace ? m_.inverse_mass.data() : k_.split_w.data();
    const SolveCoefficients<Real>* coeff = k_.coeff.data();
    const Real relax = kInPlace ? Real(1) : omega;
    Real* out = p;
    if constexpr (!kInPlace) {
      std::fill(k_.delta.begin(), k_.delta.end(), Real(0));
      out = k_.delta.data();
    }
    part_ = 0;
    pad_slot_ = part_++;
    unpad_slot_ = part_++;
    if constexpr (kInPlace)
      if (schedule_ == Schedule::blocks && !padded_blocks_) project_interiors<kReverse>(p, w, coeff);
    auto store = [&](const auto& st, auto i) { project_store<kInPlace, kReverse>(st, s_.lambda[i].data(), p, w, coeff, relax, out); };
    for_each_store(m_.stores, store);
    project_user_types<kReverse>(p, w, coeff, relax, out);
    if constexpr (!kInPlace) apply_deltas(p);
    // Volumes and contacts, in place with the true masses whatever the update (each volume is one constraint,
    // parallel within itself; contacts color by color, their friction reading the positions they leave), so they
    // have the last word in every sweep.
    project_volumes<kReverse>(p, m_.inverse_mass.data(), p);
    project_store<true, false>(k_.collisions, k_.collision_lambda.data(), p, m_.inverse_mass.data(), coeff, Real(1), p);
    project_store<true, false>(k_.particle_contacts, k_.particle_contact_lambda.data(), p, m_.inverse_mass.data(), coeff,
                               Real(1), p);
    if (padded_ && !stay_padded_) unpad(p);
  }

  template <bool kReverse>
  void project_user_types(Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real relax, Real* out) {
    const std::size_t n = m_.user.types().size();
    if (n && padded_) unpad(p);
    for (std::size_t t = 0; t < n; ++t) {
      const auto& type = *m_.user.types()[t];
      Real* lam = s_.lambda[kNumBuiltinTypes + t].data();
      const Update update = out == p ? Update::in_place : Update::jacobi;
      if (schedule_ == Schedule::insertion) {
        type.project_insertion(p, w, coeff, lam, out, relax, update, kReverse);
      } else {
        const std::size_t base = part_;
        const Index first = type.num_blocks(), colors = type.num_colors() - first;  // blocks: projected before
        part_ += std::size_t(colors);
        for (Index j = 0; j < colors; ++j) {  // one virtual call per color range, never per constraint
          const Index c = kReverse ? colors - 1 - j : j;
          range(type.color_begin(first + c), type.color_begin(first + c + 1), config_, base + c,
                    [&](Index b, Index e) { type.project_range(b, e, p, w, coeff, lam, out, relax, update); });
        }
      }
    }
  }

  template <bool kInPlace, bool kReverse, class C>
  void project_store(const Store<C>& st, Real* lam, Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                     Real relax, Real* out) {
    if constexpr (kInPlace) {  // the same array, visibly so, and no relaxation
      out = p;
      relax = Real(1);
    }
    auto coeff_of = [&](const C& c) {
      if constexpr (requires { c.set; }) return coeff[c.set];
      else return SolveCoefficients<Real>{Real(1), Real(0)};  // collisions are hard
    };
    assert(schedule_ == Schedule::insertion || st.empty() || (st.up_to_date() && st.offsets.back() == st.size()));
    if (schedule_ == Schedule::insertion) {
      project_in_insertion_order<kInPlace, kReverse>(st, lam, p, w, coeff, relax, out);
      return;
    }
    if constexpr (kInPlace && std::is_same_v<C, StretchConstraint<Real>>) {
      if (padded_kernel<C>()) {  // padded_blocks_: the interiors too, stretch alone
        if (st.num_colors() > 0) project_stretch_padded_colors<kReverse>(st, lam, p, w, coeff);
        return;
      }
    }
    if constexpr (kInPlace && (std::is_same_v<C, BendingConstraint<Real>> || std::is_same_v<C, AreaConstraint<Real>>)) {
      if (padded_kernel<C>()) {
        if (st.num_colors() > 0) project_lanes_padded_colors<kReverse>(st, lam, p, w, coeff);
        return;
      }
    }
    if (padded_ && !st.empty()) unpad(p);  // the positions are needed in p
    // The colors (under the block schedule, the boundary colors after the blocks, whose interiors ran before).
    const std::size_t base = part_;
    const Index first = st.sequential, colors = st.num_colors() - first;
    part_ += std::size_t(colors);
    for (Index j = 0; j < colors; ++j) {
      const Index c = first + (kReverse ? colors - 1 - j : j);
      boundary_range(st, c, config_, base + c - first, [&](Index b, Index e) {
        for (Index i = b; i < e; ++i) project_into(st.items[i], p, w, coeff_of(st.items[i]), lam[i], out, relax);
      });
    }
  }

  // The blocks' interiors (Schedule::blocks): one parallel loop over the blocks; block b's task projects group b of
  // every built-in store, then of every user type, each in stored (insertion) order or backwards. Blocks share no
  // movable particle, so the blocks run in any order and on any thread with the same bits.
  template <bool kReverse> void project_interiors(Real* p, const Real* w, const SolveCoefficients<Real>* coeff) {
    const std::size_t slot = part_++;
    const Index blocks = m_.num_blocks, tasks = interior_tasks(blocks, kInterleave);
    auto task = [&](Index t) {  // blocks [first, last), interleaved
      const Index first = task_begin(t, tasks, blocks), last = task_begin(t + 1, tasks, blocks);
      for_each_store(m_.stores, [&](const auto& st, auto i) {
        if (st.sequential) project_interiors_interleaved<kReverse>(st, first, last, s_.lambda[i].data(), p, w, coeff);
      });
      for (std::size_t u = 0; u < m_.user.types().size(); ++u) {
        const auto& type = *m_.user.types()[u];
        if (type.num_blocks()) type.project_interiors(first, last, p, w, coeff, s_.lambda[kNumBuiltinTypes + u].data(), kReverse);
      }
    };
    run_interior_tasks(tasks, slot, task);
  }

  // How many tasks the interiors of `blocks` blocks run as, at most `cap` blocks each: a multiple of the threads
  // when there are blocks enough, so that every thread gets the same number of blocks (task_begin cuts them evenly).
  // The bits never depend on it: blocks share no movable particle, so how they are grouped and interleaved and on
  // which thread they run changes only the time.
  Index interior_tasks(Index blocks, Index cap) const {
    const Index threads = team_ ? Index(team_->size())
                          : share_interiors_ ? Index(std::max(1, tbb::this_task_arena::max_concurrency())) : 1;
    const Index tasks = threads * ((blocks + threads * cap - 1) / (threads * cap));
    return std::max<Index>(1, std::min(tasks, blocks));
  }
  // First block of task t of `tasks` over `blocks` blocks (contiguous runs whose sizes differ by at most one).
  static Index task_begin(Index t, Index tasks, Index blocks) {
    return Index(std::uint64_t(t) * blocks / tasks);
  }

  // The interiors' tasks [0, tasks): one parallel loop, one task per chunk (each task's blocks share no particle
  // with another's, so any cut gives the same bits), or inline when the interiors are small or one thread runs.
  template <class Task> void run_interior_tasks(Index tasks, std::size_t slot, const Task& task) {
    if (team_) {
      team_->loop(0, tasks, share_interiors_ && tasks > 1 && interior_items_ >= team_share_below(config_),
                  [&](std::size_t b, std::size_t e) {
                    for (std::size_t t = b; t < e; ++t) task(Index(t));
                  });
      return;
    }
    const bool fork = share_interiors_ && tasks > 1 && tbb::this_task_arena::max_concurrency() > 1 &&
                      interior_items_ >= config_.inline_below;
    if (!fork) {
      for (Index t = 0; t < tasks; ++t) task(t);
      return;
    }
    tbb::parallel_for(
        tbb::blocked_range<Index>(0, tasks, 1),
        [&](const tbb::blocked_range<Index>& r) {
          for (Index t = r.begin(); t < r.end(); ++t) task(t);
        },
        k_.partitioners[slot]);
  }

  // The blocks' stretch interiors on padded positions q (block schedule, stretch the only type, float): up to
  // kInterleavedChains blocks to a task, the kernel's four lanes on the k-th constraints of four blocks at a time
  // (project_stretch_interleaved, in groups of eight or four blocks; each block's constraints beyond the group's
  // shortest count, and blocks left over from the groups, go one by one, interleaved). The same bits as the scalar
  // interiors.
  template <bool kReverse>
  void project_stretch_interiors_padded(const Store<StretchConstraint<float>>& st, float* q, float* lam,
                                        const SolveCoefficients<float>* coeff, bool any_xpbd) {
    const std::size_t interior_slot = part_++;
    const StretchConstraint<float>* items = st.items.data();
    const Index blocks = st.sequential, tasks = interior_tasks(blocks, kInterleavedChains);
    auto task = [&](Index t) {
      const Index first = task_begin(t, tasks, blocks), last = task_begin(t + 1, tasks, blocks);
      Index begin[kInterleavedChains], len[kInterleavedChains];
      auto one = [&](Index i) { project_stretch_padded(items[i], q, coeff[items[i].set], lam[i]); };
      for (Index g = first; g < last;) {  // a group of 8 or 4 blocks (SIMD), or fewer (one by one)
        const Index left = last - g, m = left >= 8 ? 8 : left >= 4 ? 4 : left;
        Index common = ~Index(0), longest = 0;
        for (Index j = 0; j < m; ++j) {
          begin[j] = st.offsets[g + j];
          len[j] = st.offsets[g + j + 1] - begin[j];
          common = std::min(common, len[j]);
          longest = std::max(longest, len[j]);
        }
        if (m < 4) common = 0;
        if constexpr (kReverse) {
          for (Index j = 0; j < m; ++j)
            for (Index k = len[j]; k-- > common;) one(begin[j] + k);
          if (common) project_stretch_interleaved(items, begin, m, common, q, coeff, lam, any_xpbd, true);
        } else {
          if (common) project_stretch_interleaved(items, begin, m, common, q, coeff, lam, any_xpbd, false);
          for (Index k = common; k < longest; ++k)
            for (Index j = 0; j < m; ++j)
              if (k < len[j]) one(begin[j] + k);
        }
        g += m;
      }
    };
    run_interior_tasks(tasks, interior_slot, task);
  }

  // Every stretch color on padded positions (x y z w): one aligned load and store per particle in the kernel
  // instead of three of each plus w. Copied in unless the last sweep left them there, copied back unless stretch is
  // all the sweep projects (then end() copies them back). Partitioner slots are the same whichever copies run. In
  // the block layout (padded_blocks_) the blocks' interiors come first, then the boundary colors.
  template <bool kReverse, class C>
  void project_stretch_padded_colors(const Store<C>& st, Real* lam, Real* p, const Real* w,
                                     const SolveCoefficients<Real>* coeff) {
    if constexpr (std::is_same_v<Real, float>) {
      ensure_padded(p, w);
      float* q = k_.padded.data();
      const bool any_xpbd = s_.lambda_dirty;
      if (st.sequential) project_stretch_interiors_padded<kReverse>(st, q, lam, coeff, any_xpbd);
      const bool sets_known = m_.stretch_sets.size() == std::size_t(st.num_colors());
      const std::size_t base = part_;
      const Index first = st.sequential, colors = st.num_colors() - first;
      part_ += std::size_t(colors);
      for (Index j = 0; j < colors; ++j) {
        const Index c = first + (kReverse ? colors - 1 - j : j);
        const Index set = sets_known ? m_.stretch_sets[c] : kMixedSets;
        auto project = [&](Index b, Index e) { project_stretch_range(st.items.data(), b, e, q, coeff, lam, any_xpbd, set); };
        if (st.sequential) boundary_range(st, c, config_, base + c - first, project);
        else blocks_range(st.offsets[c], st.offsets[c + 1], kStretchBlock, config_, base + c - first, project, cuts_of(st, c));
      }
    } else {  // double (AVX2): the colors, four at a time
      ensure_padded(p, w);
      double* q = k_.padded.data();
      const bool any_xpbd = s_.lambda_dirty;
      const bool sets_known = m_.stretch_sets.size() == std::size_t(st.num_colors());
      const std::size_t base = part_;
      const Index colors = st.num_colors();
      part_ += std::size_t(colors);
      for (Index j = 0; j < colors; ++j) {
        const Index c = kReverse ? colors - 1 - j : j;
        const Index set = sets_known ? m_.stretch_sets[c] : kMixedSets;
        blocks_range(st.offsets[c], st.offsets[c + 1], kBendingBlock, config_, base + c, [&](Index b, Index e) {
          project_stretch_range_avx2(st.items.data(), b, e, q, coeff, lam, any_xpbd, set);
        }, cuts_of(st, c));
      }
    }
  }

  // Every bending or area color on padded positions (colors schedule), several constraints at a time
  // (bending_kernel.hpp, kernels_avx2.hpp); ranges cut at multiples of kBendingBlock from each color's start.
  template <bool kReverse, class C>
  void project_lanes_padded_colors(const Store<C>& st, Real* lam, Real* p, const Real* w,
                                   const SolveCoefficients<Real>* coeff) {
    ensure_padded(p, w);
    Real* q = k_.padded.data();
    const bool any_xpbd = s_.lambda_dirty;
    const std::size_t base = part_;
    const Index colors = st.num_colors();
    part_ += std::size_t(colors);
    for (Index j = 0; j < colors; ++j) {
      const Index c = kReverse ? colors - 1 - j : j;
      blocks_range(st.offsets[c], st.offsets[c + 1], kBendingBlock, config_, base + c,
                   [&](Index b, Index e) {
                     if constexpr (std::is_same_v<C, AreaConstraint<Real>>) project_area_range_avx2(st.items.data(), b, e, q, coeff, lam, any_xpbd);
                     else if constexpr (std::is_same_v<Real, float>) project_bending_range(st.items.data(), b, e, q, coeff, lam, any_xpbd);
                     else project_bending_range_avx2(st.items.data(), b, e, q, coeff, lam, any_xpbd);  // double: AVX2 only
                   }, cuts_of(st, c));
    }
  }

  // The padded copy (x y z w, k_.padded) of the positions p and inverse masses w, unless it is current.
  void ensure_padded(const Real* p, const Real* w) {
    if (padded_) return;
    assert(k_.padded.size() == m_.num_particles());  // sized by begin()
    Real* q = k_.padded.data();
    range(0, m_.num_particles(), config_, pad_slot_, [&](Index b, Index e) { pad_positions(p, w, b, e, q); });
    padded_ = true;
  }

  void unpad(Real* p) {
    const Real* q = k_.padded.data();
    range(0, m_.num_particles(), config_, unpad_slot_, [&](Index b, Index e) { unpad_positions(q, b, e, p); });
    padded_ = false;
  }

  // Volume constraints: in insertion order, or color by color (a color's volumes share no particle, so they run
  // one after the other with the same bits); each is projected with its fixed-shape parallel reduction.
  template <bool kReverse> void project_volumes(Real* p, const Real* w, Real* out) {
    const auto& v = m_.volume;
    const ParallelConfig blocks = per_block(config_, kVolumeBlock);
    const Index n = Index(v.table.size());
    if (n && padded_) unpad(p);
    const std::size_t base = part_;
    part_ += std::size_t(n);
    auto one = [&](Index j) {
      const Index i = schedule_ == Schedule::insertion ? j : v.order[j];
      tbb::affinity_partitioner& ap = k_.partitioners[base + j];  // never on a team (begin())
      auto run = [&](Index b, Index e, const auto& body) { run_range(b, e, parallel_, blocks, ap, body); };
      project_volume(v.table, i, p, out, w, k_.coeff[v.table.items[i].set], k_.volume.target[i], s_.volume_lambda[i],
                     k_.volume, run);
    };
    if constexpr (kReverse) {
      for (Index j = n; j-- > 0;) one(j);
    } else {
      for (Index j = 0; j < n; ++j) one(j);
    }
  }

  void apply_deltas(Real* p) {
    const Real* delta = k_.delta.data();
    const Real* count_inv = k_.count_inv.data();
    range(0, m_.num_particles(), config_, part_++, [&](Index b, Index e) {
      for (Index i = b; i < e; ++i) {
        const Real s = omega * count_inv[i];
        for (int d = 0; d < 3; ++d) p[3 * std::size_t(i) + d] += s * delta[3 * std::size_t(i) + d];
      }
    });
  }

  Model<Real>& m_;
  State<Real>& s_;
  Scratch<Real>& k_;
  Schedule schedule_;
  Update update_;
  bool reverse_;                // this sub-step's sweeps run backwards
  bool parallel_;
  const ParallelConfig& config_;
  std::size_t part_ = 0;        // next partitioner slot of this sweep
  std::size_t pad_slot_ = 0;    // partitioner slot of the copy into k_.padded (every sweep reserves it)
  std::size_t unpad_slot_ = 0;  // partitioner slot of the copy back (every sweep reserves it)
  bool stay_padded_ = false;    // every type a sweep projects runs on padded positions: they stay between sweeps
  bool double_kernels_ = false; // double, and the AVX2 kernels run: stretch and bending colors on padded positions
  bool padded_ = false;         // k_.padded holds the positions and p is stale (until end())
  std::size_t interior_items_ = 0;  // constraints in the blocks' interiors (block schedule): decides the fork
  bool padded_blocks_ = false;      // block schedule, float, stretch the only type: on padded positions (SIMD)
  bool team_ready_ = false;         // the sweeps may run on a team
  bool share_interiors_ = false;    // the blocks' interiors run on more than one thread (at least two blocks each)
  Team::Member* team_ = nullptr;    // the team this copy of the sweeper runs in (nullptr: forks per loop)

  // Every parallel loop of the sweeps: on the team when there is one (its inline threshold), else run_range with
  // the affinity partitioner of `slot` (a cache hint for loops that fork; a team's members never touch the pool,
  // which grows on first use).
  template <class Body>
  void range(Index begin, Index end, const ParallelConfig& cfg, std::size_t slot, const Body& body) {
    if (team_) {
      team_->loop(begin, end, parallel_ && std::size_t(end - begin) >= team_loop_share_below(cfg, team_->size()),
                  [&](std::size_t b, std::size_t e) { body(Index(b), Index(e)); });
      return;
    }
    run_range(begin, end, parallel_, cfg, k_.partitioners[slot], body);
  }
  // Group c of `st`: under the block schedule on a team, each member takes the constraints filed under its own
  // blocks (those of its interior tasks; block_layout.hpp sorts each boundary color by block), so a particle's
  // cache line mostly stays with the thread that projected its block's interior; otherwise range().
  template <class C, class Body>
  void boundary_range(const Store<C>& st, Index c, const ParallelConfig& cfg, std::size_t slot, const Body& body) {
    const Index begin = st.offsets[c], end = st.offsets[c + 1];
    if (team_ && schedule_ == Schedule::colors) return blocks_range(begin, end, 1, cfg, slot, body, cuts_of(st, c));
    if (!team_ || schedule_ != Schedule::blocks || !share_interiors_ || st.sequential == 0)
      return range(begin, end, cfg, slot, body);
    const Index members = Index(team_->size()), blocks = m_.num_blocks;
    const Index tasks = interior_tasks(blocks, padded_blocks_ ? kInterleavedChains : kInterleave);
    const std::span<const std::uint32_t> block(m_.block);
    auto start = [&](int r) -> std::size_t {  // first constraint filed under member r's first block
      const std::uint32_t first = std::uint32_t(task_begin(Index(std::uint64_t(tasks) * Index(r) / members), tasks, blocks));
      const C* it = std::partition_point(st.items.data() + begin, st.items.data() + end, [&](const C& x) {
        return first_block(x, m_.fixed, block) < first;
      });
      return std::size_t(it - st.items.data());
    };
    team_->loop_parts(begin, end, interior_items_ >= team_share_below(config_), start,
                      [&](std::size_t b, std::size_t e) { body(Index(b), Index(e)); });
  }
  // range() over [begin, end) cut only at multiples of `block` from begin (the inline threshold and grain still
  // count items). With a color's particle cuts (cuts_of) on a team, member r starts near cut ⌊r·kCutParts/members⌉:
  // where the color's constraints reach member r's share of the particles, so that each thread projects the same
  // particles' constraints in every color and their cache lines stay with it (cut at half the count instead, each
  // color splits the cloth at another row; on the 100² cloth the cut moved by about 11,000 particles a sweep).
  template <class Body>
  void blocks_range(Index begin, Index end, Index block, const ParallelConfig& cfg, std::size_t slot,
                    const Body& body, const Index* cuts = nullptr) {
    const Index n = (end - begin + block - 1) / block;
    const ParallelConfig per = per_block(cfg, block);
    auto blocks = [&](std::size_t b, std::size_t e) { body(begin + Index(b) * block, std::min(end, begin + Index(e) * block)); };
    if (cuts && team_ && team_->size() > 1 && std::size_t(n) >= team_loop_share_below(per, team_->size())) {
      const std::size_t members = std::size_t(team_->size());
      auto start = [&](int r) -> std::size_t {
        const std::size_t j = (std::size_t(r) * kCutParts + members / 2) / members;
        return (std::size_t(cuts[j]) + std::size_t(block) / 2) / std::size_t(block);
      };
      team_->loop_parts(0, n, parallel_, start, blocks);
      return;
    }
    range(0, n, per, slot, [&](Index b, Index e) { blocks(b, e); });
  }
  // Color c's particle cuts (Model::particle_cuts) when `st` is a built-in store laid out in colors, else nullptr.
  template <class C> const Index* cuts_of(const Store<C>& st, Index c) const {
    if constexpr (!is_builtin_v<C, Real>) {
      return nullptr;
    } else {
      const auto& cuts = m_.particle_cuts[TypeIndex<C, BuiltinConstraintTypes<Real>>::value];
      if (&st != &m_.template store<C>() || cuts.size() != std::size_t(st.num_colors()) * (kCutParts + 1)) return nullptr;
      return cuts.data() + std::size_t(c) * (kCutParts + 1);
    }
  }
};

}  // namespace pbd::detail
