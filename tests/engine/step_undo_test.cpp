// A step that fails anywhere leaves the world bit for bit as it was (step_undo.hpp): a fault injected after each
// phase of a sub-step (fault_injection.hpp), as a pbd::Error or as an allocation failure, under every solver, on
// built-in scenes that take each path a step has (colliders and particle contacts, free bodies, volumes, tethers,
// fibers that yield, break and tear, soft bodies). The failed world must equal a copy taken before the step, and
// step on to the same bits as that copy.
#include "pbd/detail/fault_injection.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <new>
#include <string>
#include <utility>

namespace pbd {
namespace {

using detail::FaultKind;
using detail::FaultPhase;

// Bitwise equality of two doubles (NaN equals NaN: a fiber's force before its first compliant step).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Everything a host can read of the world a step changes, compared bit for bit.
template <class Real> void expect_same_world(const World<Real>& a, const World<Real>& b, const std::string& where) {
  SCOPED_TRACE(where);
  ASSERT_EQ(a.num_particles(), b.num_particles());
  EXPECT_TRUE(a.positions() == b.positions());
  EXPECT_TRUE(a.velocities() == b.velocities());
  EXPECT_TRUE(a.inverse_masses() == b.inverse_masses());
  EXPECT_TRUE(same_bits(a.time(), b.time()));
  std::vector<std::size_t> sizes_a, sizes_b;
  a.for_each_builtin([&](const auto& items) { sizes_a.push_back(items.size()); });
  b.for_each_builtin([&](const auto& items) { sizes_b.push_back(items.size()); });
  EXPECT_EQ(sizes_a, sizes_b);
  const auto fa = a.fibers(), fb = b.fibers();
  ASSERT_EQ(fa.size(), fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    EXPECT_TRUE(same_bits(fa[i].plastic, fb[i].plastic)) << "fiber " << i;
    EXPECT_TRUE(same_bits(fa[i].force, fb[i].force)) << "fiber " << i;
  }
  EXPECT_EQ(a.last_breaks().size(), b.last_breaks().size());
  EXPECT_EQ(a.last_copies().size(), b.last_copies().size());
  EXPECT_EQ(a.last_step_stats().sweeps, b.last_step_stats().sweeps);
}

// The scenes a fault is injected into, each taking paths of a step the others do not.
const char* const kScenes[] = {"balls", "cloth-fold", "inflate", "cloth-tear", "ligament", "rope", "jelly", "tet-tear"};

template <class Real> World<Real> scene_world(const std::string& name, Solver solver) {
  World<Real> w = build_world<Real>(load_scene_by_name(name, PBD_TEST_SCENE_DIR).world);
  StepParams<Real> p = w.params();
  p.solver = solver;
  if (p.substeps < 2) p.substeps = 2;  // a fault at the second sub-step follows one that changed the state
  w.set_params(p);
  return w;
}

// A world stepped twice (the state a fault is injected into) and the same world two clean steps further on.
template <class Real> struct Stepped {
  World<Real> before;
  World<Real> two_on;
};

template <class Real> Stepped<Real> stepped(const std::string& name, Solver solver) {
  World<Real> w = scene_world<Real>(name, solver);
  w.step();
  w.step();
  World<Real> two_on = w;
  two_on.step();
  two_on.step();
  return {std::move(w), std::move(two_on)};
}

// Injects the fault into a copy of `s.before`'s next step (at its second sub-step where there is one) and checks
// the undo: the failed world equals `s.before`, and two steps on it equals `s.two_on`. Returns whether the fault
// point was reached.
template <class Real>
bool fail_and_compare(const Stepped<Real>& s, const std::string& name, Solver solver, FaultPhase phase,
                      FaultKind kind) {
  World<Real> w = s.before;
  const std::string where = name + " " + std::string(pbd::name(solver)) + " " + detail::fault_phase_name(phase) +
                            (kind == FaultKind::bad_alloc ? " bad_alloc" : " error");
  detail::arm_fault(phase, kind, phase == FaultPhase::step_end ? 1 : 2);
  bool threw = false;
  try {
    w.step();
  } catch (const std::bad_alloc&) {
    threw = kind == FaultKind::bad_alloc;
  } catch (const Error& e) {
    threw = kind == FaultKind::error && std::string(e.what()).find("injected fault") != std::string::npos;
  }
  const bool fired = detail::disarm_fault();
  if (!fired) return false;  // the step took no path through this point (a team's step has no contact phase)
  EXPECT_TRUE(threw) << where;
  expect_same_world(w, s.before, where);
  w.step();
  w.step();
  expect_same_world(w, s.two_on, where + ", two steps on");
  return true;
}

TEST(StepUndo, AFaultAtAnyPhaseUnderAnySolverLeavesTheWorldAsItWas) {
  for (const char* name : kScenes)
    for (const Solver solver : kSolvers) {
      const Stepped<double> s = stepped<double>(name, solver);
      int fired = 0;
      for (const FaultPhase phase : {FaultPhase::predict, FaultPhase::contacts, FaultPhase::solve, FaultPhase::update,
                                     FaultPhase::step_end}) {
        const FaultKind kind = (int(phase) + int(solver)) % 2 ? FaultKind::bad_alloc : FaultKind::error;
        fired += fail_and_compare(s, name, solver, phase, kind);
      }
      EXPECT_GE(fired, 4) << name << " " << std::string(pbd::name(solver)) << ": the faults did not reach the step's phases";
    }
}

TEST(StepUndo, BothKindsOfFaultInAFloatWorld) {
  const Stepped<float> s = stepped<float>("cloth-fold", Solver::colored);
  for (const FaultKind kind : {FaultKind::error, FaultKind::bad_alloc})
    for (const FaultPhase phase : {FaultPhase::contacts, FaultPhase::solve, FaultPhase::update})
      EXPECT_TRUE(fail_and_compare(s, "cloth-fold", Solver::colored, phase, kind));
}

// A step whose state becomes non-finite (in-range inputs that blow up: here a velocity of 3e38 m/s in a float world,
// whose stretch correction overflows) fails at that step, naming the particle and the step, and is undone.
TEST(StepUndo, ANonFiniteStateStopsTheStepThatMadeIt) {
  World<float> w;
  w.add_particle({0, 0, 0}, 1.0f);
  w.add_particle({1, 0, 0}, 1.0f, {3e38f, 0, 0});
  w.add_stretch(0, 1, w.add_constraint_set(Stiffness::pbd_k(1.0f)));
  bool threw = false;
  for (int i = 0; i < 10 && !threw; ++i) {
    const World<float> last = w;
    try {
      w.step();
    } catch (const Error& e) {
      threw = true;
      const std::string m = e.what();
      EXPECT_NE(m.find("step " + std::to_string(i + 1) + " "), std::string::npos) << m;
      EXPECT_NE(m.find(" got a non-finite "), std::string::npos) << m;
      expect_same_world(w, last, "non-finite step");
      EXPECT_THROW(w.step(), Error);  // the same inputs fail the same way again
      expect_same_world(w, last, "non-finite step, again");
    }
  }
  EXPECT_TRUE(threw) << "a velocity of 3e38 m/s in a float world never overflowed";
}

}  // namespace
}  // namespace pbd
