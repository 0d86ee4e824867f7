#pragma once
/// \file world.hpp
/// A simulated world: particles, constraints, colliders and the PBD step (Müller et al. 2006).
///
/// Typical use: add particles, constraint sets and constraints, colliders, set the step parameters, then call
/// step() as often as needed and read positions()/velocities() (Eigen maps, no copies). Every mutating call
/// validates its input first and throws pbd::Error naming the offending item, leaving the world unchanged.
#include "pbd/colliders.hpp"
#include "pbd/colored_solver.hpp"
#include "pbd/constraint_arrays.hpp"
#include "pbd/error.hpp"
#include "pbd/solver.hpp"
#include "pbd/types.hpp"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace pbd {

/// Parameters of step(); validated by World::set_params.
template <class Real> struct StepParams {
  Real dt = Real(1) / Real(60);              ///< time step in seconds, > 0
  int substeps = 1;                          ///< sub-steps per step, ≥ 1, each with its own sweeps
  int iterations = 10;                       ///< Gauss-Seidel sweeps per sub-step, ≥ 0
  Vec3<Real> gravity{Real(0), Real(0), Real(-9.81)};  ///< acceleration applied to every movable particle
  Real damping = 0;                          ///< velocity damping rate in 1/s, ≥ 0: v ← v·max(0, 1 − damping·h)
  Real collision_margin = Real(0.01);        ///< contacts are generated for particles ending within this distance, ≥ 0
  Solver solver = Solver::colored;           ///< which solver step() runs
  Real jacobi_omega = 1;                     ///< Jacobi over-relaxation factor ω, in (0, 2)
};

/// Violation of one constraint type after a step, normalized as metrics.hpp defines it (relative stretch, angle
/// error in radians, relative area and volume, penetration depth; anchors: distance to the target).
struct TypeViolation {
  std::string name;        ///< the constraint type (kName), "volume" or "collision"
  std::size_t count = 0;   ///< items measured
  double rms = 0.0;        ///< root mean square
  double max = 0.0;        ///< maximum
};

/// What the last step() did and how long each phase took (wall-clock seconds, summed over sub-steps).
struct StepStats {
  double seconds = 0.0;             ///< the whole step
  double seconds_integrate = 0.0;   ///< forces, damping, prediction and velocity update
  double seconds_collisions = 0.0;  ///< generating (and coloring) collision constraints
  double seconds_coloring = 0.0;    ///< coloring persistent constraints (only when they changed)
  double seconds_solve = 0.0;       ///< the sweeps
  int substeps = 0;                 ///< sub-steps taken
  int sweeps = 0;                   ///< sweeps taken (substeps × iterations)
  Index colors = 0;                 ///< colors of the persistent constraints (0 for the serial solver)
  std::size_t collisions = 0;       ///< collision constraints of the last sub-step
  std::vector<TypeViolation> violation;  ///< per type, at the end of the step (only with measure_violation on)
};

