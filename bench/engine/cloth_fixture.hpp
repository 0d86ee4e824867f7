#pragma once
// The solver benchmarks' scene: the stretch constraints of an N×N hanging cloth (float, PBD k = 1) with positions
// perturbed so every projection does work, and the solve of one sub-step as World::step runs it (the engine's
// internal solver entry, engine/src/solve/solver.hpp: λ reset, kSweeps sweeps, positions back from the padded copy).
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "solve/schedule.hpp"
#include "solve/solver.hpp"

#include <random>

namespace pbd::bench {

using Real = float;
constexpr int kSweeps = 10;  ///< sweeps per sub-step: StepParams' default iterations

/// An N×N cloth's constraints and perturbed positions (seed 42), ready for one solver's sub-steps.
struct ClothFixture {
  World<Real> world;
  detail::Model<Real> model;
  detail::State<Real> state;
  detail::Scratch<Real> scratch;
  StepParams<Real> params;

  /// bending: the grid mesh's stretch and dihedral bending (k = 0.2) instead of the cloth's stretch alone.
  /// per_block: BlockOptions::constraints_per_block (0: the default).
  ClothFixture(int n, Solver solver, bool bending = false, std::size_t per_block = 0) {
    if (per_block) world.set_blocking({per_block, true});
    if (bending) {
      MeshConstraintSets sets;
      sets.stretch = world.add_constraint_set(Stiffness::pbd_k(1.0));
      sets.bending = world.add_constraint_set(Stiffness::pbd_k(0.2));
      MeshBodyOptions o;
      o.pinned = {Index(n * (n - 1)), Index(n * n - 1)};
      add_mesh(world, grid_mesh(n, 1.0), o, sets);
    } else {
      ClothOptions o;
      o.resolution = n;
      add_cloth(world, o, world.add_constraint_set(Stiffness::pbd_k(1.0)));
    }
    Matrix3X<Real>& p = scratch.p;
    p = world.positions();
    std::mt19937 rng(42);
    std::uniform_real_distribution<Real> u(-0.3f, 0.3f);
    const Real spacing = Real(1.0 / (n - 1));
    for (Eigen::Index i = 0; i < p.cols(); ++i)
      if (world.inverse_masses()[i] != 0) p.col(i) += spacing * Vec3<Real>(u(rng), u(rng), u(rng));
    model = world.model();
    model.layout = uses_blocks(solver) ? detail::Layout::blocks : detail::Layout::colors;
    if (solver != Solver::serial) detail::color_everything(model);
    for (const Stiffness& set : world.constraint_sets()) scratch.coeff.push_back(coefficients<Real>(set, 1.0 / 60, kSweeps));
    params.solver = solver;
    params.iterations = kSweeps;
  }
  /// One sub-step's solve in the calling thread's arena.
  void substep(const ParallelConfig& config = {}) { detail::solve(model, state, scratch, params, config, 0.0, false); }
  /// The positions being solved.
  const Matrix3X<Real>& p() const { return scratch.p; }
  std::size_t constraints() const { return world.num_constraints(); }
  Index colors() const { return model.store<StretchConstraint<Real>>().num_colors(); }
  Index blocks() const { return model.num_blocks; }
};

}  // namespace pbd::bench
