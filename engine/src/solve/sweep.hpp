#pragma once
// The sweep driver (private): every solver is a schedule × an update rule over the same projection functions.
//   schedule_walk.hpp    the order: insertion | colors | blocks (forward, or each type backwards)
//   update_rule.hpp      in place (Gauss-Seidel) | Jacobi (split masses, deltas applied after the types)
//   padded_positions.hpp the padded copy of the positions the SIMD kernels run on, and when it goes back to p
//   sweep_loops.hpp      the loops: a team of threads for the whole solve, or a fork per loop
//   kernel_table.hpp     each type's SIMD kernel (kernels.hpp), if it has one
// A sweep visits, in this order: under the block schedule the blocks' interiors; every constraint type through one
// loop (for_each_type: the built-in types in list order, then the user-defined ones in the order first added), each
// by its SIMD kernel when it has one this sub-step runs (colors schedule, in place; or the interiors and boundary of
// the only type, under the block schedule) or else by the generic projection; Jacobi's deltas; the volume
// constraints; then the sub-step's collisions and particle contacts. The volumes and the contacts are projected in
// place under every update rule (a volume is one constraint, parallel within itself, and contacts are inequalities
// whose friction reads the positions they leave), so every sweep ends with the volumes and then the contacts
// holding. The kernels give the generic projection's bits.
// What a sub-step runs is decided once, in begin() (SweepPlan): which types run a kernel, whether the padded copy is
// kept from sweep to sweep, whether the sweeps may run on a team. Nothing in a sweep changes it.
// Threads: Gauss-Seidel sweeps of the built-in types (no volume, no user type: those fork inside their loops) run
// all of a sub-step's sweeps on one team of threads (team.hpp: one fork/join per sub-step, a barrier per shared
// loop); otherwise each loop forks and joins (run_range).
#include "padded_positions.hpp"
#include "schedule_walk.hpp"
#include "update_rule.hpp"
#include "volume_projection.hpp"

#include <algorithm>
#include <cassert>
#include <vector>