/// Particles, constraints and colliders of one simulation, in precision Real (float or double).
template <class Real> class World {
public:
  using Vec = Vec3<Real>;          ///< 3-vector
  using Positions = Matrix3X<Real>;  ///< 3×N particle data

  /// Mass value meaning "pinned": inverse mass 0, never moved by the solver.
  static constexpr Real kPinned = std::numeric_limits<Real>::infinity();

  /// An empty world with default parameters.
  World() = default;

  /// Adds a particle; mass > 0 (kPinned for a fixed particle). Returns its index (indices never change).
  Index add_particle(const Vec& position, Real mass, const Vec& velocity = Vec::Zero());
  /// Adds many particles at once (all validated before any is added); returns the index of the first.
  Index add_particles(const Positions& positions, const VectorX<Real>& masses);
  /// add_particles by inverse mass (1/kg, finite and >= 0; 0 = pinned), velocities zero: a world rebuilt from
  /// another's inverse masses gets exactly those values.
  Index add_particles_by_inverse_mass(const Positions& positions, const VectorX<Real>& inverse_masses);
  /// Sets a particle's mass (kPinned pins it).
  void set_mass(Index particle, Real mass);

  /// Adds a constraint set with its own stiffness; constraints name it by the returned id.
  Index add_constraint_set(const Stiffness& stiffness);
  /// Adds a stretch constraint between a and b; rest distance defaults to their current distance.
  Index add_stretch(Index a, Index b, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds an anchor pulling `particle` to `target` (default: its current position).
  Index add_anchor(Index particle, Index set, std::optional<Vec> target = std::nullopt);
  /// Adds a dihedral bending constraint on triangles (p1, p2, p3) and (p1, p2, p4) sharing edge p1–p2; the rest
  /// angle defaults to the current one (an error if a triangle is degenerate there).
  Index add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds a triangle area constraint; the rest area defaults to the current one.
  Index add_area(Index a, Index b, Index c, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds a volume constraint on a closed, consistently oriented mesh (counter-clockwise seen from outside); the
  /// target is pressure.at(time()) × rest, rest in the 6V unit of constraints/volume.hpp (default: the current one).
  /// Throws naming the first bad edge if the mesh is open, non-manifold or inconsistently oriented, and rejects a
  /// flat or inside-out mesh.
  Index add_volume(std::span<const std::array<Index, 3>> triangles, Index set, const PressureSchedule& pressure = {},
                   std::optional<Real> rest = std::nullopt);

  /// Adds a constraint of a user-defined type C (see custom_constraints.hpp for what C provides); it is colored and
  /// projected like the built-in types. Returns its index among the constraints of type C.
  template <class C> Index add_custom(const C& constraint);
  /// The constraints of user-defined type C, in insertion order (empty if none).
  template <class C> std::span<const C> custom() const {
    const auto* t = custom_.template find<C>();
    return t ? std::span<const C>(t->items) : std::span<const C>();
  }

  /// Removes stretch constraints by index (each at most once; later indices move down, as with std::vector::erase).
  /// The colors of the remaining constraints are kept: nothing is recolored.
  void remove_stretch(std::span<const Index> indices);
  void remove_anchor(std::span<const Index> indices);   ///< as remove_stretch, for anchors
  void remove_bending(std::span<const Index> indices);  ///< as remove_stretch, for bending constraints
  void remove_area(std::span<const Index> indices);     ///< as remove_stretch, for area constraints
  /// Removes a particle from the simulation: every constraint on it is removed, it is pinned where it is and never
  /// moves or collides again. Its index stays valid (indices never shift). An error if a volume constraint uses it.
  void remove_particle(Index particle);

  /// Adds an infinite plane n·x ≥ offset (n is normalized).
  void add_plane(const Vec& normal, Real offset);
  /// Adds a solid sphere.
  void add_sphere(const Vec& center, Real radius);

  /// Sets how constraints are colored for the colored and Jacobi solvers (recolors at the next step).
  void set_coloring(const coloring::Options& options);
  /// Sets how parallel loops are cut (never changes results).
  void set_parallel_config(const ParallelConfig& config) { parallel_ = config; }
  /// The colored constraints (colors them now if needed): each type's array in color order with its ranges
  /// and the insertion→color-order index map.
  const ColoredConstraints<Real>& colored_constraints();

  /// Sets the step parameters after validating them.
  void set_params(const StepParams<Real>& params);
  /// The current step parameters.
  const StepParams<Real>& params() const { return params_; }

  /// Advances the world by params().dt: substeps × (forces, predict, collisions, sweeps, velocity update).
  void step();
  /// step() with external forces (N, 3×N, one column per particle) applied during the whole step: v += h·w·f.
  void step(Eigen::Ref<const Positions> forces);
  /// Called at every sub-step with the time and positions; fills `forces` (3×N, zeroed before each call). If it
  /// throws or gives a non-finite force, step() throws and the world is left as it was before the step.
  using ForceCallback = std::function<void(double time, Eigen::Ref<const Positions> x, Eigen::Ref<Positions> forces)>;
  /// Sets (or with an empty function clears) the force callback used by step().
  void set_force_callback(ForceCallback callback) { force_callback_ = std::move(callback); }

  /// Statistics of the last step().
  const StepStats& last_step_stats() const { return stats_; }
  /// Whether step() measures the per-type violation at its end (one extra pass over the constraints; off by default).
  void set_measure_violation(bool on) { measure_violation_ = on; }

  /// Simulated time in seconds: params().dt per step() (drives volume pressure schedules).
  double time() const { return time_; }
  /// Sets the simulated time in seconds (finite), e.g. to step a copy of another world from where it is.
  void set_time(double seconds);

  /// Number of particles.
  Index num_particles() const { return Index(x_.cols()); }
  /// Positions, 3×N (no copy). Writing through the mutable map is allowed between steps.
  Eigen::Map<const Positions> positions() const { return {x_.data(), 3, x_.cols()}; }
  Eigen::Map<Positions> positions() { return {x_.data(), 3, x_.cols()}; }  ///< mutable positions
  /// Velocities, 3×N (no copy).
  Eigen::Map<const Positions> velocities() const { return {v_.data(), 3, v_.cols()}; }
  Eigen::Map<Positions> velocities() { return {v_.data(), 3, v_.cols()}; }  ///< mutable velocities
  /// Inverse masses, N (0 = pinned).
  Eigen::Map<const VectorX<Real>> inverse_masses() const { return {w_.data(), w_.size()}; }

  /// The persistent constraints, one array per type, in solver order.
  const ConstraintArrays<Real>& constraints() const { return constraints_; }
  // Temporary shim (branch io) of the engine rewrite's accessors, over ConstraintArrays; the merge uses the real ones.
  /// The constraints of built-in type C (StretchConstraint<Real>, AnchorConstraint<Real>, BendingConstraint<Real>,
  /// AreaConstraint<Real>), in insertion order.
  template <class C> const std::vector<C>& constraints() const {
    if constexpr (std::is_same_v<C, StretchConstraint<Real>>) return constraints_.stretch;
    else if constexpr (std::is_same_v<C, AnchorConstraint<Real>>) return constraints_.anchor;
    else if constexpr (std::is_same_v<C, BendingConstraint<Real>>) return constraints_.bending;
    else {
      static_assert(std::is_same_v<C, AreaConstraint<Real>>, "not a built-in fixed-arity constraint type");
      return constraints_.area;
    }
  }
  /// The volume constraints with the triangles they span.
  const VolumeConstraints<Real>& volumes() const { return constraints_.volume; }
  /// The stiffness of each constraint set, indexed by the constraints' `set`.
  std::span<const Stiffness> constraint_sets() const { return constraints_.sets; }
  /// Number of persistent constraints of all built-in types.
  std::size_t num_constraints() const { return constraints_.size(); }
  /// The colliders.
  const Colliders<Real>& colliders() const { return colliders_; }
  /// Collision constraints generated by the last sub-step (for inspection and error measures).
  const std::vector<CollisionConstraint<Real>>& last_collisions() const { return collisions_; }

private:
  void check_particle(Index i, const char* item, std::size_t index) const;  // throws naming "item index"
  void check_set(Index set, const char* item, std::size_t index) const;
  void substep(Real h, double time, const Real* forces);
  void ensure_colored();
  void advance(const Real* forces);
  void measure_violation();
  template <class C> void erase(std::vector<C>& items, ColoredArray<C>& colored, std::span<const Index> indices,
                                const char* what);

  // Runtime state.
  Positions x_;      ///< positions
  Positions v_;      ///< velocities
  // Model.
  VectorX<Real> w_;  ///< inverse masses
  ConstraintArrays<Real> constraints_;
  Colliders<Real> colliders_;
  StepParams<Real> params_;
  double time_ = 0.0;  ///< simulated time
  // Per-step scratch, kept to avoid reallocation.
  Positions p_;      ///< predicted positions
  std::vector<CollisionConstraint<Real>> collisions_;
  Multipliers<Real> lambda_;
  VolumeScratch<Real> volume_scratch_;  ///< serial solver: volume targets and gradients
  std::vector<SolveCoefficients<Real>> coeff_;
  // Colored and Jacobi solvers: the colored copy of the constraints, rebuilt when constraints or pins change.
  ColoredSolver<Real> colored_;
  CustomTypes<Real> custom_;  ///< user-defined constraint types
  ForceCallback force_callback_;
  Positions callback_forces_;  ///< scratch filled by the force callback
  Positions rollback_x_, rollback_v_;  ///< state at the start of a step with a callback and sub-steps (restored if it throws)
  StepStats stats_;
  bool measure_violation_ = false;
  coloring::Options coloring_;
  ParallelConfig parallel_;
  PartitionerPool particle_partitioners_;
};

template <class Real> template <class C> Index World<Real>::add_custom(const C& c) {
  static_assert(C::kArity >= 1, "a user-defined constraint type needs kArity >= 1");
  const std::size_t index = custom_.template find<C>() ? custom_.template find<C>()->items.size() : 0;
  const char* item = "add_custom: constraint";
  for (int i = 0; i < C::kArity; ++i) {
    check_particle(c.particles[i], item, index);
    for (int j = 0; j < i; ++j)
      if (c.particles[i] == c.particles[j])
        throw Error(std::string("add_custom: ") + C::kName + " constraint " + std::to_string(index) + ": names particle " +
                    std::to_string(c.particles[i]) + " twice");
  }
  check_set(c.set, item, index);
  custom_.template of<C>().items.push_back(c);
  return Index(index);
}

extern template class World<float>;
extern template class World<double>;

}  // namespace pbd
