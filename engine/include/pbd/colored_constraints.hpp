#pragma once
/// \file colored_constraints.hpp
/// Constraints reordered by color: within one color no two constraints move the same particle.
#include "pbd/constraint_arrays.hpp"

#include <pbd/graph_coloring/color.hpp>

#include <vector>

namespace pbd {

/// One constraint type's array in color order: color c is items[offsets[c], offsets[c + 1]).
template <class Constraint> struct ColoredArray {
  using value_type = Constraint;  ///< the constraint type
  std::vector<Constraint> items;  ///< the constraints, color by color, by insertion index within a color
  std::vector<Index> offsets;     ///< num_colors() + 1 entries
  std::vector<Index> new_index;   ///< insertion index → position in items (the old→new map)

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

/// The coloring of one array of fixed-arity constraints (for statistics and for color_constraints).
template <class Constraint>
coloring::Coloring color_array(const std::vector<Constraint>& items, const std::vector<std::uint8_t>& fixed,
                               Index num_particles, const coloring::Options& options);

}  // namespace pbd