namespace pbd::detail {

/// What a sub-step's sweeps run (Sweeper::begin decides it from the model, the solver and the CPU).
template <class Real> struct SweepPlan {
  std::vector<PaddedKernel<Real>> kernel;  ///< per type position: the kernel its constraints run by (empty: none)
  std::size_t interiors_kernel = ~std::size_t(0);  ///< block schedule: the type whose kernel runs the interiors
  std::size_t interior_items = 0;          ///< constraints in the blocks' interiors
  bool team = false;                       ///< the sweeps may run on a team
};

/// One sub-step's sweeps over a model: begin(), sweep() × iterations, end().
template <class Real> class Sweeper {
public:
  /// reverse: this sub-step sweeps each type backwards (SweepOrder::symmetric on an odd sub-step; not for Jacobi).
  /// keep: the positions may stay in the padded copy between sweeps when every type runs there (per_sweep: p holds
  /// them after every sweep, as Chebyshev acceleration needs).
  Sweeper(Model<Real>& model, State<Real>& state, Scratch<Real>& scratch, Schedule schedule, Update update,
          bool reverse, bool parallel, const ParallelConfig& config, Real omega = Real(1),
          typename PaddedPositions<Real>::Keep keep = PaddedPositions<Real>::Keep::substep)
      : m_(model), s_(state), k_(scratch), walk_(model, schedule, reverse && update == Update::in_place),
        update_(update, omega), loops_(model, scratch, parallel, schedule == Schedule::blocks, config),
        padded_(scratch, model.num_particles(), PaddedPositions<Real>::Keep::per_sweep), keep_(keep) {}

  /// Starts a sub-step at `time` (s): volume targets, λ reset (only if some λ may be non-zero), the update rule's
  /// counts, and the plan.
  void begin(double time) {
    k_.volume.set_targets(m_.volume.table, time);
    reset_lambda();
    update_.begin(m_, k_);
    plan_sweeps();
  }

  /// Whether the sweeps would run on a team (team.hpp), without changing anything: Gauss-Seidel in place with the
  /// built-in types and contacts only (user types may fork inside, volumes reduce with loops of their own), only when
  /// some loop is large enough to share, and under the block schedule only when the interiors are shared (else
  /// sharing the boundary alone moves its cache lines between the threads every sweep).
  bool team_possible() const {
    if (!loops_.parallel() || walk_.schedule() == Schedule::insertion || !update_.in_place() || !m_.user.empty() ||
        !m_.volume.table.empty() || tbb::this_task_arena::max_concurrency() <= 1)
      return false;
    const bool share = loops_.shares_interiors();
    if (walk_.schedule() == Schedule::blocks && !share) return false;
    std::size_t largest = share ? count_interior_items() : 0;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t) {
      for (Index c = type.num_blocks(); c < type.num_colors(); ++c)
        largest = std::max<std::size_t>(largest, type.color_begin(c + 1) - type.color_begin(c));
    });
    return largest >= SweepLoops<Real>::team_share_below(loops_.config());
  }
  /// The sweeps may run on a team (Team::run, then join() on each member's own copy of this sweeper).
  bool team_ready() const { return plan_.team; }
  /// Runs this sweeper's loops as `member` of a team (nullptr: on its own again).
  void join(Team::Member* member) { loops_.join(member); }
  /// Within a team, whether a loop over `n` items is shared.
  static std::size_t team_loop_share_below(const ParallelConfig& cfg, int members) {
    return SweepLoops<Real>::team_loop_share_below(cfg, members);
  }

  /// One sweep over every constraint, updating p (3 per particle).
  void sweep(Real* p) {
    loops_.start_sweep();
    padded_.start_sweep(loops_);
    const SolveCoefficients<Real>* coeff = k_.coeff.data();
    const Real* w = update_.masses(m_, k_);
    Real* out = update_.start_sweep(p, k_);
    if (walk_.schedule() == Schedule::blocks && update_.in_place()) project_interiors(p, w, coeff);
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) { project_type(type, t, p, w, coeff, out); });
    update_.finish_sweep(p, m_, k_, loops_);
    // Volumes and contacts, in place with the true masses whatever the update rule, so they have the last word.
    project_volumes(p);
    project_contacts(k_.collisions, k_.collision_lambda.data(), p);
    project_contacts(k_.particle_contacts, k_.particle_contact_lambda.data(), p);
    padded_.end_sweep(loops_, p);
  }

  /// Whether every sweep keeps the positions in the padded copy (scratch.padded, sized by begin()) from the first
  /// type to the end: a caller may then write that copy itself (adopt_padded) and read the result from it.
  bool stays_padded() const { return padded_.kept(); }
  /// The caller wrote every particle's predicted position and inverse mass into scratch.padded (stays_padded()):
  /// the sweeps start from it, and p is not read.
  void adopt_padded() { padded_.adopt(); }
  /// Whether the solved positions are in scratch.padded rather than p (until end() copies them back).
  bool padded() const { return padded_.current(); }
  /// Ends the sub-step's sweeps: p holds the solved positions afterwards.
  void end(Real* p) { padded_.to_p(loops_, p); }

private:
  // λ reset where some may be non-zero (or the arrays do not match the stores); the contacts' every sub-step.
  void reset_lambda() {
    bool sized = s_.volume_lambda.size() == m_.volume.table.size() && s_.lambda.size() == m_.num_types();
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) { sized = sized && s_.lambda[t].size() == type.num_lambdas(); });
#ifndef NDEBUG
    if (!s_.lambda_dirty && sized)  // debug builds: λ is zero wherever no sweep had α̃ ≠ 0 since the last reset
      for (const auto& l : s_.lambda) assert(std::ranges::all_of(l, [](Real x) { return x == Real(0); }));
