#pragma once
/// \file world.hpp
/// A simulated world: particles, constraints, colliders and the PBD step (Müller et al. 2006). The host API.
///
/// Typical use: add particles, constraint sets and constraints, colliders, set the step parameters, then call
/// step() as often as needed and read positions()/velocities() (Eigen maps, no copies). Every mutating call
/// validates its input first and throws pbd::Error naming the offending item, leaving the world unchanged. What a
/// step runs, in what order and in parallel how: engine/src/solve/solver.hpp.
#include "pbd/colliders.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/contacts.hpp"
#include "pbd/constraint_types.hpp"
#include "pbd/constraint_view.hpp"
#include "pbd/custom_constraints.hpp"
#include "pbd/detail/model.hpp"
#include "pbd/error.hpp"
#include "pbd/fiber_state.hpp"
#include "pbd/solver.hpp"
#include "pbd/step_params.hpp"
#include "pbd/tethers.hpp"
#include "pbd/types.hpp"

#include <pbd/graph_coloring/stats.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pbd {

namespace detail {
template <class Real> struct Scratch;
template <class Real> class StepUndo;
/// Deletes a Scratch (defined where Scratch is complete).
template <class Real> struct ScratchDeleter {
  void operator()(Scratch<Real>* s) const;  ///< deletes s
};
}  // namespace detail

