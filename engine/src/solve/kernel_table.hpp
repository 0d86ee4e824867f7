#pragma once
// The SIMD kernels of every constraint type, by the type's position in for_each_type (private): one entry per
// built-in type, from its Kernels<C> specialization (kernels.hpp); user-defined types (positions from
// kNumBuiltinTypes on) have none. The sweeps call an entry once per color range, never per constraint.
#include "bending_kernel.hpp"
#include "kernels_avx2.hpp"
#include "stretch_kernel.hpp"

#include "pbd/detail/model.hpp"

#include <array>

namespace pbd::detail {

/// One type's kernel on padded positions, type-erased.
template <class Real> struct PaddedKernel {
  /// Constraints [b, e) of one color of `type` on padded positions q (λ: the type's λ array; set: the set the
  /// color's constraints share, or kMixedSets).
  using Range = void (*)(const TypeStore<Real>& type, Index b, Index e, Real* q, const SolveCoefficients<Real>* coeff,
                         Real* lambda, bool any_xpbd, Index set);
  /// Block interiors [first, last) of `type` on padded positions q (backwards when reverse).
  using Interiors = void (*)(const TypeStore<Real>& type, Index first, Index last, Real* q,
                             const SolveCoefficients<Real>* coeff, Real* lambda, bool any_xpbd, bool reverse);
  Range range = nullptr;          ///< nullptr: no kernel (the generic projection)
  Interiors interiors = nullptr;  ///< nullptr: none for the interiors
  Index block = 1;                ///< colors' ranges are cut at multiples of this from each color's start
  Index chains = 1;               ///< most blocks a task of the interiors kernel takes (1: each block on its own)
  bool color_sets = false;        ///< range reads the set a color shares (Model::color_sets is kept for the type)
};

namespace kernel_table_detail {

template <class C, class Real> const Store<C>& store_of(const TypeStore<Real>& type) {
  return static_cast<const TypedStore<C, Real, false>&>(type).store;
}

template <class C, class Real> constexpr bool takes_set() {
  return requires(const C* c, Real* q, const SolveCoefficients<Real>* k, Real* l) {
    Kernels<C>::range(c, Index(0), Index(0), q, k, l, false, Index(0));
  };
}

template <class C, class Real> void range(const TypeStore<Real>& type, Index b, Index e, Real* q,
                                          const SolveCoefficients<Real>* coeff, Real* lambda, bool any_xpbd, Index set) {
  const C* items = store_of<C>(type).items.data();
  if constexpr (takes_set<C, Real>()) Kernels<C>::range(items, b, e, q, coeff, lambda, any_xpbd, set);
  else Kernels<C>::range(items, b, e, q, coeff, lambda, any_xpbd);
}

template <class C, class Real> void interiors(const TypeStore<Real>& type, Index first, Index last, Real* q,
                                              const SolveCoefficients<Real>* coeff, Real* lambda, bool any_xpbd,
                                              bool reverse) {
  const Store<C>& st = store_of<C>(type);
  Kernels<C>::interiors(st.items.data(), st.offsets.data(), first, last, q, coeff, lambda, any_xpbd, reverse);
}

// Colored interiors (traits.hpp): each block's runs by the type's range kernel, as the generic projection
// (TypeStore::project_interiors) visits them.
template <class C, class Real> void colored_interiors(const TypeStore<Real>& type, Index first, Index last, Real* q,
                                                      const SolveCoefficients<Real>* coeff, Real* lambda,
                                                      bool any_xpbd, bool reverse) {
  for_each_run(store_of<C>(type), first, last, reverse, [&](Index b, Index e) {
    range<C, Real>(type, b, e, q, coeff, lambda, any_xpbd, kMixedSets);
  });
}

// The entry of type C: its kernel when this build has it and the CPU runs it.
template <class C, class Real> PaddedKernel<Real> entry() {
  using K = Kernels<C>;
  PaddedKernel<Real> k;
  if constexpr (K::kBuilt) {
    if (K::kNeedsAvx2 && !avx2_enabled()) return k;
    k.range = &range<C, Real>;
    k.block = K::kBlock;
    k.color_sets = takes_set<C, Real>();
    if constexpr (pbd::colored_interiors<C>()) {
      k.interiors = &colored_interiors<C, Real>;
      k.chains = 1;
    } else if constexpr (requires { K::interiors; }) {
      k.interiors = &interiors<C, Real>;
      k.chains = K::kChains;
    }
  }
  return k;
}

template <class Real, class... Cs> std::array<PaddedKernel<Real>, sizeof...(Cs)> entries(std::tuple<Cs...>*) {
  return {entry<Cs, Real>()...};
}

}  // namespace kernel_table_detail

/// The kernel of the type at position t (for_each_type), or an empty entry (no kernel: user-defined types, types
/// without a specialization, kernels this build or CPU lacks).
template <class Real> const PaddedKernel<Real>& padded_kernel(std::size_t t) {
  static const std::array<PaddedKernel<Real>, kNumBuiltinTypes> table =
      kernel_table_detail::entries<Real>(static_cast<BuiltinConstraintTypes<Real>*>(nullptr));
  static const PaddedKernel<Real> none;
  return t < kNumBuiltinTypes ? table[t] : none;
}

}  // namespace pbd::detail
