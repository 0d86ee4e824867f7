#pragma once
// What a step does with the constraints that follow a stress–strain curve besides projecting them (private;
// constraints/fiber.hpp, tet_fiber.hpp, material.hpp): the plastic flow after each sub-step's sweeps, and the
// breaks after the step. Every type that takes a material (traits.hpp: takes_material), from the list.
#include "pbd/detail/model.hpp"
#include "pbd/fiber_state.hpp"

#include <tuple>
#include <vector>

namespace pbd::detail {

/// Whether a step's sub-steps flow plastic strains: some constraint of a material type is in a set whose curve
/// yields.
template <class Real> bool fibers_flow(const Model<Real>& m);

/// Step 4b of a sub-step: every constraint of a material type in a yielding set whose force at the solved
/// positions p is above its yield force gets the plastic strain that puts it back on it (Material::plastic_after).
/// Each on its own, so the order changes no bit.
template <class Real> void flow_fibers(Model<Real>& m, const Real* p);

/// Whether some constraint of a material type is in a set whose curve ruptures: only then can a step break one.
template <class Real> bool fibers_break(const Model<Real>& m);

/// After a step: the constraints of the material types whose total strain at positions x has reached their set's
/// rupture strain, type by type in the list's order and each type in insertion order, each with the force λ
/// (State::lambda, h2 the step's h²) says it carried. All are judged on the same positions, so which break depends
/// neither on their order nor on the thread count.
template <class Real> std::vector<FiberBreak> find_breaks(const Model<Real>& m, const State<Real>& s, std::int64_t step);

/// Each constraint of material type C's reading (fiber_state.hpp), in insertion order.
template <class C, class Real> std::vector<FiberReading> read_fibers(const Model<Real>& m, const State<Real>& s);

/// The plastic strains of a step's start, put back when a sub-step fails (World::step's rollback).
template <class Real> class PlasticRollback {
 public:
  /// Keeps the material types' constraints of m when `keep`.
  PlasticRollback(const Model<Real>& m, bool keep);
  /// Puts them back into m, when kept.
  void restore(Model<Real>& m);

 private:
  bool kept_ = false;
  std::vector<std::vector<Real>> plastic_;  // per built-in type (empty: not a material type)
};

}  // namespace pbd::detail
