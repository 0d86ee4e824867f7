#pragma once
/// \file constraint_view.hpp
/// Read-only views of a world's constraints of one type, by the index the user got when adding them.
#include "pbd/detail/constraint_store.hpp"

#include <iterator>

namespace pbd {

/// The constraints of type C in insertion (user) order: c[i] is the constraint add_* returned index i for. The
/// engine stores them in color order; the view follows the map, so it costs one indirection per access.
template <class C> class ConstraintView {
public:
  using value_type = C;  ///< the constraint type
  ConstraintView() = default;
  explicit ConstraintView(const detail::Store<C>* store) : store_(store) {}  ///< view of a store (nullptr: empty)
  std::size_t size() const { return store_ ? store_->size() : 0; }          ///< number of constraints
  bool empty() const { return size() == 0; }                                 ///< true when there are none
  const C& operator[](std::size_t i) const { return store_->at(Index(i)); }  ///< the constraint with user index i

  /// Iterates in user-index order.
  class iterator {
  public:
    using iterator_category = std::forward_iterator_tag;  ///< forward iteration
    using value_type = C;                                 ///< the constraint type
    using difference_type = std::ptrdiff_t;               ///< distance
    using pointer = const C*;                             ///< pointer to a constraint
    using reference = const C&;                           ///< reference to a constraint
    iterator() = default;
    iterator(const detail::Store<C>* s, Index i) : s_(s), i_(i) {}  ///< at user index i
    const C& operator*() const { return s_->at(i_); }               ///< the constraint
    const C* operator->() const { return &s_->at(i_); }             ///< the constraint
    iterator& operator++() { ++i_; return *this; }                  ///< next user index
    iterator operator++(int) { iterator t = *this; ++i_; return t; }  ///< next user index
    bool operator==(const iterator& o) const { return i_ == o.i_; }   ///< same position
  private:
    const detail::Store<C>* s_ = nullptr;
    Index i_ = 0;
  };
  iterator begin() const { return {store_, 0}; }                 ///< first constraint
  iterator end() const { return {store_, Index(size())}; }       ///< past the last

private:
  const detail::Store<C>* store_ = nullptr;
};

/// The constraints of one type as the colored solvers store and run them.
template <class C> struct ConstraintColors {
  std::span<const C> items;       ///< the constraints in color order
  Index num_colors = 0;           ///< colors of the type
  std::span<const Index> color;   ///< color of each constraint, by user index
  std::span<const Index> stored;  ///< position of each constraint in color order, by user index (the old→new map)
  std::span<const Index> offsets; ///< color c holds color-order positions [offsets[c], offsets[c + 1])
  std::size_t size() const { return items.size(); }  ///< number of constraints
};

}  // namespace pbd
