#pragma once
/// \file detail/type_store.hpp
/// One constraint type's store behind the interface every pass over the types uses (engine internals). The built-in
/// types (constraint_types.hpp) and the user-defined ones (custom_constraints.hpp) are both a TypedStore<C, Real>:
/// the built-in ones sit in Model::stores (a tuple, for typed access), the user-defined ones in Model::user, and
/// for_each_type (model.hpp) visits them all through this interface, in sweep order. Each virtual call covers a
/// whole type or one range of a group (a color, or a block's interior), never one constraint: the loops below are
/// instantiated per type, with the projection inlined into them, so a user type runs the same loop as a built-in
/// one. The SIMD kernels of the built-in types are chosen beside this interface (engine/src/solve/kernels.hpp).
#include "pbd/constraints/projection.hpp"
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/block_layout.hpp"
#include "pbd/detail/constraint_store.hpp"

#include <pbd/graph_coloring/stats.hpp>
#include <pbd/graph_coloring/validate.hpp>

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <typeindex>
#include <vector>

namespace pbd::detail {

/// λ values per constraint of type C (multipliers(), traits.hpp): its λ are lam[kMul<C>·i ...].
template <class C> inline constexpr Index kMul = Index(multipliers<C>());

/// The coefficients of constraint c: its set's, or those of a hard constraint when C has no set (collisions).
template <class C, class Real>
[[gnu::always_inline]] inline SolveCoefficients<Real> coefficients_of(const C& c, const SolveCoefficients<Real>* coeff) {
  if constexpr (requires { c.set; }) return coeff[c.set];
  else return SolveCoefficients<Real>{Real(1), Real(0)};
}

/// Every constraint of `st` in insertion order (kReverse: backwards), each projected into `out`. kInPlace: out is p
/// (Gauss-Seidel) and relax is 1, and the compiler sees both (else Jacobi: out holds deltas, λ += relax·Δλ).
template <bool kInPlace, bool kReverse, class C, class Real>
[[gnu::noinline]] void project_in_insertion_order(const Store<C>& st, Real* lam, Real* p, const Real* w,
                                                  const SolveCoefficients<Real>* coeff, Real relax, Real* out) {
  if constexpr (kInPlace) {
    out = p;
    relax = Real(1);
  }
  const Index n = Index(st.size());
  auto one = [&](Index i) { project_into(st.items[i], p, w, coefficients_of(st.items[i], coeff), lam[kMul<C> * i], out, relax); };
  if (st.slot.empty()) {  // never colored: stored order is insertion order
    if constexpr (kReverse) {
      for (Index i = n; i-- > 0;) one(i);
    } else {
      for (Index i = 0; i < n; ++i) one(i);
    }
  } else {
    if constexpr (kReverse) {
      for (Index u = n; u-- > 0;) one(st.slot[u]);
    } else {
      for (Index i : st.slot) one(i);
    }
  }
}

/// Stored positions [b, e) of `st` (inside one color: no two share a movable particle, so their order changes no
/// bit), each projected into `out` as project_in_insertion_order does.
template <bool kInPlace, class C, class Real>
[[gnu::noinline]] void project_stored_range(const Store<C>& st, Index b, Index e, Real* lam, Real* p, const Real* w,
                                            const SolveCoefficients<Real>* coeff, Real relax, Real* out) {
  if constexpr (kInPlace) {
    out = p;
    relax = Real(1);
  }
  for (Index i = b; i < e; ++i)
    project_into(st.items[i], p, w, coefficients_of(st.items[i], coeff), lam[kMul<C> * i], out, relax);
}

/// Blocks handled by one task of the block schedule's scalar interiors: they are projected interleaved, the k-th
/// constraint of each in turn, so that the processor overlaps independent dependency chains (a block's own
/// constraints mostly share particles with their predecessors, so one block alone waits on every square root).
/// Blocks share no movable particle, so interleaving them gives the bits of one block after the other.
inline constexpr Index kInterleave = 4;

/// Block interiors [first, last) of `st` (at most kInterleave), each in stored (insertion) order (kReverse:
/// backwards), interleaved, projected in place.
template <bool kReverse, class C, class Real>
[[gnu::noinline]] void project_interiors_interleaved(const Store<C>& st, Index first, Index last, Real* lam, Real* p,
                                                     const Real* w, const SolveCoefficients<Real>* coeff) {
  const C* items = st.items.data();
  const Index m = last - first;
  Index begin[kInterleave], len[kInterleave];
  Index common = ~Index(0);
  for (Index j = 0; j < m; ++j) {
    begin[j] = st.offsets[first + j];
    len[j] = st.offsets[first + j + 1] - begin[j];
    common = std::min(common, len[j]);
  }
  auto one = [&](Index i) { project_into(items[i], p, w, coeff[items[i].set], lam[kMul<C> * i], p, Real(1)); };
  if constexpr (kReverse) {  // each block backwards: its tail beyond the common length first, then interleaved
    for (Index j = 0; j < m; ++j)
      for (Index k = len[j]; k-- > common;) one(begin[j] + k);
    for (Index k = common; k-- > 0;)
      for (Index j = 0; j < m; ++j) one(begin[j] + k);
  } else {
    for (Index k = 0; k < common; ++k)
      for (Index j = 0; j < m; ++j) one(begin[j] + k);
    for (Index j = 0; j < m; ++j)
      for (Index k = common; k < len[j]; ++k) one(begin[j] + k);
  }
}

/// Calls run(b, e) for each run [b, e) of the colored interiors of blocks [first, last) of `st` (block_layout.hpp),
/// block after block, each block's runs in order (backwards when reverse: a run's constraints share no movable
/// particle, so only the runs' order counts).
template <class C, class F> void for_each_run(const Store<C>& st, Index first, Index last, bool reverse, const F& run) {
  for (Index block = first; block < last; ++block) {
    const Index r0 = st.block_runs[block], r1 = st.block_runs[block + 1];
    for (Index j = 0; j < r1 - r0; ++j) {
      const Index k = reverse ? r1 - 1 - j : r0 + j;
      run(st.runs[k], st.runs[k + 1]);
    }
  }
}

/// How a sweep writes a projection: in place (Gauss-Seidel) or into per-particle deltas (Jacobi, split masses).
enum class Update { in_place, jacobi };

/// One constraint type's store, as every pass over the types sees it (the file comment). `lambda` is the type's λ
/// array in stored order (State::lambda[t], t the type's position in for_each_type).
template <class Real> class TypeStore {
public:
  virtual ~TypeStore() = default;
  virtual std::unique_ptr<TypeStore> clone() const = 0;  ///< deep copy
  virtual std::type_index type() const = 0;              ///< the constraint type C
  virtual const char* name() const = 0;                  ///< C::kName
  virtual std::size_t size() const = 0;                  ///< number of constraints
  virtual std::size_t num_lambdas() const = 0;           ///< λ values: size() × the type's multipliers()
  bool empty() const { return size() == 0; }             ///< true when there are none
  virtual bool up_to_date() const = 0;                   ///< every constraint has a group
  virtual Index first_uncolored() const = 0;             ///< user index of the first constraint without a group

  // ---- layout (schedule.cpp) ----
  virtual void color_all(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) = 0;  ///< colors all
  virtual bool color_tail(const std::vector<std::uint8_t>& fixed) = 0;  ///< colors the appended ones (false: all)
  /// Lays out every constraint for the block schedule (block_layout.hpp).
  virtual void lay_out_blocks(const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block,
                              Index blocks, const coloring::Options& o) = 0;
  virtual Index num_colors() const = 0;                 ///< groups laid out (blocks and colors)
  virtual Index num_blocks() const = 0;                 ///< leading groups that are block interiors
  virtual Index color_begin(Index c) const = 0;         ///< first stored position of group c
  /// Every group's first stored position, and the end: group c is [groups()[c], groups()[c + 1]) (empty: none).
  virtual std::span<const Index> groups() const = 0;
  virtual Index tail_color() const = 0;                 ///< first tail color (Store::kNoTail: none)
  /// Adds 1 per constraint at each of its particles, for the constraints with user index ≥ first.
  virtual void count_particles(std::vector<Index>& count, Index first) const = 0;
  /// Calls join(a, b) for each constraint and each of its particles b after its first a.
  virtual void join_particles(const std::function<void(Index, Index)>& join) const = 0;
  /// Sets held[p] for each particle a constraint of a type that ties particles to the world holds (ties_to_world).
  virtual void mark_held(std::vector<std::uint8_t>& held) const = 0;
  /// Appends this type's items to the graph the block partition cuts (schedule.cpp): a built-in constraint as one
  /// item on all its particles, a user-defined one as one item per pair (its first particle and each other one),
  /// as each has always been given (the blocks, so the block solver's bits, depend on it). Returns the constraints.
  virtual std::size_t add_to_partition_graph(ConstraintGraph& g) const = 0;
  /// Per group c ≥ first: the set all its constraints share, or `mixed` (sets[c]; sets is resized to num_colors()).
  virtual void note_color_sets(std::vector<Index>& sets, Index first, Index mixed) const = 0;
  /// Per color, kCuts + 1 counts (model.hpp: Model::particle_cuts) of the constraints whose smallest particle is
  /// below ⌊j·n / kCuts⌋; `cuts` is cleared first.
  virtual void note_particle_cuts(std::vector<Index>& cuts, Index n, Index kCuts) const = 0;
  /// Within stored positions [b, e) of one boundary color (sorted by first_block, block_layout.hpp): the first
  /// position whose first block is not below `first`.
  virtual Index boundary_start(Index b, Index e, std::uint32_t first, const std::vector<std::uint8_t>& fixed,
                               std::span<const std::uint32_t> block) const = 0;

  // ---- editing and checking (edit.cpp) ----
  virtual std::size_t erase_touching(Index particle) = 0;  ///< removes every constraint on `particle`; how many
  /// Store::validate, and every particle index below n.
  virtual void validate(const std::vector<std::uint8_t>& fixed, Index n) const = 0;
  /// Colors the constraints anew with `options` (the world's colors untouched), checks the coloring, and returns its
  /// statistics (World::color_statistics).
  virtual coloring::Stats color_statistics(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) const = 0;

  // ---- projection (the sweeps) ----
  /// Every constraint in insertion order (or backwards), each projected into `out` (out = p: Gauss-Seidel; else
  /// Jacobi deltas, λ += relax·Δλ).
  virtual void project_insertion(Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real* lambda,
                                 Real* out, Real relax, Update update, bool reverse) const = 0;
  /// Stored positions [b, e) (inside one color), each projected into `out`.
  virtual void project_range(Index b, Index e, Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                             Real* lambda, Real* out, Real relax, Update update) const = 0;
  /// Block interiors [first, last) (at most kInterleave), in place: interleaved, or block after block and run after
  /// run for a type with colored interiors (backwards when reverse: each interior, or each block's runs).
  virtual void project_interiors(Index first, Index last, Real* p, const Real* w,
                                 const SolveCoefficients<Real>* coeff, Real* lambda, bool reverse) const = 0;
};

/// The store of constraint type C (built in, or user-defined: kUser).
template <class C, class Real, bool kUser> class TypedStore final : public TypeStore<Real> {
public:
  Store<C> store;  ///< the constraints

  std::unique_ptr<TypeStore<Real>> clone() const override { return std::make_unique<TypedStore>(*this); }
  std::type_index type() const override { return typeid(C); }
  const char* name() const override { return C::kName; }
  std::size_t size() const override { return store.size(); }
  std::size_t num_lambdas() const override { return std::size_t(kMul<C>) * store.size(); }
  bool up_to_date() const override { return store.up_to_date(); }
  Index first_uncolored() const override { return Index(store.color.size()); }

  void color_all(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) override {
    detail::color_all(store, fixed, o);
  }
  bool color_tail(const std::vector<std::uint8_t>& fixed) override { return detail::color_tail(store, fixed); }
  void lay_out_blocks(const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block, Index blocks,
                      const coloring::Options& o) override {
    detail::lay_out_blocks(store, fixed, block, blocks, o);
  }
  Index num_colors() const override { return store.num_colors(); }
  Index num_blocks() const override { return store.sequential; }
  Index color_begin(Index c) const override { return store.offsets[c]; }
  std::span<const Index> groups() const override { return store.offsets; }
  Index tail_color() const override { return store.tail_color; }
  void count_particles(std::vector<Index>& count, Index first) const override {
    for (Index u = first; u < Index(store.size()); ++u)
      for (Index p : store.at(u).particles) ++count[p];
  }
  void join_particles(const std::function<void(Index, Index)>& join) const override {
    for (const C& c : store.items)
      for (int i = 1; i < C::kArity; ++i) join(c.particles[0], c.particles[i]);
  }
  void mark_held(std::vector<std::uint8_t>& held) const override {
    if constexpr (ties_to_world<C>())
      for (const C& c : store.items)
        for (Index p : c.particles) held[p] = 1;
  }

  std::size_t add_to_partition_graph(ConstraintGraph& g) const override {
    for (const C& c : store.items) {
      if constexpr (kUser) {
        for (int i = 1; i < C::kArity; ++i) {
          g.nodes.push_back(c.particles[0]);
          g.nodes.push_back(c.particles[i]);
          g.offsets.push_back(std::uint32_t(g.nodes.size()));
        }
      } else {
        for (Index p : c.particles) g.nodes.push_back(p);
        g.offsets.push_back(std::uint32_t(g.nodes.size()));
      }
    }
    return store.size();
  }
  void note_color_sets(std::vector<Index>& sets, Index first, Index mixed) const override {
    sets.resize(store.num_colors(), mixed);
    for (Index c = first; c < store.num_colors(); ++c) {
      const auto b = store.items.begin() + store.offsets[c], e = store.items.begin() + store.offsets[c + 1];
      const bool one = b != e && std::all_of(b, e, [&](const C& x) { return x.set == b->set; });
      sets[c] = one ? b->set : mixed;
    }
  }
  void note_particle_cuts(std::vector<Index>& cuts, Index n, Index kCuts) const override {
    cuts.clear();
    if (store.empty() || !store.up_to_date()) return;
    const Index per = kCuts + 1;
    cuts.assign(std::size_t(store.num_colors()) * per, 0);
    for (Index c = 0; c < store.num_colors(); ++c) {
      Index* row = cuts.data() + std::size_t(c) * per;
      for (Index k = store.offsets[c]; k < store.offsets[c + 1]; ++k) {
        Index lo = ~Index(0);
        for (Index q : store.items[k].particles) lo = std::min(lo, q);
        // counted from the smallest j with lo < ⌊j·n / kCuts⌋ on (j ≤ kCuts: ⌊kCuts·n / kCuts⌋ = n)
        Index j = Index(std::uint64_t(lo) * kCuts / n);
        while (std::uint64_t(j) * n / kCuts <= lo) ++j;
        ++row[j];
      }
      for (Index j = 1; j <= kCuts; ++j) row[j] += row[j - 1];
    }
  }
  Index boundary_start(Index b, Index e, std::uint32_t first, const std::vector<std::uint8_t>& fixed,
                       std::span<const std::uint32_t> block) const override {
    const C* it = std::partition_point(store.items.data() + b, store.items.data() + e,
                                       [&](const C& x) { return first_block(x, fixed, block) < first; });
    return Index(it - store.items.data());
  }

  std::size_t erase_touching(Index particle) override {
    std::vector<std::uint8_t> drop(store.size(), 0);
    std::size_t n = 0;
    for (Index u = 0; u < Index(store.size()); ++u)
      for (Index p : store.at(u).particles)
        if (p == particle) {
          drop[u] = 1;
          ++n;
          break;
        }
    if (n) {
      detail::erase(store, drop);
      store.uncolor();  // the world recolors everything after removing a particle
    }
    return n;
  }
  void validate(const std::vector<std::uint8_t>& fixed, Index n) const override {
    for (std::size_t i = 0; i < store.items.size(); ++i)
      for (Index p : store.items[i].particles)
        if (p >= n)
          throw Error(std::string("validate: ") + C::kName + " constraint at " + std::to_string(i) + ": particle " +
                      std::to_string(p) + " out of range");
    store.validate(fixed, C::kName);
    if (!store.color.empty() && store.color.size() > store.size())
      throw Error(std::string("validate: ") + C::kName + " store: more colors than constraints");
  }
  coloring::Stats color_statistics(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) const override {
    const std::vector<C> items = store.in_insertion_order();
    const ConstraintGraph g = constraint_graph(std::span<const C>(items), fixed);
    const coloring::Coloring c = coloring::color(g.view(), o);
    if (auto error = coloring::find_coloring_error(g.view(), c))
      throw Error(std::string("color_statistics: improper coloring of ") + C::kName + " constraints: " + *error);
    return coloring::compute_stats(g.view(), c);
  }

  void project_insertion(Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real* lambda, Real* out,
                         Real relax, Update update, bool reverse) const override {
    if (update == Update::in_place) {
      if (reverse) project_in_insertion_order<true, true>(store, lambda, p, w, coeff, relax, out);
      else project_in_insertion_order<true, false>(store, lambda, p, w, coeff, relax, out);
    } else {
      if (reverse) project_in_insertion_order<false, true>(store, lambda, p, w, coeff, relax, out);
      else project_in_insertion_order<false, false>(store, lambda, p, w, coeff, relax, out);
    }
  }
  void project_range(Index b, Index e, Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real* lambda,
                     Real* out, Real relax, Update update) const override {
    if (update == Update::in_place) project_stored_range<true>(store, b, e, lambda, p, w, coeff, relax, out);
    else project_stored_range<false>(store, b, e, lambda, p, w, coeff, relax, out);
  }
  void project_interiors(Index first, Index last, Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                         Real* lambda, bool reverse) const override {
    if constexpr (colored_interiors<C>()) {
      for_each_run(store, first, last, reverse, [&](Index b, Index e) {
        project_stored_range<true>(store, b, e, lambda, p, w, coeff, Real(1), p);
      });
    } else if (reverse) {
      project_interiors_interleaved<true>(store, first, last, lambda, p, w, coeff);
    } else {
      project_interiors_interleaved<false>(store, first, last, lambda, p, w, coeff);
    }
  }
};

}  // namespace pbd::detail
