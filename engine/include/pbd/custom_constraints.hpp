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
/// detail::TypedStore<C> like a built-in one (detail/type_store.hpp), and every pass visits it through the same
/// interface, after the built-in types; the only virtual call is one per type or color range (never per
/// constraint), so a user type runs the same tight, inlined loop as a built-in one and is just as deterministic.
#include "pbd/detail/type_store.hpp"

#include <memory>
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
    types_.push_back(std::make_unique<TypedStore<C, Real, true>>());
    return static_cast<TypedStore<C, Real, true>&>(*types_.back()).store;
  }
  /// The store of type C, or nullptr if none was added.
  template <class C> const Store<C>* find() const {
    for (const auto& t : types_)
      if (t->type() == typeid(C)) return &static_cast<const TypedStore<C, Real, true>*>(t.get())->store;
    return nullptr;
  }
  /// Every type, in sweep order.
  const std::vector<std::unique_ptr<TypeStore<Real>>>& types() const { return types_; }
  bool empty() const { return types_.empty(); }  ///< true when the world has no user-defined constraints

private:
  std::vector<std::unique_ptr<TypeStore<Real>>> types_;
};

}  // namespace detail
}  // namespace pbd
