#include "pbd/colored_constraints.hpp"

namespace pbd {

template <class Real>
ColoredConstraints<Real> color_constraints(const ConstraintArrays<Real>& c, const VectorX<Real>& w,
                                           const coloring::Options& options) {
  const std::vector<std::uint8_t> fixed = pinned_flags(w);
  ColoredConstraints<Real> out;
  out.stretch = color_array(c.stretch, fixed, options);
  out.anchor = color_array(c.anchor, fixed, options);
  out.bending = color_array(c.bending, fixed, options);
  out.area = color_array(c.area, fixed, options);
  out.volume = c.volume;
  return out;
}

template ColoredConstraints<float> color_constraints(const ConstraintArrays<float>&, const VectorX<float>&,
                                                     const coloring::Options&);
template ColoredConstraints<double> color_constraints(const ConstraintArrays<double>&, const VectorX<double>&,
                                                      const coloring::Options&);

}  // namespace pbd
