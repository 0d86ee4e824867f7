#pragma once
// A vertical compliant chain for the closed-form tests (physics_test, hierarchy_test): particle 0 pinned at z = 0,
// particles 1..n of mass m hanging below it at their rest spacing, links of rest length `rest` with XPBD compliance
// `alpha` (m/N). At rest link k stretches by alpha * T_k, T_k the weight below it.
#include "pbd/world.hpp"

namespace pbd::test {

template <class Real> World<Real> hanging_chain(int n, double m, double rest, double alpha, Solver s) {
  World<Real> w;
  const Index set = w.add_constraint_set(Stiffness::xpbd_compliance(alpha));
  w.add_particle(Vec3<Real>::Zero(), World<Real>::kPinned);
  for (int i = 1; i <= n; ++i) {
    w.add_particle(Vec3<Real>(Real(0), Real(0), Real(-rest * i)), Real(m));
    w.add_stretch(i - 1, i, set);
  }
  StepParams<Real> p;
  p.solver = s;
  w.set_params(p);
  return w;
}

}  // namespace pbd::test
