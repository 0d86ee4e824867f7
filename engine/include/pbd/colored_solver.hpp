#pragma once
/// \file colored_solver.hpp
/// The colored Gauss-Seidel solver (serial or parallel over each color) and the Jacobi solver.
///
/// Scheduling: a sweep visits the constraint types in solver order, each type's colors in order, then the volume
/// constraints one after another (each spans a whole mesh, so each is its own color, projected with a fixed-shape
/// parallel reduction inside it: see constraints/volume.hpp), and then the sub-step's collisions (colored by "k-th
/// collision of its particle"). Within a color no two constraints write
/// the same particle, so its constraints are projected by tbb::parallel_for with no synchronisation, and the result
/// is bitwise identical to projecting them one after the other: for any thread count. Colors smaller than
/// ParallelConfig::inline_below run inline; each color keeps its own affinity_partitioner so a thread tends to get
/// the same slice every sweep. The solver runs in whatever tbb::task_arena the caller runs it in.
#include "pbd/colored_constraints.hpp"
#include "pbd/constraints/collision.hpp"
#include "pbd/custom_constraints.hpp"
#include "pbd/solver.hpp"

#include <oneapi/tbb/partitioner.h>

#include <deque>
#include <span>

namespace pbd {

/// Affinity partitioners, one per color, created on first use. A copy starts with fresh ones: affinity is only a
/// cache hint, so copying a world never copies it.
class PartitionerPool {
public:
  PartitionerPool() = default;
  PartitionerPool(const PartitionerPool&) {}                                        ///< fresh partitioners
  PartitionerPool& operator=(const PartitionerPool&) { pool_.clear(); return *this; }  ///< fresh partitioners
  /// The partitioner of slot i.
  tbb::affinity_partitioner& operator[](std::size_t i) {
    while (pool_.size() <= i) pool_.emplace_back();
    return pool_[i];
  }
  void clear() { pool_.clear(); }  ///< forgets every partitioner

private:
  std::deque<tbb::affinity_partitioner> pool_;
};

/// Colored constraints plus the per-step scratch of the colored and Jacobi sweeps.
template <class Real> class ColoredSolver {
public:
  /// Colors and reorders every constraint (built-in and user-defined) from scratch.
  void build(const ConstraintArrays<Real>& constraints, const VectorX<Real>& inverse_masses,
             const coloring::Options& options, CustomTypes<Real>& custom);
  /// True when the colored copy covers exactly these constraints and particles.
  bool up_to_date(const ConstraintArrays<Real>& constraints, const CustomTypes<Real>& custom,
                  Index num_particles) const;
  /// Brings the colored copy up to date after constraints or particles were added: only the new constraints are
  /// colored (first fit against the colors at their particles); falls back to build() past 64 colors.
  void update(const ConstraintArrays<Real>& constraints, const VectorX<Real>& inverse_masses,
              const coloring::Options& options, CustomTypes<Real>& custom);
  /// True once build() has run.
  bool built() const { return built_; }
  /// Drops the coloring (the next step rebuilds it).
  void invalidate() { built_ = false; }

  /// Starts a sub-step: reorders `collisions` by color in place, sets every λ to 0 and the volume targets to their
  /// schedule's value at `time` (seconds).
  void begin_substep(std::vector<CollisionConstraint<Real>>& collisions, double time, CustomTypes<Real>& custom);
  /// Ends a sub-step's sweeps: p holds the solved positions afterwards. Gauss-Seidel sweeps that project only
  /// stretch constraints (float) may keep the positions in the solver's padded copy between sweeps; p is only
  /// guaranteed up to date after this call.
  void end_substep(Real* p, bool parallel, const ParallelConfig& config);

  /// One Gauss-Seidel sweep color by color; `parallel` = false gives the serial color-order bridge.
  void sweep_gauss_seidel(std::span<const CollisionConstraint<Real>> collisions,
                          std::span<const SolveCoefficients<Real>> coeff, Real* p, const Real* w, bool parallel,
                          const ParallelConfig& config, CustomTypes<Real>& custom);

  /// One Jacobi sweep: all corrections from the same p, averaged per particle over the constraints touching it,
  /// scaled by omega, then applied.
  void sweep_jacobi(std::span<const CollisionConstraint<Real>> collisions,
                    std::span<const SolveCoefficients<Real>> coeff, Real* p, const Real* w, Real omega, bool parallel,
                    const ParallelConfig& config, CustomTypes<Real>& custom);

  /// The colored constraints.
  const ColoredConstraints<Real>& constraints() const { return colored_; }
  /// Colors of the persistent constraints, user-defined types included.
  Index num_colors(const CustomTypes<Real>& custom) const {
    Index n = colored_.num_colors();
    for (const auto& t : custom.types()) n += t->num_colors();
    return n;
  }
  /// Number of colors of the sub-step's collisions.
  Index collision_colors() const { return collision_offsets_.empty() ? 0 : Index(collision_offsets_.size() - 1); }

private:
  template <class> friend class World;  // erases constraints in place (World::remove_*)
  // What follows the colored arrays' layout, after a full coloring or a removal: the Jacobi counts
  // (static_count_) and, through note_stretch_sets(), each stretch color's set.
  void count_static(const CustomTypes<Real>& custom);
  // The stretch colors on padded positions (float with SSE2; see stretch_block.hpp).
  // any_xpbd: some set has α̃ ≠ 0 (otherwise the kernel neither reads nor writes λ).
  void project_stretch_colors(const ColoredArray<StretchConstraint<Real>>& array, Real* lambda, Real* p,
                              const Real* w, const SolveCoefficients<Real>* coeff, bool any_xpbd, bool keep_padded,
                              bool parallel, const ParallelConfig& config, std::size_t& part);
  // True when some set of `coeff` has α̃ ≠ 0; then λ may be written this sub-step (begin_substep must reset it).
  bool note_compliance(std::span<const SolveCoefficients<Real>> coeff);
  void unpad(Real* p, bool parallel, const ParallelConfig& config);  // padded copy → p
  // stretch_sets_ for stretch colors [first, num_colors) from colored_.stretch, after a change to them (float only).
  void note_stretch_sets(Index first = 0);
  void project_volumes(const Real* p, Real* out, const Real* w, std::span<const SolveCoefficients<Real>> coeff,
                       bool parallel, const ParallelConfig& config, std::size_t& part);
  bool built_ = false;
  ColoredConstraints<Real> colored_;
  Multipliers<Real> lambda_;
  bool lambda_written_ = true;       // a sweep since the last reset had α̃ ≠ 0, so some λ may be non-zero
  std::vector<Index> collision_offsets_;
  std::vector<CollisionConstraint<Real>> collision_scratch_;
  PartitionerPool partitioners_;  // one per color of the persistent types, then collisions, then the Jacobi update
  Index num_particles_ = 0;
  std::vector<std::uint8_t> fixed_;  // pinned flags the coloring was made with (pins changing = full rebuild)
  std::vector<Index> stretch_sets_;  // per stretch color: the set all its constraints share, or kMixedSets
  std::vector<Index> static_count_;  // Jacobi: persistent constraints touching each particle
  std::vector<Index> count_;         // Jacobi: constraints touching each particle this sub-step (scratch)
  bool counts_ready_ = false;        // Jacobi: count_inv_ is up to date for this sub-step
  std::vector<Real> count_inv_;      // Jacobi: 1 / constraints touching each particle this sub-step
  std::vector<Real> delta_;          // Jacobi: accumulated corrections, 3 per particle
  VolumeScratch<Real> volume_;       // volume targets, gradients and block sums
  Eigen::Matrix<Real, 4, Eigen::Dynamic> padded_;  // stretch sweep: x y z w per particle (float only)
  bool padded_current_ = false;      // padded_ holds the positions and p is stale (until end_substep)
  std::size_t unpad_slot_ = 0;       // partitioner slot of the copy back (the stretch colors reserve it)
};

extern template class ColoredSolver<float>;
extern template class ColoredSolver<double>;

}  // namespace pbd
