#include "pbd/colored_constraints.hpp"

#include "message.hpp"
#include "pbd/error.hpp"

#include <pbd/graph_coloring/error.hpp>

namespace pbd {

template <class Constraint>
coloring::Coloring color_array(const std::vector<Constraint>& items, const std::vector<std::uint8_t>& fixed,
                               Index num_particles, const coloring::Options& options) {
  constexpr Index arity = Constraint::kArity;
  const Index n = Index(items.size());
  std::vector<std::uint32_t> offsets = coloring::uniform_offsets(n, arity);
  std::vector<std::uint32_t> nodes(std::size_t(n) * arity);
  for (Index i = 0; i < n; ++i)
    for (Index k = 0; k < arity; ++k) nodes[std::size_t(i) * arity + k] = items[i].particles[k];
  coloring::Hypergraph graph{offsets, nodes, num_particles, fixed};
  try {
    return coloring::color(graph, options);
  } catch (const coloring::Error& e) {
    throw Error(detail::message("coloring constraints: ", e.what()));
  }
}

namespace {

template <class Constraint>
ColoredArray<Constraint> reorder(const std::vector<Constraint>& items, const std::vector<std::uint8_t>& fixed,
                                 Index num_particles, const coloring::Options& options) {
  ColoredArray<Constraint> out;
  if (items.empty()) return out;
  const coloring::Coloring col = color_array(items, fixed, num_particles, options);
  out.offsets.assign(col.color_offsets.begin(), col.color_offsets.end());
  out.items.reserve(items.size());
  out.new_index.resize(items.size());
  for (std::uint32_t old : col.items) {
    out.new_index[old] = Index(out.items.size());
    out.items.push_back(items[old]);
  }
  return out;
}

}  // namespace

template <class Real>
ColoredConstraints<Real> color_constraints(const ConstraintArrays<Real>& c, const VectorX<Real>& w,
                                           const coloring::Options& options) {
  const Index n = Index(w.size());
  std::vector<std::uint8_t> fixed(n);
  for (Index i = 0; i < n; ++i) fixed[i] = w[i] == Real(0);
  ColoredConstraints<Real> out;
  out.stretch = reorder(c.stretch, fixed, n, options);
  out.anchor = reorder(c.anchor, fixed, n, options);
  out.bending = reorder(c.bending, fixed, n, options);
  out.area = reorder(c.area, fixed, n, options);
  out.volume = c.volume;
  return out;
}

template ColoredConstraints<float> color_constraints(const ConstraintArrays<float>&, const VectorX<float>&,
                                                     const coloring::Options&);
template ColoredConstraints<double> color_constraints(const ConstraintArrays<double>&, const VectorX<double>&,
                                                      const coloring::Options&);
#define PBD_INSTANTIATE_COLOR_ARRAY(T)                                                                         \
  template coloring::Coloring color_array(const std::vector<T>&, const std::vector<std::uint8_t>&, Index,      \
                                          const coloring::Options&);
PBD_INSTANTIATE_COLOR_ARRAY(StretchConstraint<float>)
PBD_INSTANTIATE_COLOR_ARRAY(StretchConstraint<double>)
PBD_INSTANTIATE_COLOR_ARRAY(AnchorConstraint<float>)
PBD_INSTANTIATE_COLOR_ARRAY(AnchorConstraint<double>)
PBD_INSTANTIATE_COLOR_ARRAY(BendingConstraint<float>)
PBD_INSTANTIATE_COLOR_ARRAY(BendingConstraint<double>)
PBD_INSTANTIATE_COLOR_ARRAY(AreaConstraint<float>)
PBD_INSTANTIATE_COLOR_ARRAY(AreaConstraint<double>)
#undef PBD_INSTANTIATE_COLOR_ARRAY

}  // namespace pbd
