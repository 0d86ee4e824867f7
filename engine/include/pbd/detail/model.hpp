#pragma once
/// \file detail/model.hpp
/// The cooked model of a world and its runtime state (engine internals, held by World; a host reads them through
/// World's accessors). Jolt's soft bodies keep the same three kinds of data apart (shared settings / motion
/// properties / update context): the Model is what the scene describes (particles' inverse masses, constraint sets,
/// one store per constraint type with its colors, volumes, colliders) plus what is cooked from it for the solvers;
/// the State is what a step advances (x, v, time, λ); per-step scratch lives in engine/src/solve/scratch.hpp.
#include "pbd/colliders.hpp"
#include "pbd/contacts.hpp"
#include "pbd/constraint_types.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/custom_constraints.hpp"
#include "pbd/detail/type_store.hpp"
#include "pbd/solver.hpp"
#include "pbd/stiffness.hpp"

#include <array>
#include <memory>
#include <tuple>
#include <vector>

namespace pbd::detail {

/// std::tuple<TypedStore<C, Real>...> for a tuple of built-in constraint types.
template <class Types, class Real> struct StoresOf;
template <class... Cs, class Real> struct StoresOf<std::tuple<Cs...>, Real> {
  using type = std::tuple<TypedStore<Cs, Real, false>...>;
};

/// Calls f(store, index) for each built-in type's Store<C>, in solver order (index: position in
/// BuiltinConstraintTypes): for what needs the type C itself. Every pass over all the types, built-in and
/// user-defined, uses for_each_type instead.
template <class Stores, class F> void for_each_store(Stores& stores, F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::get<I>(stores).store, std::integral_constant<std::size_t, I>{}), ...);
  }(std::make_index_sequence<std::tuple_size_v<std::remove_const_t<Stores>>>{});
}

/// Volume constraints (each spans a whole mesh) and the order the colored solvers project them in.
template <class Real> struct VolumeStore {
  VolumeConstraints<Real> table;  ///< the constraints and the meshes they span, in insertion order
  std::vector<Index> order;       ///< volume indices color by color (graph_coloring on their particles)
  std::vector<Index> offsets;     ///< color c is order[offsets[c], offsets[c + 1])
  Index num_colors() const { return offsets.empty() ? 0 : Index(offsets.size() - 1); }  ///< colors laid out
};

/// The hierarchy of the stretch constraints (engine/src/solve/hierarchy.hpp), cooked when StepParams::hierarchy is on.
template <class Real> struct HierarchyModel;

/// A surface that tears (World::add_surface): its triangles (particles renamed as it tears) and its cut edges.
struct Surface {
  std::vector<std::array<Index, 3>> triangles;  ///< as given, each particle replaced by its copy where it tore
  std::vector<std::array<Index, 2>> cut;        ///< edges (lower particle first) whose fiber broke, sorted
};

/// Particle ranges Model::particle_cuts are counted for: a team of M threads, M dividing it, cuts exactly there.
inline constexpr Index kCutParts = 64;

/// The arrangement the stores are cooked in: colors (serial_colored, colored, Jacobi) or blocks (block).
enum class Layout : std::uint8_t { colors, blocks };