#endif
    if (s_.lambda_dirty || !sized) {
      s_.lambda.resize(m_.num_types());
      for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) { s_.lambda[t].assign(type.num_lambdas(), Real(0)); });
      s_.volume_lambda.assign(m_.volume.table.size(), Real(0));
    }
    // Contacts' λ count the projections that moved them (collision.hpp, particle_contact.hpp): reset every sub-step.
    k_.collision_lambda.assign(k_.collisions.size(), Real(0));
    k_.particle_contact_lambda.assign(k_.particle_contacts.size(), Real(0));
    s_.lambda_dirty = std::ranges::any_of(k_.coeff, [](const auto& c) { return c.alpha_tilde != Real(0); });
  }

  // The plan (SweepPlan): the kernels run in place, under the colors schedule; under the block schedule only for
  // the interiors and boundary of a type that is the only one with constraints, with no user type and, when the
  // kernel's lanes run several blocks at once (chains), at least 4 blocks (with fewer they are not filled). The copy
  // is kept from sweep to sweep when every type with constraints runs a kernel and nothing else reads p (no user
  // type, volume or contact).
  void plan_sweeps() {
    const Schedule schedule = walk_.schedule();
    plan_.kernel.assign(m_.num_types(), PaddedKernel<Real>{});
    plan_.interiors_kernel = ~std::size_t(0);
    std::size_t nonempty = 0, only = 0;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) {
      if (!type.empty()) ++nonempty, only = t;
    });
    if (update_.in_place() && schedule == Schedule::colors) {
      for (std::size_t t = 0; t < plan_.kernel.size(); ++t) plan_.kernel[t] = padded_kernel<Real>(t);
    } else if (update_.in_place() && schedule == Schedule::blocks && m_.user.empty() && nonempty == 1 &&
               padded_kernel<Real>(only).interiors &&
               m_.num_blocks >= std::min<Index>(4, padded_kernel<Real>(only).chains)) {
      plan_.kernel[only] = padded_kernel<Real>(only);
      plan_.interiors_kernel = only;
    }
    bool all_padded = schedule != Schedule::insertion, any_padded = false;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) {
      const bool kernel = plan_.kernel[t].range != nullptr;
      all_padded = all_padded && (type.empty() || kernel);
      any_padded = any_padded || (!type.empty() && kernel);
    });
    const bool keep = all_padded && m_.user.empty() && m_.volume.table.empty() && k_.collisions.empty() &&
                      k_.particle_contacts.empty() && keep_ == PaddedPositions<Real>::Keep::substep;
    padded_ = PaddedPositions<Real>(k_, m_.num_particles(),
                                    keep ? PaddedPositions<Real>::Keep::substep : PaddedPositions<Real>::Keep::per_sweep);
    if (any_padded) k_.padded.resize(m_.num_particles());  // sized here, never by a team's members
    plan_.interior_items = count_interior_items();
    const std::size_t k = plan_.interiors_kernel;
    loops_.set_interiors(plan_.interior_items, k < plan_.kernel.size() ? plan_.kernel[k].chains : kInterleave);
    plan_.team = team_possible();
  }

  // Constraints in the blocks' interiors (block schedule; 0 otherwise).
  std::size_t count_interior_items() const {
    std::size_t n = 0;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t) {
      n += type.num_blocks() ? type.color_begin(type.num_blocks()) : 0;
    });
    return n;
  }

  // One type after the interiors: in insertion order, or its colors by its kernel or the generic projection.
  void project_type(const TypeStore<Real>& type, std::size_t t, Real* p, const Real* w,
                    const SolveCoefficients<Real>* coeff, Real* out) {
    if (type.empty()) return;
    Real* lam = s_.lambda[t].data();
    const Real relax = update_.relax();
    const Update update = update_.kind();
    assert(walk_.schedule() == Schedule::insertion || type.empty() ||
           (type.up_to_date() && type.color_begin(type.num_colors()) == Index(type.size())));
    if (walk_.schedule() == Schedule::insertion) {
      type.project_insertion(p, w, coeff, lam, out, relax, update, walk_.reverse());
      return;
    }
    const PaddedKernel<Real>& kernel = plan_.kernel[t];
    if (kernel.range) {
      Real* q = padded_.to_padded(loops_, p, m_.inverse_mass.data());
      const bool any_xpbd = s_.lambda_dirty;
      const std::vector<Index>* sets = t < m_.color_sets.size() ? &m_.color_sets[t] : nullptr;
      const bool sets_known = kernel.color_sets && sets && sets->size() == std::size_t(type.num_colors());
      walk_.colors(loops_, type, t, kernel.block, [&](Index c, Index b, Index e) {
        const Index set = sets_known ? (*sets)[c] : kMixedSets;
        kernel.range(type, b, e, q, coeff, lam, any_xpbd, set);
      });
      return;
    }
    padded_.to_p(loops_, p);  // the generic projection reads p
    walk_.colors(loops_, type, t, 1, [&](Index, Index b, Index e) {
      type.project_range(b, e, p, w, coeff, lam, out, relax, update);
    });
  }

  // The blocks' interiors (block schedule): one parallel loop over tasks of blocks; a task projects its blocks of
  // every type in types' order (or, when a kernel runs them, of the only type, on the padded copy). Blocks share no
  // movable particle, so the blocks run in any order and on any thread with the same bits.
  void project_interiors(Real* p, const Real* w, const SolveCoefficients<Real>* coeff) {
    const std::size_t k = plan_.interiors_kernel;
    const bool reverse = walk_.reverse();
    if (k < plan_.kernel.size()) {
      const TypeStore<Real>& type = type_at(k);
      if (type.num_blocks() == 0) return;
      Real* q = padded_.to_padded(loops_, p, m_.inverse_mass.data());
      Real* lam = s_.lambda[k].data();
      const bool any_xpbd = s_.lambda_dirty;
      walk_.interiors(loops_, [&](Index first, Index last) {
        plan_.kernel[k].interiors(type, first, last, q, coeff, lam, any_xpbd, reverse);
      });
      return;
    }
    walk_.interiors(loops_, [&](Index first, Index last) {
      for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) {
        if (type.num_blocks()) type.project_interiors(first, last, p, w, coeff, s_.lambda[t].data(), reverse);
      });
    });
  }

  const TypeStore<Real>& type_at(std::size_t k) const {
    const TypeStore<Real>* found = nullptr;
    for_each_type(m_, [&](const TypeStore<Real>& type, std::size_t t) {
      if (t == k) found = &type;
    });
    return *found;
  }

  // Volume constraints: in insertion order, or color by color (a color's volumes share no particle, so they run one
  // after the other with the same bits); each is projected with its fixed-shape parallel reduction (never on a team).
  void project_volumes(Real* p) {
    const auto& v = m_.volume;
    const ParallelConfig blocks = per_block(loops_.config(), kVolumeBlock);
    const Index n = Index(v.table.size());
    if (n) padded_.to_p(loops_, p);
    const std::size_t base = loops_.slots(std::size_t(n));
    const Real* w = m_.inverse_mass.data();
    auto one = [&](Index j) {
      const Index i = walk_.schedule() == Schedule::insertion ? j : v.order[j];
      tbb::affinity_partitioner& ap = k_.partitioners[base + j];
      auto run = [&](Index b, Index e, const auto& body) { run_range(b, e, loops_.parallel(), blocks, ap, body); };
      project_volume(v.table, i, p, p, w, k_.coeff[v.table.items[i].set], k_.volume.target[i], s_.volume_lambda[i],
                     k_.volume, run);
    };
    if (walk_.reverse()) {
      for (Index j = n; j-- > 0;) one(j);
    } else {
      for (Index j = 0; j < n; ++j) one(j);
    }
  }

  // This sub-step's collisions or particle contacts (not constraint types of the list: generated each sub-step),
  // in place with the true masses, in generation order or color by color (always forward).
  template <class C> void project_contacts(const Store<C>& st, Real* lam, Real* p) {
    const Real* w = m_.inverse_mass.data();
    const SolveCoefficients<Real>* coeff = k_.coeff.data();
    if (walk_.schedule() == Schedule::insertion) {
      project_in_insertion_order<true, false>(st, lam, p, w, coeff, Real(1), p);
      return;
    }
    if (!st.empty()) padded_.to_p(loops_, p);
    const Index colors = st.num_colors();
    const std::size_t base = loops_.slots(std::size_t(colors));
    for (Index c = 0; c < colors; ++c)
      loops_.range(st.offsets[c], st.offsets[c + 1], loops_.config(), base + std::size_t(c), [&](Index b, Index e) {
        project_stored_range<true>(st, b, e, lam, p, w, coeff, Real(1), p);
      });
  }

  Model<Real>& m_;
  State<Real>& s_;
  Scratch<Real>& k_;
  ScheduleWalk<Real> walk_;
  UpdateRule<Real> update_;
  SweepLoops<Real> loops_;
  PaddedPositions<Real> padded_;
  typename PaddedPositions<Real>::Keep keep_;  // what the caller allows (Chebyshev needs p after every sweep)
  SweepPlan<Real> plan_;
};

}  // namespace pbd::detail
