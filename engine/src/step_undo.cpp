// A step's undo (step_undo.hpp).
#include "step_undo.hpp"

namespace pbd::detail {

template <class Real>
StepUndo<Real>::StepUndo(const Model<Real>& m, const State<Real>& s, State<Real>& buffer)
    : kept_(buffer), plastic_(m, fibers_flow(m)) {
  buffer = s;  // same sizes as the last step's: no allocation
  for (const TetherConstraint<Real>& t : m.template store<TetherConstraint<Real>>().items) targets_.push_back(t.target);
}

template <class Real> void StepUndo<Real>::restore(Model<Real>& m, State<Real>& s) {
  if (model_) m = std::move(*model_);  // kept after the sub-steps: their tether targets and plastic strains follow
  s = kept_;  // every member; Eigen copies into the positions' own storage (same size), where the host's maps point
  auto& tethers = m.template store<TetherConstraint<Real>>().items;
  for (std::size_t i = 0; i < tethers.size() && i < targets_.size(); ++i) tethers[i].target = targets_[i];
  plastic_.restore(m);
}

template class StepUndo<float>;
template class StepUndo<double>;

}  // namespace pbd::detail