/// What the scene describes, and what is cooked from it for the solvers.
template <class Real> struct Model {
  VectorX<Real> inverse_mass;                                     ///< per particle, 1/kg (0 = pinned)
  std::vector<Stiffness> sets;                                    ///< stiffness of each constraint set
  typename StoresOf<BuiltinConstraintTypes<Real>, Real>::type stores;  ///< one store per built-in type
  UserTypes<Real> user;                                          ///< one store per user-defined type, first added first
  VolumeStore<Real> volume;                                      ///< volume constraints
  Colliders<Real> colliders;                                     ///< static colliders
  ContactBodies<Real> contact;                                   ///< contact bodies (radii, materials)
  coloring::Options coloring;                                    ///< how the colored and Jacobi solvers color
  BlockOptions blocking;                                         ///< how the block solver splits the particles
  std::vector<Surface> surfaces;                                 ///< surfaces that tear along broken fibers
  std::uint64_t edits = 0;  ///< particles or constraints added, removed or (un)pinned so far: keys what is cooked

  // Cooked for the colored, Jacobi and block solvers (schedule.cpp), valid while colors_current is set.
  bool colors_current = false;         ///< every store's groups match its constraints, the pins and `layout`
  Layout layout = Layout::colors;      ///< what the stores are laid out for
  std::vector<std::uint32_t> block;    ///< block layout: each particle's block (kNoBlock: pinned, free or added since)
  Index num_blocks = 0;                ///< block layout: number of blocks (groups [0, num_blocks) of every store)
  std::vector<std::uint8_t> fixed;     ///< pinned flags the colors were made with, one per particle then
  std::vector<Index> touch_count;      ///< Jacobi: built-in and user constraints touching each particle
  /// Per type whose SIMD kernel reads it (engine/src/solve/kernels.hpp), per color: the set all its constraints
  /// share, or kMixedSets.
  std::vector<std::vector<Index>> color_sets;
  /// Colors layout, per type (for_each_type's position): for color c, entries [c·(kCutParts + 1), (c + 1)·(kCutParts
  /// + 1)); entry j counts the color's constraints whose smallest particle index is below ⌊j·n / kCutParts⌋ (n
  /// particles). A team cuts each color there (sweep.hpp), so each thread keeps one range of particles from color
  /// to color.
  std::vector<std::vector<Index>> particle_cuts;
  /// Cooked when the hierarchy is on (solve/hierarchy.hpp: ensure_hierarchy, keyed by `edits`); never changed once
  /// built, so copies of a world may share it.
  std::shared_ptr<const HierarchyModel<Real>> hierarchy;

  /// The store of built-in type C.
  template <class C> Store<C>& store() {
    return std::get<TypeIndex<C, BuiltinConstraintTypes<Real>>::value>(stores).store;
  }
  template <class C> const Store<C>& store() const {  ///< read-only store()
    return std::get<TypeIndex<C, BuiltinConstraintTypes<Real>>::value>(stores).store;
  }
  /// Number of particles.
  Index num_particles() const { return Index(inverse_mass.size()); }
  /// Number of constraint types: the built-in ones, then the user-defined ones (for_each_type).
  std::size_t num_types() const { return kNumBuiltinTypes + user.types().size(); }
};

/// Calls f(type, t) for every constraint type of `m` (a TypeStore, type_store.hpp): the built-in ones in list order
/// (constraint_types.hpp), then the user-defined ones in the order first added, the order every sweep projects them
/// in. t is the type's position: the index of its λ array (State::lambda) and of its cooked data (particle_cuts).
/// The one way a pass visits every type.
template <class Real, class F> void for_each_type(Model<Real>& m, F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(static_cast<TypeStore<Real>&>(std::get<I>(m.stores)), I), ...);
  }(std::make_index_sequence<kNumBuiltinTypes>{});
  std::size_t t = kNumBuiltinTypes;
  for (const auto& u : m.user.types()) f(*u, t++);
}
/// for_each_type over a read-only model.
template <class Real, class F> void for_each_type(const Model<Real>& m, F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(static_cast<const TypeStore<Real>&>(std::get<I>(m.stores)), I), ...);
  }(std::make_index_sequence<kNumBuiltinTypes>{});
  std::size_t t = kNumBuiltinTypes;
  for (const auto& u : m.user.types()) f(std::as_const(*u), t++);
}

/// "The constraints of a color belong to more than one set" (Model::color_sets).
inline constexpr Index kMixedSets = ~Index(0);

/// What a step advances.
template <class Real> struct State {
  Matrix3X<Real> x;   ///< positions, m
  Matrix3X<Real> v;   ///< velocities, m/s
  double time = 0.0;  ///< simulated time, s
  /// XPBD λ per constraint type (for_each_type's position: the built-in types, then the user-defined ones), in
  /// stored order.
  std::vector<std::vector<Real>> lambda = std::vector<std::vector<Real>>(kNumBuiltinTypes);
  std::vector<Real> volume_lambda;                          ///< λ per volume constraint
  double lambda_h2 = 0.0;  ///< h² of the sub-steps whose λ the arrays hold, s² (0: no step yet): force = −λ/h²
  /// Some λ may be non-zero: a sweep since the last reset had α̃ ≠ 0 (λ changes only there, projection.hpp).
  bool lambda_dirty = true;
  /// ρ of Chebyshev acceleration measured by a sub-step (StepParams::chebyshev.rho = 0 uses it; 0: none yet). An
  /// output, kept here rather than in the parameters; World::set_params clears it when the Chebyshev settings change.
  Real chebyshev_rho = 0;
};

}  // namespace pbd::detail
