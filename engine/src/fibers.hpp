#pragma once
// What a step does with the fibers besides projecting them (private; constraints/fiber.hpp, material.hpp): the
// plastic flow after each sub-step's sweeps, and the breaks after the step.
#include "pbd/detail/model.hpp"
#include "pbd/fiber_state.hpp"

#include <vector>

namespace pbd::detail {

/// Whether a step's sub-steps flow plastic strains: some fiber is in a set whose curve yields.
template <class Real> bool fibers_flow(const Model<Real>& m);

/// Step 4b of a sub-step: every fiber of a yielding set whose force at the solved positions p is above its yield
/// force gets the plastic strain that puts it back on it (Material::plastic_after). Each fiber on its own, so the
/// order changes no bit.
template <class Real> void flow_fibers(Model<Real>& m, const Real* p);

/// After a step: the fibers whose total strain at positions x has reached their set's rupture strain, in
/// insertion order, each with the force λ (State::lambda, h2 the step's h²) says it carried. All are judged on the
/// same positions, so which break depends neither on the order of the fibers nor on the thread count.
template <class Real> std::vector<FiberBreak> find_breaks(const Model<Real>& m, const State<Real>& s, std::int64_t step);

/// Each fiber's reading (fiber_state.hpp), in insertion order.
template <class Real> std::vector<FiberReading> read_fibers(const Model<Real>& m, const State<Real>& s);

}  // namespace pbd::detail
