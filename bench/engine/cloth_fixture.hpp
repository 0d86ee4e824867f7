#pragma once
// The solver benchmarks' scene: the stretch constraints of an N×N hanging cloth (float, PBD k = 1) with positions
// perturbed so every projection does work, and the solve of one sub-step as World::step runs it.
#include "pbd/colored_solver.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/serial_solver.hpp"

#include <random>

namespace pbd::bench {

using Real = float;
constexpr int kSweeps = 10;  ///< sweeps per sub-step: StepParams' default iterations

/// An N×N cloth's constraints and perturbed positions (seed 42).
struct ClothFixture {
  World<Real> world;
  Matrix3X<Real> p;
  std::vector<SolveCoefficients<Real>> coeff;

  explicit ClothFixture(int n) {
    ClothOptions o;
    o.resolution = n;
    add_cloth(world, o, world.add_constraint_set(Stiffness::pbd_k(1.0)));
    p = world.positions();
    std::mt19937 rng(42);
    std::uniform_real_distribution<Real> u(-0.3f, 0.3f);
    const Real spacing = Real(1.0 / (n - 1));
    for (Eigen::Index i = 0; i < p.cols(); ++i)
      if (world.inverse_masses()[i] != 0) p.col(i) += spacing * Vec3<Real>(u(rng), u(rng), u(rng));
    coeff = {coefficients<Real>(world.constraints().sets[0], 1.0 / 60, kSweeps)};
  }
  std::size_t constraints() const { return world.constraints().stretch.size(); }
};

/// One sub-step of the serial reference: λ reset, kSweeps sweeps in insertion order.
inline void serial_substep(ClothFixture& f, Multipliers<Real>& lambda) {
  lambda.reset(f.world.constraints(), 0);
  for (int s = 0; s < kSweeps; ++s)
    sweep_serial<Real>(f.world.constraints(), {}, f.coeff, f.p.data(), f.world.inverse_masses().data(), lambda);
}

/// One sub-step of the colored solver (jacobi = false: Gauss-Seidel) in the calling thread's arena.
inline void colored_substep(ClothFixture& f, ColoredSolver<Real>& solver, CustomTypes<Real>& custom, bool jacobi,
                            const ParallelConfig& config = {}) {
  std::vector<CollisionConstraint<Real>> none;
  const Real* w = f.world.inverse_masses().data();
  solver.begin_substep(none, 0.0, custom);
  for (int s = 0; s < kSweeps; ++s) {
    if (jacobi) solver.sweep_jacobi(none, f.coeff, f.p.data(), w, Real(1), true, config, custom);
    else solver.sweep_gauss_seidel(none, f.coeff, f.p.data(), w, true, config, custom);
  }
  solver.end_substep(f.p.data(), true, config);
}

}  // namespace pbd::bench
