#pragma once
/// \file custom_constraints.hpp
/// User-defined fixed-arity constraint types: stored, colored and projected by the same store, coloring and sweep
/// driver as the built-in ones.
///
/// A host type C needs what the built-in types have (see constraints/stretch.hpp): `static constexpr int kArity`,
/// `static constexpr bool kInequality`, `static constexpr const char* kName`, `std::array<Index, kArity> particles`,
/// `Index set`, optionally `static constexpr bool kUnitGradients = true` when every |∇_i C| is 1, and a free function
/// `bool evaluate(const C&, const Vec3<Real> (&p)[kArity], Real& C, Vec3<Real> (&grad)[kArity])` found by
/// argument-dependent lookup (optionally also its own `correction`, as stretch has). Each type lives in a
/// detail::Store<C> like a built-in one; the only virtual call is one per color range (never per constraint), so a
/// user type runs the same tight, inlined loop as a built-in one and is just as deterministic.
#include "pbd/constraints/projection.hpp"
#include "pbd/detail/block_layout.hpp"
#include "pbd/detail/constraint_store.hpp"

#include <functional>
#include <memory>
#include <typeindex>
#include <vector>

namespace pbd {

/// The requirements on a user-defined constraint type C of precision Real (see the file comment).
template <class C, class Real>
concept UserConstraint = requires(const C& c, const Vec3<Real> (&p)[C::kArity], Real& value,
                                  Vec3<Real> (&grad)[C::kArity]) {
  { C::kArity } -> std::convertible_to<int>;
  { C::kInequality } -> std::convertible_to<bool>;
  { C::kName } -> std::convertible_to<const char*>;
  { c.set } -> std::convertible_to<Index>;
  { evaluate(c, p, value, grad) } -> std::convertible_to<bool>;
} && (C::kArity >= 1);

namespace detail {

/// One user-defined type's store behind a type-erased interface: what the coloring and the sweep driver need.
/// `lambda` is the type's λ array in stored order (kept in the world's State).
template <class Real> class UserStoreBase {
public:
  virtual ~UserStoreBase() = default;
  virtual std::unique_ptr<UserStoreBase> clone() const = 0;  ///< deep copy
  virtual std::type_index type() const = 0;                  ///< the host type C
  virtual const char* name() const = 0;                      ///< C::kName
  virtual std::size_t size() const = 0;                      ///< number of constraints
  virtual bool up_to_date() const = 0;                       ///< every constraint has a color
  virtual void color_all(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) = 0;  ///< colors all
  virtual bool color_tail(const std::vector<std::uint8_t>& fixed) = 0;  ///< colors the appended ones (false: all)
  /// Lays out every constraint for the block schedule (block_layout.hpp).
  virtual void lay_out_blocks(const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block,
                              Index blocks, const coloring::Options& o) = 0;
  virtual Index num_colors() const = 0;                                  ///< groups laid out (blocks and colors)
  virtual Index num_blocks() const = 0;                                  ///< leading groups that are block interiors
  virtual Index color_begin(Index c) const = 0;                          ///< first stored position of group c
  /// Adds 1 per constraint at each of its particles, for the constraints with user index ≥ first.
  virtual void count_particles(std::vector<Index>& count, Index first) const = 0;
  virtual std::size_t erase_touching(Index particle) = 0;  ///< removes every constraint on `particle`; how many
  /// Calls join(a, b) for each constraint and each of its particles b after its first a.
  virtual void join_particles(const std::function<void(Index, Index)>& join) const = 0;
  virtual void validate(const std::vector<std::uint8_t>& fixed) const = 0;  ///< Store::validate
  /// Every constraint in insertion order (or backwards), each projected into `out` (out = p: Gauss-Seidel; else
  /// Jacobi deltas, λ += relax·Δλ).
  virtual void project_insertion(const Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real* lambda,
                                 Real* out, Real relax, bool reverse) const = 0;
  /// Stored positions [b, e) (inside one group), each projected into `out`, in stored order or backwards.
  virtual void project_range(Index b, Index e, const Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                             Real* lambda, Real* out, Real relax, bool reverse) const = 0;
};

/// The store of host type C.
template <class C, class Real> class UserStore final : public UserStoreBase<Real> {
public:
  Store<C> store;  ///< the constraints

  std::unique_ptr<UserStoreBase<Real>> clone() const override { return std::make_unique<UserStore>(*this); }
  std::type_index type() const override { return typeid(C); }
  const char* name() const override { return C::kName; }
  std::size_t size() const override { return store.size(); }
  bool up_to_date() const override { return store.up_to_date(); }
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
  void count_particles(std::vector<Index>& count, Index first) const override {
    for (Index u = first; u < Index(store.size()); ++u)
      for (Index p : store.at(u).particles) ++count[p];
  }
  void join_particles(const std::function<void(Index, Index)>& join) const override {
    for (const C& c : store.items)
      for (int i = 1; i < C::kArity; ++i) join(c.particles[0], c.particles[i]);
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
  void validate(const std::vector<std::uint8_t>& fixed) const override { store.validate(fixed, C::kName); }
  void project_insertion(const Real* p, const Real* w, const SolveCoefficients<Real>* coeff, Real* lambda,
                         Real* out, Real relax, bool reverse) const override {
    const Index n = Index(store.size());
    for (Index k = 0; k < n; ++k) {
      const Index i = store.stored(reverse ? n - 1 - k : k);
      project_into(store.items[i], p, w, coeff[store.items[i].set], lambda[i], out, relax);
    }
  }
  void project_range(Index b, Index e, const Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                     Real* lambda, Real* out, Real relax, bool reverse) const override {
    if (reverse) {
      for (Index i = e; i-- > b;) project_into(store.items[i], p, w, coeff[store.items[i].set], lambda[i], out, relax);
    } else {
      for (Index i = b; i < e; ++i) project_into(store.items[i], p, w, coeff[store.items[i].set], lambda[i], out, relax);
    }
  }
};

/// All user-defined constraint types of a world, in the order they were first added (their sweep order); copying
/// deep-copies them.
template <class Real> class UserTypes {
public:
  UserTypes() = default;
  UserTypes(const UserTypes& o) { *this = o; }  ///< deep copy
  UserTypes& operator=(const UserTypes& o) {   ///< deep copy
    if (this != &o) {
      types_.clear();
      for (const auto& t : o.types_) types_.push_back(t->clone());
    }
    return *this;
  }
  UserTypes(UserTypes&&) noexcept = default;             ///< move
  UserTypes& operator=(UserTypes&&) noexcept = default;  ///< move

  /// The store of type C, created on first use.
  template <class C> Store<C>& of() {
    if (auto* s = find<C>()) return const_cast<Store<C>&>(*s);
    types_.push_back(std::make_unique<UserStore<C, Real>>());
    return static_cast<UserStore<C, Real>&>(*types_.back()).store;
  }
  /// The store of type C, or nullptr if none was added.
  template <class C> const Store<C>* find() const {
    for (const auto& t : types_)
      if (t->type() == typeid(C)) return &static_cast<const UserStore<C, Real>*>(t.get())->store;
    return nullptr;
  }
  /// Every type, in sweep order.
  const std::vector<std::unique_ptr<UserStoreBase<Real>>>& types() const { return types_; }
  bool empty() const { return types_.empty(); }  ///< true when the world has no user-defined constraints

private:
  std::vector<std::unique_ptr<UserStoreBase<Real>>> types_;
};

}  // namespace detail
}  // namespace pbd
