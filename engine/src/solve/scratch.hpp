#pragma once
#include <chrono>
// Per-step scratch of a world (private): what a step computes and throws away. Kept between steps only so that
// nothing is reallocated; a copied world starts with an empty one.
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/detail/constraint_store.hpp"
#include "pbd/detail/model.hpp"
#include "free_bodies.hpp"
#include "pbd/stiffness.hpp"

#include <oneapi/tbb/partitioner.h>

#include <cstdlib>
#include <deque>
#include <memory>
#include <new>

namespace pbd::detail {

/// The contact generators' buffers (contact/scratch.hpp), complete only where a sub-step makes them (substep.cpp). Held
/// by a shared_ptr, which frees it with the deleter made there, so a Scratch is destroyed wherever, as the solver
/// benchmarks' fixture does, without the type.
template <class Real> struct ContactScratch;

/// Affinity partitioners, one per parallel loop of a sub-step (each color, each particle pass), created on first
/// use: a thread tends to get the same slice every sweep. Only a cache hint: results never depend on it.
class PartitionerPool {
public:
  /// The partitioner of slot i.
  tbb::affinity_partitioner& operator[](std::size_t i) {
    while (pool_.size() <= i) pool_.emplace_back();
    return pool_[i];
  }
  void clear() { pool_.clear(); }  ///< forgets every partitioner

private:
  std::deque<tbb::affinity_partitioner> pool_;
};

/// x y z w per particle (w: inverse mass) for the SIMD kernels, 64-byte aligned so that no particle straddles a
/// cache line (16 bytes each in float, 32 in double). Copies start empty: it is per-sub-step scratch.
template <class Real> class PaddedPoints {
public:
  PaddedPoints() = default;
  PaddedPoints(const PaddedPoints&) {}
  PaddedPoints& operator=(const PaddedPoints&) { return *this; }
  /// Room for n particles (contents undefined).
  void resize(Index n) {
    if (n == size_) return;
    const std::size_t bytes = (4 * sizeof(Real) * std::size_t(n) + 63) / 64 * 64;
    data_.reset(n ? static_cast<Real*>(std::aligned_alloc(64, bytes)) : nullptr);
    if (n && !data_) throw std::bad_alloc();
    size_ = n;
  }
  Index size() const { return size_; }
  Real* data() { return data_.get(); }
  const Real* data() const { return data_.get(); }

private:
  struct Free {
    void operator()(Real* p) const { std::free(p); }
  };
  std::unique_ptr<Real, Free> data_;
  Index size_ = 0;
};

/// Buffers of the per-sub-step colorings (schedule.hpp: color_collisions, color_particle_contacts), kept between sub-steps so that nothing is reallocated.
template <class C> struct FirstFitScratch {
  ConstraintGraph graph;              // the constraints' particles
  std::vector<std::uint64_t> used;    // per particle: colors taken there (bit c)
  std::vector<std::uint32_t> color;   // per constraint, generation order
  std::vector<C> by_index;            // the constraints in generation order while they are laid out
};

/// The hierarchy's per-sub-step buffers (hierarchy.hpp: run_hierarchy).
template <class Real> struct HierarchyScratch {
  std::vector<Real> start;           // p at the start of the pass, 3 per particle
  std::vector<Real> lambda;          // λ of every level's constraints, level l's from lambda_offsets[l]
  std::vector<std::size_t> lambda_offsets;
  PartitionerPool partitioners;      // one per loop of the pass
};

template <class Real> struct Scratch {
  Matrix3X<Real> p;                                 // predicted positions
  Store<CollisionConstraint<Real>> collisions;      // this sub-step's collisions (color order for colored solvers)
  std::vector<Real> collision_lambda;               // their λ, stored order (counts the projections that moved one)
  Store<ParticleContact<Real>> particle_contacts;   // this sub-step's particle contacts (color order likewise)
  std::vector<Real> particle_contact_lambda;        // their λ likewise
  std::shared_ptr<ContactScratch<Real>> contact;    // the contact generators' buffers (made by the first step), unshared
  FirstFitScratch<CollisionConstraint<Real>> collision_coloring;  // their colorings' buffers
  FirstFitScratch<ParticleContact<Real>> contact_coloring;
  std::vector<SolveCoefficients<Real>> coeff;       // per constraint set, for this step's sub-step length
  VolumeScratch<Real> volume;                       // volume targets, gradients, block sums
  std::chrono::microseconds team_wait{20};          // how long the next solve waits for its team (team.hpp)
  int team_misses = 0;                              // solves in a row whose team lacked a thread it waited for
  int team_skip = 0;                                // solves still to run without a team after such a miss
  std::vector<Real> count_inv;                      // Jacobi: 1 / (persistent constraints touching the particle)
  std::vector<Real> split_w;                        // Jacobi: split inverse masses, w · that count
  std::vector<Real> delta;                          // Jacobi: accumulated corrections, 3 per particle
  PaddedPoints<Real> padded;                        // the SIMD kernels' positions: x y z w per particle
  PartitionerPool partitioners;                     // one per color and pass of the sweeps
  PartitionerPool particle_partitioners;            // the per-particle passes of a sub-step (substep.cpp)
  FreeBodies<Real> free_bodies;                     // bodies nothing outside touches, and their solver spin
  std::vector<Real> cheb_prev, cheb_cur;            // Chebyshev: positions before the last sweep and this one
  std::vector<Real> cheb_lambda_prev, cheb_lambda_cur;  // Chebyshev: every λ likewise (compliant sets only)
  std::vector<double> cheb_sums;                    // Chebyshev: per block of particles, the sweep's change
  PartitionerPool cheb_partitioners;                // Chebyshev: its three particle passes
  HierarchyScratch<Real> hierarchy;                 // the hierarchy's pass (hierarchy.hpp)
  Matrix3X<Real> callback_forces;                   // filled by the force callback
  State<Real> before;                               // the state a step started from (step_undo.hpp)
};

}  // namespace pbd::detail
