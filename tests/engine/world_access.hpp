#pragma once
// Short names for a world's built-in constraint views in tests: stretch_of(w) is w.constraints<StretchConstraint<R>>().
#include "pbd/world.hpp"

namespace pbd::test {

template <class W> auto stretch_of(const W& w) { return w.template constraints<StretchConstraint<typename W::Scalar>>(); }
template <class W> auto anchor_of(const W& w) { return w.template constraints<AnchorConstraint<typename W::Scalar>>(); }
template <class W> auto bending_of(const W& w) { return w.template constraints<BendingConstraint<typename W::Scalar>>(); }
template <class W> auto area_of(const W& w) { return w.template constraints<AreaConstraint<typename W::Scalar>>(); }

}  // namespace pbd::test
