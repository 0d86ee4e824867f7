#pragma once
/// \file constraint_types.hpp
/// THE list of built-in fixed-arity constraint types, in solver order. Every pass over the constraints (storage,
/// coloring, sweeps, λ, Jacobi counts, removal, statistics, error measures) folds over this list, so a new built-in
/// type is: its header under constraints/ (struct, evaluate, violation), one entry here, its scene key.
/// Volume constraints (one spans a whole mesh) and the per-step collision constraints are not in the list: the sweep
/// projects them after these types, in that order (engine/src/solve/sweep.hpp).
#include "pbd/constraints/anchor.hpp"
#include "pbd/constraints/area.hpp"
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/stretch.hpp"

#include <cstddef>
#include <tuple>
#include <utility>

namespace pbd {

/// The built-in fixed-arity constraint types of precision Real, in the order a sweep projects them.
template <class Real>
using BuiltinConstraintTypes =
    std::tuple<StretchConstraint<Real>, AnchorConstraint<Real>, BendingConstraint<Real>, AreaConstraint<Real>>;

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

}  // namespace pbd
