#pragma once
/// \file constraint_types.hpp
/// THE list of built-in fixed-arity constraint types, in solver order. Every pass over the constraints folds over
/// this list: storage, coloring, sweeps, λ, Jacobi counts, removal and validate() (World), the input checks
/// (checks.hpp), the metrics with their units (metrics.hpp), and outside the engine the scene keys and their checks,
/// scene sizes, world descriptions and the describe round trip (pbd::io), the Python bindings (add_<name>,
/// <name>_violation), `pbd run`'s summary and the study's per-type errors. So a new built-in type is its header
/// under constraints/ (the struct, `evaluate`, and what constraints/traits.hpp lists: name, scene key, violation and
/// its unit, rest values, checks), its SIMD kernel if it has one, and one entry here. tests/new_type shows it.
/// Volume constraints (one spans a whole mesh) and the per-step collision constraints are not in the list: the sweep
/// projects them after these types, in that order (engine/src/solve/sweep.hpp).
#include "pbd/constraints/anchor.hpp"
#include "pbd/constraints/area.hpp"
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/fiber.hpp"
#include "pbd/constraints/neo_hookean.hpp"
#include "pbd/constraints/shape_match.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/constraints/tet_fiber.hpp"
#include "pbd/constraints/tet_volume.hpp"
#include "pbd/constraints/tether.hpp"

#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>

namespace pbd {

/// The built-in fixed-arity constraint types of precision Real, in the order a sweep projects them.
template <class Real>
using BuiltinConstraintTypes =
    std::tuple<StretchConstraint<Real>, AnchorConstraint<Real>, BendingConstraint<Real>, AreaConstraint<Real>,
               TetherConstraint<Real>, TetVolumeConstraint<Real>, NeoHookeanConstraint<Real>,
               ShapeMatchConstraint<Real>, FiberConstraint<Real>, TetFiberConstraint<Real>>;

/// Number of built-in fixed-arity types.
inline constexpr std::size_t kNumBuiltinTypes = std::tuple_size_v<BuiltinConstraintTypes<float>>;

/// Position of type C in BuiltinConstraintTypes (a compile error if C is not built in).
template <class C, class Tuple> struct TypeIndex;
template <class C, class... Ts> struct TypeIndex<C, std::tuple<Ts...>> {
  static constexpr std::size_t value = [] {
    constexpr bool same[] = {std::is_same_v<C, Ts>...};
    for (std::size_t i = 0; i < sizeof...(Ts); ++i)
      if (same[i]) return i;
    return sizeof...(Ts);
  }();
};

/// True when C is one of the built-in fixed-arity types of precision Real.
template <class C, class Real>
inline constexpr bool is_builtin_v = TypeIndex<C, BuiltinConstraintTypes<Real>>::value < kNumBuiltinTypes;

/// Calls f(std::type_identity<C>{}, index) for each type C of the tuple Types, in order (index: a
/// std::integral_constant, C's position). The one way the passes outside the solver visit the list.
template <class Types, class F> constexpr void for_each_type(F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::type_identity<std::tuple_element_t<I, Types>>{}, std::integral_constant<std::size_t, I>{}), ...);
  }(std::make_index_sequence<std::tuple_size_v<Types>>{});
}

/// std::tuple<std::vector<C>...> and the like: Wrap<C> for each type of a tuple. Wrap takes a pack, so a template
/// with defaulted parameters (std::vector) matches without C++17's relaxed matching, which clang leaves off.
template <template <class...> class Wrap, class Types> struct EachOf;
template <template <class...> class Wrap, class... Cs> struct EachOf<Wrap, std::tuple<Cs...>> {
  using type = std::tuple<Wrap<Cs>...>;  ///< one Wrap<C> per type
};

}  // namespace pbd
