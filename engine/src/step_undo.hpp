#pragma once
// A step's undo (private; World::step): what a step changes, kept before it runs and put back when it fails in any
// way (an exception from the host's force callback, an allocation failure, a non-finite state, an injected fault),
// so that a failed step() leaves the world bit for bit as it was (docs/robustness.md).
//   every step      the state: positions, velocities, time, λ, Chebyshev's measured ρ (copied into the scratch's
//                   buffer, which keeps its capacity from step to step)
//   when they move  the tethers' targets (they follow their pins) and the plastic strains (a set that yields)
//   on a break      the whole model, copied by World::break_fibers only on a step that breaks or tears something
// The caches a step cooks (colors, blocks, the hierarchy, the contact bodies) are not put back: each is cooked from
// the model alone, so what a failed step cooked is what the next step would cook.
#include "fibers.hpp"
#include "pbd/detail/model.hpp"

#include <optional>
#include <vector>

namespace pbd::detail {

template <class Real> class StepUndo {
 public:
  /// Keeps what a step may change of (m, s): the state into `buffer`.
  StepUndo(const Model<Real>& m, const State<Real>& s, State<Real>& buffer);
  /// Keeps the whole model too, before a step's breaks edit it (World::break_fibers; rare).
  void keep_model(const Model<Real>& m) { model_ = m; }
  /// Puts it back (the positions copied into their own storage, so maps the host holds stay valid).
  void restore(Model<Real>& m, State<Real>& s);

 private:
  const State<Real>& kept_;
  std::vector<Vec3<Real>> targets_;  // the tethers' targets
  PlasticRollback<Real> plastic_;
  std::optional<Model<Real>> model_;
};

}  // namespace pbd::detail
