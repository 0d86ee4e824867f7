#pragma once
/// \file colored_constraints.hpp
/// Constraints reordered by color: within one color no two constraints move the same particle.
#include "pbd/constraint_arrays.hpp"
#include "pbd/constraint_graph.hpp"
#include "pbd/error.hpp"

#include <pbd/graph_coloring/color.hpp>
#include <pbd/graph_coloring/error.hpp>

#include <algorithm>
#include <bit>
#include <vector>

namespace pbd {

/// One constraint type's array in color order: color c is items[offsets[c], offsets[c + 1]).
template <class Constraint> struct ColoredArray {
  using value_type = Constraint;  ///< the constraint type
  std::vector<Constraint> items;  ///< the constraints, color by color, by insertion index within a color
  std::vector<Index> offsets;     ///< num_colors() + 1 entries
  std::vector<Index> new_index;   ///< insertion index → position in items (the old→new map)
  std::vector<Index> color;       ///< insertion index → its color
  /// Constraints appended after the last full coloring live in "tail" colors after the others (color_appended):
  /// tail_color is the first of them (kNoTail: none), tail_item the first appended insertion index, tail_used the
  /// tail colors present at each particle (bit c = tail color tail_color + c).
  static constexpr Index kNoTail = ~Index(0);
  Index tail_color = kNoTail;               ///< first tail color
  Index tail_item = 0;                      ///< first insertion index in the tail
  std::vector<std::uint64_t> tail_used;     ///< per particle, tail colors in use

  /// Number of constraints.
  std::size_t size() const { return items.size(); }
  /// Number of colors.
  Index num_colors() const { return offsets.empty() ? 0 : Index(offsets.size() - 1); }
};

/// Every persistent constraint type, colored and reordered. Built from a world's arrays and inverse masses.
template <class Real> struct ColoredConstraints {
  ColoredArray<StretchConstraint<Real>> stretch;  ///< stretch constraints by color
  ColoredArray<AnchorConstraint<Real>> anchor;    ///< anchors by color
  ColoredArray<BendingConstraint<Real>> bending;  ///< bending constraints by color
  ColoredArray<AreaConstraint<Real>> area;        ///< area constraints by color
  VolumeConstraints<Real> volume;                 ///< volume constraints, insertion order: each is its own color

  /// Calls f(colored_array) for each fixed-arity type, in solver order (volume comes after them).
  template <class F> void for_each(F&& f) const {
    f(stretch);
    f(anchor);
    f(bending);
    f(area);
  }
  /// Calls f(insertion_array, colored_array) for each fixed-arity type of `c`, in solver order.
  template <class F> void zip(const ConstraintArrays<Real>& c, F&& f) { zip_arrays(*this, c, f); }
  /// Read-only zip, for comparing the colored copy with the insertion arrays.
  template <class F> void zip(const ConstraintArrays<Real>& c, F&& f) const { zip_arrays(*this, c, f); }
  template <class Self, class F> static void zip_arrays(Self& self, const ConstraintArrays<Real>& c, F& f) {
    f(c.stretch, self.stretch);
    f(c.anchor, self.anchor);
    f(c.bending, self.bending);
    f(c.area, self.area);
  }
  /// Total number of colors over all types (one per volume constraint).
  Index num_colors() const {
    Index n = Index(volume.size());
    for_each([&](const auto& a) { n += a.num_colors(); });
    return n;
  }
};

/// Colors each constraint type of `c` separately with graph_coloring (particles with inverse mass 0 never
/// conflict, since no projection writes them) and reorders it by color. Throws pbd::Error on failure.
template <class Real>
ColoredConstraints<Real> color_constraints(const ConstraintArrays<Real>& c, const VectorX<Real>& inverse_masses,
                                           const coloring::Options& options);

/// Places items[first_item, end) into a.items grouped by their colors (all in [first_color, first_color + colors)),
/// by insertion index within a color, starting at a.offsets[first_color]; sets the offsets after it and new_index.
template <class Constraint>
void place_by_color(ColoredArray<Constraint>& a, const std::vector<Constraint>& items, Index first_item,
                    Index first_color, Index colors) {
  const Index n = Index(items.size());
  std::vector<Index> count(colors, 0);
  for (Index i = first_item; i < n; ++i) ++count[a.color[i] - first_color];
  for (Index c = 0; c < colors; ++c) a.offsets[first_color + c + 1] = a.offsets[first_color + c] + count[c];
  std::vector<Index> next(a.offsets.begin() + first_color, a.offsets.begin() + first_color + colors);
  a.items.resize(n);
  a.new_index.resize(n);
  for (Index i = first_item; i < n; ++i) {
    const Index at = next[a.color[i] - first_color]++;
    a.new_index[i] = at;
    a.items[at] = items[i];
  }
}

/// Lays `items` out by the colors in a.color (one per item, insertion order): items grouped by color, by
/// insertion index within a color; colors left empty are dropped and the others renumbered in order.
template <class Constraint> void layout_by_color(ColoredArray<Constraint>& a, const std::vector<Constraint>& items) {
  const Index n = Index(items.size());
  Index colors = 0;
  for (Index c : a.color) colors = std::max(colors, c + 1);
  std::vector<Index> count(colors, 0), renumber(colors, 0);
  for (Index c : a.color) ++count[c];
  Index used = 0;
  for (Index c = 0; c < colors; ++c) renumber[c] = count[c] ? used++ : 0;
  for (Index& c : a.color) c = renumber[c];
  // Room for the tail that color_appended may add (at most 10%) without moving the arrays.
  const std::size_t room = std::size_t(n) + n / 10 + 16;
  a.items.reserve(room);
  a.new_index.reserve(room);
  a.color.reserve(room);
  a.offsets.assign(std::size_t(used) + 1, 0);
  place_by_color(a, items, 0, 0, used);
  if (n == 0) a.offsets.clear();
  a.tail_color = ColoredArray<Constraint>::kNoTail;  // everything is laid out as one: no tail any more
  a.tail_used.clear();
}

/// Colors an array of fixed-arity constraints with graph_coloring and lays it out by color.
template <class Constraint>
ColoredArray<Constraint> color_array(const std::vector<Constraint>& items, const std::vector<std::uint8_t>& fixed,
                                     const coloring::Options& options) {
  ColoredArray<Constraint> out;
  if (items.empty()) return out;
  const ConstraintGraph graph = constraint_graph(items, fixed);
  coloring::Coloring col;
  try {
    col = coloring::color(graph.view(), options);
  } catch (const coloring::Error& e) {
    throw Error(std::string("coloring ") + Constraint::kName + " constraints: " + e.what());
  }
  out.color.assign(col.color.begin(), col.color.end());
  layout_by_color(out, items);
  return out;
}

/// Colors items[first, end) appended since `a` was last laid out, without touching the others: appended
/// constraints go into "tail" colors after the existing ones, first fit among those tail colors only (different
/// colors run one after the other, so a tail constraint may share particles with any earlier color). Work is
/// proportional to the number of appended constraints (plus one per-particle table the first time). Returns false
/// when the tail grows past 8 colors or 10% of the constraints: the caller then colors everything anew, which keeps
/// the color count low.
template <class Constraint>
bool color_appended(ColoredArray<Constraint>& a, const std::vector<Constraint>& items,
                    const std::vector<std::uint8_t>& fixed) {
  constexpr Index kMaxTailColors = 8;
  const Index first = Index(a.color.size()), n = Index(items.size());
  if (a.tail_color == ColoredArray<Constraint>::kNoTail) {
    a.tail_color = a.num_colors();
    a.tail_item = first;
    a.tail_used.assign(fixed.size(), 0);
  }
  a.tail_used.resize(fixed.size(), 0);
  if (std::size_t(n - a.tail_item) * 10 > std::size_t(n)) return false;
  Index tail_colors = a.num_colors() - a.tail_color;
  for (Index i = first; i < n; ++i) {
    std::uint64_t taken = 0;
    for (Index p : items[i].particles)
      if (!fixed[p]) taken |= a.tail_used[p];
    const Index c = Index(std::countr_one(taken));
    if (c >= kMaxTailColors) return false;
    for (Index p : items[i].particles)
      if (!fixed[p]) a.tail_used[p] |= std::uint64_t(1) << c;
    a.color.push_back(a.tail_color + c);
    tail_colors = std::max(tail_colors, c + 1);
  }
  // Lay out the tail only: its items by color, then insertion index, after the untouched colors.
  a.offsets.resize(std::size_t(a.tail_color) + tail_colors + 1, 0);
  place_by_color(a, items, a.tail_item, a.tail_color, tail_colors);
  return true;
}

}  // namespace pbd