/// Particles, constraints and colliders of one simulation, in precision Real (float or double).
template <class Real> class World {
public:
  using Scalar = Real;               ///< float or double
  using Vec = Vec3<Real>;            ///< 3-vector
  using Positions = Matrix3X<Real>;  ///< 3×N particle data

  /// Mass value meaning "pinned": inverse mass 0, never moved by the solver nor by forces. A pinned particle moves
  /// at its own velocity (0 unless set: a host or a scene's grip sets one to pull at a constant speed).
  static constexpr Real kPinned = std::numeric_limits<Real>::infinity();

  World();                                   ///< an empty world with default parameters
  World(const World& other);                 ///< a copy (its per-step scratch starts empty)
  World& operator=(const World& other);      ///< a copy (its per-step scratch starts empty)
  World(World&&) noexcept;                   ///< move
  World& operator=(World&&) noexcept;        ///< move
  ~World();                                  ///< destroys the world

  // ---- particles ----
  /// Adds a particle; mass in kg, > 0 (kPinned for a fixed particle). Returns its index (indices never change).
  Index add_particle(const Vec& position, Real mass, const Vec& velocity = Vec::Zero());
  /// Adds many particles at once (all validated before any is added); returns the index of the first.
  Index add_particles(const Positions& positions, const VectorX<Real>& masses);
  /// As add_particles, given inverse masses in 1/kg (finite, ≥ 0; 0 = pinned), e.g. computed in another precision.
  Index add_particles_by_inverse_mass(const Positions& positions, const VectorX<Real>& inverse_masses);
  /// Sets a particle's mass in kg (kPinned pins it).
  void set_mass(Index particle, Real mass);
  /// Removes a particle from the simulation: every constraint on it is removed, it is pinned where it is and never
  /// moves or collides again. Its index stays valid (indices never shift). An error if a volume constraint uses it.
  void remove_particle(Index particle);

  // ---- constraints ----
  /// Adds a constraint set with its own stiffness; constraints name it by the returned id.
  Index add_constraint_set(const Stiffness& stiffness);
  /// Adds a stretch constraint between a and b; rest distance in m, default: their current distance.
  Index add_stretch(Index a, Index b, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds an anchor pulling `particle` to `target` (default: its current position).
  Index add_anchor(Index particle, Index set, std::optional<Vec> target = std::nullopt);
  /// Adds a fiber (constraints/fiber.hpp) between a and b; rest length in m, default: their current distance. In a
  /// set with a stress–strain curve (Stiffness::fiber) it follows the curve, yields and breaks.
  Index add_fiber(Index a, Index b, Index set, std::optional<Real> rest = std::nullopt) {
    return add(FiberConstraint<Real>{{a, b}, set, rest.value_or(Real(0)), Real(0)}, rest ? FieldMask(3) : FieldMask(2));
  }
  /// Adds a dihedral bending constraint on triangles (p1, p2, p3) and (p1, p2, p4) sharing edge p1–p2; the rest
  /// angle in radians defaults to the current one (an error if a triangle is degenerate there).
  Index add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds a triangle area constraint; the rest area in m² defaults to the current one.
  Index add_area(Index a, Index b, Index c, Index set, std::optional<Real> rest = std::nullopt);
  /// Adds a volume constraint on a closed, consistently oriented mesh (counter-clockwise seen from outside); the
  /// target is pressure.at(time()) × rest, rest in the 6V unit of constraints/volume.hpp (default: the current one).
  /// Throws naming the first bad edge if the mesh is open, non-manifold or inconsistently oriented, and rejects a
  /// flat or inside-out mesh.
  Index add_volume(std::span<const std::array<Index, 3>> triangles, Index set, const PressureSchedule& pressure = {},
                   std::optional<Real> rest = std::nullopt);
  /// Adds long-range attachments (pbd/tethers.hpp) to the particles `body` (each once): every one with mass that is
  /// not anchored gets tethers to the body's pinned or anchored particles as `options` says, measured at the current
  /// positions, in a new constraint set of XPBD compliance options.compliance. Returns how many were added, the last
  /// ones of constraints<TetherConstraint<Real>>(); 0 and no set when the body has no pinned or anchored particle.
  Index add_tethers(std::span<const Index> body, const TetherOptions& options = {});
  /// Adds a constraint of a user-defined type C (custom_constraints.hpp says what C provides); it is stored,
  /// colored and projected like the built-in types, after them. Returns its index among the constraints of type C.
  template <class C> Index add_custom(const C& constraint);

  /// Adds a constraint of built-in type C given whole: its particles, its set and the rest values in `given` (bit i:
  /// C::fields()[i]; the others are measured at the current positions), checked as pbd/checks.hpp says.
  template <class C> Index add(const C& constraint, FieldMask given = kAllFields);
  /// As remove_stretch, for the constraints of built-in type C.
  template <class C> void remove_constraints(std::span<const Index> indices);

  /// Makes room for n constraints of built-in type C in all (a loader that knows the count adds them faster).
  template <class C> void reserve(std::size_t n) { model_.template store<C>().items.reserve(n); }

  /// Removes stretch constraints by index (each at most once; later indices move down, as with std::vector::erase).
  /// The colors of the remaining constraints are kept: nothing is recolored.
  void remove_stretch(std::span<const Index> indices) { remove<StretchConstraint<Real>>(indices, "remove_stretch"); }
  /// As remove_stretch, for anchors.
  void remove_anchor(std::span<const Index> indices) { remove<AnchorConstraint<Real>>(indices, "remove_anchor"); }
  /// As remove_stretch, for bending constraints.
  void remove_bending(std::span<const Index> indices) { remove<BendingConstraint<Real>>(indices, "remove_bending"); }
  /// As remove_stretch, for area constraints.
  void remove_area(std::span<const Index> indices) { remove<AreaConstraint<Real>>(indices, "remove_area"); }

  /// The constraints of type C (built in, or user-defined) in insertion order.
  template <class C> ConstraintView<C> constraints() const {
    if constexpr (is_builtin_v<C, Real>) return ConstraintView<C>(&model_.template store<C>());
    else return ConstraintView<C>(model_.user.template find<C>());
  }
  /// The constraints of user-defined type C in insertion order (empty if none): constraints<C>().
  template <class C> ConstraintView<C> custom() const { return constraints<C>(); }
  /// The volume constraints and the meshes they span, in insertion order.
  const VolumeConstraints<Real>& volumes() const { return model_.volume.table; }
  /// The stiffness of each constraint set, by set id.
  std::span<const Stiffness> constraint_sets() const { return model_.sets; }
  /// Number of persistent constraints of every type (user-defined and volume included).
  std::size_t num_constraints() const;
  /// Calls f(constraints<C>()) for each built-in fixed-arity type, in solver order.
  template <class F> void for_each_builtin(F&& f) const {
    detail::for_each_store(model_.stores, [&](const auto& s, auto) {
      f(ConstraintView<typename std::decay_t<decltype(s)>::value_type>(&s));
    });
  }

  // ---- colliders ----
  /// Adds an infinite plane n·x ≥ offset (n is normalized; offset in m) with its surface's friction and restitution.
  void add_plane(const Vec& normal, Real offset, const ContactMaterial<Real>& material = {});
  /// Adds a solid sphere (center in m, radius in m, > 0) with its surface's friction and restitution.
  void add_sphere(const Vec& center, Real radius, const ContactMaterial<Real>& material = {});
  /// The colliders.
  const Colliders<Real>& colliders() const { return model_.colliders; }
  /// Makes particles [body.first, body.first + body.count) a contact body (contacts.hpp): they touch colliders
  /// with its radius and material, and other bodies' particles as spheres. A particle is in at most one body.
  /// Returns the body's index.
  Index add_contact_body(const ContactBody<Real>& body);
  /// The contact bodies, in the order added.
  const std::vector<ContactBody<Real>>& contact_bodies() const { return model_.contact.bodies; }
  /// Particle contacts generated by the last sub-step (for inspection and error measures), in solver order.
  std::span<const ParticleContact<Real>> last_particle_contacts() const;

  // ---- coloring ----
  /// Sets how constraints are colored for the colored and Jacobi solvers (recolors at the next step).
  void set_coloring(const coloring::Options& options);
  /// Sets how the block solver splits the particles into blocks (partitions anew at the next block step);
  /// throws pbd::Error when constraints_per_block is 0.
  void set_blocking(const BlockOptions& options);
  /// How the block solver splits the particles.
  const BlockOptions& blocking() const { return model_.blocking; }
  /// Sets how parallel loops are cut (never changes results).
  void set_parallel_config(const ParallelConfig& config) { parallel_ = config; }
  /// Lays out now if needed for the current solver and gives type C's groups (colors; for the block solver the
  /// blocks' interiors first, then the boundary colors).
  template <class C> ConstraintColors<C> colors();
  /// Groups of the persistent constraints as the current solver runs them (lays out now if needed): colors, or for
  /// the block solver each type's blocks plus its boundary colors.
  Index num_colors();
  /// Blocks of the block solver's partition (0 until a block step or num_colors() under Solver::block).
  Index num_blocks() const { return model_.layout == detail::Layout::blocks ? model_.num_blocks : 0; }
  /// Colors each constraint type's conflict graph anew with `options`, checks each coloring, and returns its
  /// statistics per type (kName), without changing the world's own colors.
  std::vector<coloring::NamedStats> color_statistics(const coloring::Options& options) const;

  // ---- stepping ----
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
  /// The fibers and tet fibers the last step() broke (empty if none), fibers first, each type in the order of
  /// their indices just before: each reached its set's rupture strain at the step's end and has left the model (as
  /// remove_constraints removes, so later ones' indices moved down). The constraints of a type that breaks with
  /// fibers (the tet types: constraints/traits.hpp) holding both ends of a broken fiber, or all four corners of a
  /// broken tet fiber, left with it.
  std::span<const FiberBreak> last_breaks() const { return breaks_; }
  /// Adds a surface that tears (engine/src/tear.hpp): when fibers on its edges break, the particles along the cut
  /// are copied, one copy for each side, so that the surface separates; v's mass is split between the sides by
  /// their triangle counts (momentum kept), and each constraint on a side follows its copy (a bending hinge on the
  /// cut is removed). `cut`: edges already cut (a described world's, surface_cut). Returns its index. Throws naming
  /// a triangle or edge with a particle out of range or named twice.
  Index add_surface(std::span<const std::array<Index, 3>> triangles, std::span<const std::array<Index, 2>> cut = {});
  /// The triangles of surface s as they are now (particles renamed where it tore).
  std::span<const std::array<Index, 3>> surface(Index s) const { return model_.surfaces.at(s).triangles; }
  /// The edges of surface s that are cut (each lower particle first, sorted).
  std::span<const std::array<Index, 2>> surface_cut(Index s) const { return model_.surfaces.at(s).cut; }
  /// Number of surfaces.
  Index num_surfaces() const { return Index(model_.surfaces.size()); }
  /// The particles the last step's tears added, each with the one it copies (empty if none).
  std::span<const TornParticle> last_copies() const { return copies_; }
  /// Each fiber's strains and the tension it carries after the last step (fiber_state.hpp), in insertion order.
  std::vector<FiberReading> fibers() const { return material_readings<FiberConstraint<Real>>(); }
  /// Each constraint of type C's strains and force after the last step, in insertion order: C is a type that may
  /// follow a curve (constraints/traits.hpp: takes_material), FiberConstraint (N) or TetFiberConstraint (Pa).
  template <class C> std::vector<FiberReading> material_readings() const;
  /// Statistics of the last step().
  const StepStats& last_step_stats() const { return stats_; }
  /// Whether step() measures the per-type violation at its end (one extra pass over the constraints; off by default).
  void set_measure_violation(bool on) { measure_violation_ = on; }

  // ---- state ----
  /// Simulated time in seconds: params().dt per step() (drives volume pressure schedules).
  double time() const { return state_.time; }
  /// Sets the simulated time in seconds (finite), e.g. to step a copy of another world from where it is.
  void set_time(double seconds);
  /// Number of particles.
  Index num_particles() const { return Index(state_.x.cols()); }
  /// Positions in m, 3×N (no copy). A map stays valid across step() (its storage is reallocated only by adding
  /// particles). Writing through the mutable map is allowed between steps: the next step() first checks every
  /// position and velocity (one pass) and throws pbd::Error naming the first non-finite one, leaving the world
  /// unchanged. Steps that follow no mutable map skip that pass.
  Eigen::Map<const Positions> positions() const { return {state_.x.data(), 3, state_.x.cols()}; }
  Eigen::Map<Positions> positions() {  ///< mutable positions (the next step() checks that they are finite)
    host_wrote_ = true;
    return {state_.x.data(), 3, state_.x.cols()};
  }
  /// Velocities in m/s, 3×N (no copy); a write through the mutable map is checked as positions' are.
  Eigen::Map<const Positions> velocities() const { return {state_.v.data(), 3, state_.v.cols()}; }
  Eigen::Map<Positions> velocities() {  ///< mutable velocities (the next step() checks that they are finite)
    host_wrote_ = true;
    return {state_.v.data(), 3, state_.v.cols()};
  }
  /// Inverse masses in 1/kg, N (0 = pinned).
  Eigen::Map<const VectorX<Real>> inverse_masses() const {
    return {model_.inverse_mass.data(), model_.inverse_mass.size()};
  }
  /// Collision constraints generated by the last sub-step (for inspection and error measures), in solver order.
  std::span<const CollisionConstraint<Real>> last_collisions() const;

  /// Checks every invariant of the model (stores, color ranges, maps, no particle twice in a color, λ zero where
  /// no set is compliant); throws pbd::Error naming the first broken one. Tests call it; debug builds also assert
  /// cheap invariants as they go.
  void validate() const;

  /// The cooked model (engine internals: for benchmarks and tests that drive the solver directly).
  const detail::Model<Real>& model() const { return model_; }

private:
  void check_particle(Index i, const char* item, std::size_t index) const;  // throws naming "item index"
  void check_set(Index set, const char* item, std::size_t index) const;
  // Removes the constraints of type C at `indices` (user indices); lay_out false leaves the colors' arrays to the
  // caller, which lays them out once after several removals (break_fibers).
  template <class C> void remove(std::span<const Index> indices, const char* what, bool lay_out = true);
  void ensure_colored();
  void break_fibers(detail::StepUndo<Real>& undo);  // the breaks and tears after a step (the model kept in undo)
  void apply_breaks();  // break_fibers' edits of the model, for the breaks it found
  void advance(const Real* forces);                        // a step, undone if it fails (step_undo.hpp)
  void cook_for_step(detail::Scratch<Real>& k);             // the caches a step reads, before it changes anything
  void take_step(detail::Scratch<Real>& k, const Real* forces, detail::StepUndo<Real>& undo);  // the step itself
  void check_state_finite() const;  // throws naming the first particle with a non-finite position or velocity
  void check_stepped_state(long long step) const;  // the same after step number `step`
  void check_volumes_not_inverted(long long step) const;  // throws naming a volume whose mesh a step turned inside out
  detail::Scratch<Real>& scratch();

  detail::Model<Real> model_;   // cooked model: particles' inverse masses, constraints with their colors, colliders
  detail::State<Real> state_;   // x, v, time, λ
  std::unique_ptr<detail::Scratch<Real>, detail::ScratchDeleter<Real>> scratch_;  // per-step scratch (made on demand)
  StepParams<Real> params_;
  StepStats stats_;
  std::vector<FiberBreak> breaks_;  // the fibers the last step broke
  std::vector<TornParticle> copies_;  // the particles its tears added
  bool measure_violation_ = false;
  bool host_wrote_ = false;     // a mutable map of positions or velocities was handed out since the last check
  ParallelConfig parallel_;
  ForceCallback force_callback_;
};

template <class Real> template <class C> Index World<Real>::add_custom(const C& c) {
  static_assert(UserConstraint<C, Real>, "a user-defined constraint type must provide what custom_constraints.hpp lists");
  static_assert(!is_builtin_v<C, Real>, "add_custom is for user-defined types; use add_stretch etc. for built-in ones");
  const auto* s = model_.user.template find<C>();
  const std::size_t index = s ? s->size() : 0;
  const char* item = "add_custom: constraint";
  for (int i = 0; i < C::kArity; ++i) {
    check_particle(c.particles[i], item, index);
    for (int j = 0; j < i; ++j)
      if (c.particles[i] == c.particles[j])
        throw Error(std::string("add_custom: ") + C::kName + " constraint " + std::to_string(index) + ": names particle " +
                    std::to_string(c.particles[i]) + " twice");
  }
  check_set(c.set, item, index);
  const bool first_of_type = s == nullptr;
  model_.user.template of<C>().append(c);
  ++model_.edits;
  if (first_of_type) {
    state_.lambda.emplace_back();  // λ arrays follow the types' order (for_each_type)
    model_.colors_current = false;  // a new type: colored with everything at the next colored step
  }
  return Index(index);
}

template <class Real> template <class C> ConstraintColors<C> World<Real>::colors() {
  ensure_colored();
  const detail::Store<C>* s;
  if constexpr (is_builtin_v<C, Real>) s = &model_.template store<C>();
  else s = model_.user.template find<C>();
  if (!s) return {};
  return {s->items, s->num_colors(), s->color, s->slot, s->offsets};
}

extern template class World<float>;
extern template class World<double>;

}  // namespace pbd
