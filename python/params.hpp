#pragma once
// The Python StepParams and ContactMaterial: precision-free (double) copies of the engine's structs, converted to a
// World<Real>'s precision when given to it.
#include "pbd/colliders.hpp"
#include "pbd/step_params.hpp"

#include <array>

namespace pbd::python {

/// StepParams<Real> without the precision: every field of it.
struct StepParamsPy {
  double dt = 1.0 / 60.0;
  int substeps = 1;
  int iterations = 10;
  std::array<double, 3> gravity{0.0, 0.0, -9.81};
  double damping = 0.0;
  double collision_margin = 0.01;
  Solver solver = Solver::colored;
  SweepOrder sweep_order = SweepOrder::forward;
  double jacobi_omega = 1.0;
  Chebyshev<double> chebyshev;  // acceleration of the sweeps (off by default)
  Hierarchy hierarchy;  // hierarchical PBD (off by default)
};

/// The Python view of a world's parameters.
template <class Real> StepParamsPy to_python(const StepParams<Real>& p) {
  return {double(p.dt), p.substeps, p.iterations, {double(p.gravity.x()), double(p.gravity.y()), double(p.gravity.z())},
          double(p.damping), double(p.collision_margin), p.solver, p.sweep_order, double(p.jacobi_omega),
          Chebyshev<double>{p.chebyshev.enabled, double(p.chebyshev.rho), p.chebyshev.delay, double(p.chebyshev.max_rho),
                            double(p.chebyshev.diverge)},
          p.hierarchy};
}

/// `base` (the world's parameters) with the fields of `p` in Real.
template <class Real> StepParams<Real> to_engine(const StepParamsPy& p, StepParams<Real> base) {
  base.dt = Real(p.dt);
  base.substeps = p.substeps;
  base.iterations = p.iterations;
  base.gravity = Vec3<Real>(Real(p.gravity[0]), Real(p.gravity[1]), Real(p.gravity[2]));
  base.damping = Real(p.damping);
  base.collision_margin = Real(p.collision_margin);
  base.solver = p.solver;
  base.sweep_order = p.sweep_order;
  base.jacobi_omega = Real(p.jacobi_omega);
  base.chebyshev = {p.chebyshev.enabled, Real(p.chebyshev.rho), p.chebyshev.delay, Real(p.chebyshev.max_rho),
                    Real(p.chebyshev.diverge)};
  base.hierarchy = p.hierarchy;
  return base;
}

/// A Python ContactMaterial in Real.
template <class Real> ContactMaterial<Real> to_engine(const ContactMaterial<double>& m) {
  return {Real(m.static_friction), Real(m.kinetic_friction), Real(m.restitution)};
}

}  // namespace pbd::python
