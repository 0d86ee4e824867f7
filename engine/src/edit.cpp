// World: adding, changing and removing particles, constraints and colliders (each validated first, so a bad call
// throws pbd::Error naming the offending item and leaves the world unchanged), parameters, and validate().
#include "pbd/world.hpp"

#include "step_undo.hpp"

#include "pbd/checks.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/closed_mesh.hpp"
#include "solve/hierarchy.hpp"
#include "solve/schedule.hpp"
#include "fibers.hpp"
#include "tear.hpp"
#include "tear_cells.hpp"

#include <limits>

#include <pbd/graph_coloring/validate.hpp>

#include <cmath>

namespace pbd {
namespace {

// The input checks live in pbd/checks.hpp (exported: pbd::io's DescriptionBuilder runs the same ones).
template <class Real> bool finite(const Vec3<Real>& v) { return v.allFinite(); }
template <class Real> Real inverse_mass(Real mass) { return inverse_mass_of(mass); }

}  // namespace

template <class Real> void World<Real>::check_particle(Index i, const char* item, std::size_t index) const {
  if (i >= num_particles()) detail::fail_particle_index(detail::message(item, " ", index), i, num_particles());
}

template <class Real> void World<Real>::check_set(Index set, const char* item, std::size_t index) const {
  if (set >= model_.sets.size()) detail::fail_set_index(detail::message(item, " ", index), set, model_.sets.size());
  if (model_.sets[set].mode == StiffnessMode::material)  // only fibers and tet fibers take a curve (checked_constraint)
    throw Error(detail::message(item, " ", index, ": set ", set,
                                " has a stress-strain curve, which only fibers and tet fibers take"));
}

// ---- particles ----

template <class Real> Index World<Real>::add_particle(const Vec& position, Real mass, const Vec& velocity) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  const Index i = num_particles();
  if (!finite(position)) throw Error(detail::message("add_particle: particle ", i, ": position is not finite"));
  if (!finite(velocity)) throw Error(detail::message("add_particle: particle ", i, ": velocity is not finite"));
  check_mass(mass, "add_particle", i);
  state_.x.conservativeResize(3, i + 1);
  state_.v.conservativeResize(3, i + 1);
  model_.inverse_mass.conservativeResize(i + 1);
  state_.x.col(i) = position;
  state_.v.col(i) = velocity;
  model_.inverse_mass[i] = inverse_mass(mass);
  return i;
}

template <class Real> Index World<Real>::add_particles(const Positions& positions, const VectorX<Real>& masses) {
  check_particles(positions, masses, "add_particles", num_particles());
  VectorX<Real> w(masses.size());
  for (Eigen::Index j = 0; j < positions.cols(); ++j) w[j] = inverse_mass(masses[j]);
  return add_particles_by_inverse_mass(positions, w);
}

template <class Real>
Index World<Real>::add_particles_by_inverse_mass(const Positions& positions, const VectorX<Real>& w) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  const Index first = num_particles();
  const char* fn = "add_particles_by_inverse_mass";
  if (positions.cols() != w.size())
    throw Error(detail::message(fn, ": ", positions.cols(), " positions but ", w.size(), " inverse masses"));
  for (Eigen::Index j = 0; j < positions.cols(); ++j) {
    if (!finite<Real>(positions.col(j)))
      throw Error(detail::message(fn, ": particle ", first + j, ": position is not finite"));
    // A subnormal inverse mass is a mass beyond what Real holds (check_mass): 0 pins, anything else is normal.
    if (!std::isfinite(w[j]) || !(w[j] == Real(0) || w[j] >= std::numeric_limits<Real>::min()))
      throw Error(detail::message(fn, ": particle ", first + j, ": inverse mass must be 0 (pinned) or a finite normal "
                                  "number > 0, got ", w[j]));
  }
  const Eigen::Index n = first + positions.cols();
  state_.x.conservativeResize(3, n);
  state_.v.conservativeResize(3, n);
  model_.inverse_mass.conservativeResize(n);
  state_.x.rightCols(positions.cols()) = positions;
  state_.v.rightCols(positions.cols()).setZero();
  model_.inverse_mass.tail(w.size()) = w;
  return first;
}

template <class Real> void World<Real>::set_mass(Index particle, Real mass) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  check_particle(particle, "set_mass: particle", particle);
  check_mass(mass, "set_mass", particle);
  if ((model_.inverse_mass[particle] == Real(0)) != (inverse_mass(mass) == Real(0)))
    model_.colors_current = false;  // pins changed: so did the conflicts
  model_.inverse_mass[particle] = inverse_mass(mass);
}

template <class Real> void World<Real>::remove_particle(Index particle) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  check_particle(particle, "remove_particle: particle", particle);
  for (Index p : model_.volume.table.particles)
    if (p == particle)
      throw Error(detail::message("remove_particle: particle ", particle,
                                  " belongs to a volume constraint; volume meshes cannot lose particles"));
  detail::for_each_type(model_, [&](detail::TypeStore<Real>& type, std::size_t) { type.erase_touching(particle); });
  model_.inverse_mass[particle] = Real(0);  // pinned: never moves, never collides
  state_.v.col(particle).setZero();
  model_.colors_current = false;  // a particle became pinned: conflicts changed
}

// ---- constraints ----

template <class Real> Index World<Real>::add_constraint_set(const Stiffness& stiffness) {
  check_stiffness(stiffness, detail::message("add_constraint_set: set ", model_.sets.size()));
  model_.sets.push_back(stiffness);
  return Index(model_.sets.size() - 1);
}

// Each add_<type> is add<C> with the rest value given or measured (the checks: checked_constraint, checks.hpp).
template <class Real> Index World<Real>::add_stretch(Index a, Index b, Index set, std::optional<Real> rest) {
  return add(StretchConstraint<Real>{{a, b}, set, rest.value_or(Real(0))}, rest ? kAllFields : 0);
}

template <class Real> Index World<Real>::add_anchor(Index particle, Index set, std::optional<Vec> target) {
  return add(AnchorConstraint<Real>{{particle}, set, target.value_or(Vec::Zero())}, target ? kAllFields : 0);
}

template <class Real>
Index World<Real>::add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<Real> rest) {
  return add(BendingConstraint<Real>{{p1, p2, p3, p4}, set, rest.value_or(Real(0))}, rest ? kAllFields : 0);
}

template <class Real> Index World<Real>::add_area(Index a, Index b, Index c, Index set, std::optional<Real> rest) {
  return add(AreaConstraint<Real>{{a, b, c}, set, rest.value_or(Real(0))}, rest ? kAllFields : 0);
}

template <class Real> Index World<Real>::add_tethers(std::span<const Index> body, const TetherOptions& options) {
  check_tether_request(body, std::size_t(num_particles()), options, "add_tethers");
  const auto anchors = model_.template store<AnchorConstraint<Real>>().in_insertion_order();
  const auto stretch = model_.template store<StretchConstraint<Real>>().in_insertion_order();
  const TetherInputs<Real> in{body, &state_.x, &model_.inverse_mass, anchors, stretch};
  const Index set = Index(model_.sets.size());  // the set made below, if any tether is made
  const std::vector<TetherConstraint<Real>> tethers = plan_tethers(in, options, set);
  if (tethers.empty()) return 0;
  add_constraint_set(Stiffness::xpbd_compliance(options.compliance));
  model_.template store<TetherConstraint<Real>>().items.reserve(tethers.size());
  for (const auto& t : tethers) add(t);
  return Index(tethers.size());
}

template <class Real> template <class C> Index World<Real>::add(const C& constraint, FieldMask given) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  auto& store = model_.template store<C>();
  const std::size_t index = store.size();
  store.append(checked_constraint(constraint, given, state_.x, std::span<const Stiffness>(model_.sets), index));
  return Index(index);
}

template <class Real> template <class C> void World<Real>::remove_constraints(std::span<const Index> indices) {
  remove<C>(indices, detail::message("remove_", C::kName).c_str());
}

template <class Real>
Index World<Real>::add_volume(std::span<const std::array<Index, 3>> triangles, Index set,
                              const PressureSchedule& pressure, std::optional<Real> rest) {
  ++model_.edits;
  auto& table = model_.volume.table;
  const char* item = "add_volume: volume constraint";
  const std::size_t index = table.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_set(set, item, index);
  const Real r = checked_rest_volume<Real>(triangles, state_.x, pressure, rest, what());
  table.add(triangles, set, r, pressure);
  return Index(index);
}

template <class Real>
template <class C>
void World<Real>::remove(std::span<const Index> indices, const char* what, bool lay_out) {
  ++model_.edits;  // free bodies are found again (free_bodies.hpp)
  auto& store = model_.template store<C>();
  std::vector<std::uint8_t> drop(store.size(), 0);
  for (Index i : indices) {
    if (i >= store.size())
      throw Error(detail::message(what, ": constraint index ", i, " out of range (", store.size(), " constraints)"));
    if (drop[i]) throw Error(detail::message(what, ": constraint index ", i, " given twice"));
    drop[i] = 1;
  }
  if (indices.empty()) return;
  // λ follows its constraints to their new places: what the last step left there is read as forces (World::fibers).
  constexpr Index kMul = detail::kMul<C>;
  std::vector<Real>& lambda = state_.lambda[TypeIndex<C, BuiltinConstraintTypes<Real>>::value];
  const bool carry = lambda.size() == std::size_t(kMul) * store.size();
  std::vector<Real> kept;
  if (carry)
    for (Index u = 0; u < Index(store.size()); ++u)
      if (!drop[u])
        for (Index j = 0; j < kMul; ++j) kept.push_back(lambda[std::size_t(kMul) * store.stored(u) + j]);
  const bool kept_colors = detail::erase(store, drop);
  if (carry) {
    lambda.assign(kept.size(), Real(0));
    for (Index v = 0; v < Index(store.size()); ++v)
      for (Index j = 0; j < kMul; ++j) lambda[std::size_t(kMul) * store.stored(v) + j] = kept[std::size_t(kMul) * v + j];
  }
  if (!kept_colors) model_.colors_current = false;
  else if (model_.colors_current && lay_out) detail::note_layout(model_);
}

// After a step: the fibers at their rupture strain leave the model (fibers.hpp: find_breaks), reported by
// last_breaks(); removed as remove_constraints removes them, so the colors of the others are kept. The tets on a
// broken fiber's two ends break with it (tear_cells.hpp); surfaces are torn along the broken edges (tear.hpp), which
// may remove more constraints. The arrays every color walks are laid out once, after all the removals: each layout
// is a pass over the whole model.
template <class Real> void World<Real>::break_fibers(detail::StepUndo<Real>& undo) {
  breaks_.clear();
  copies_.clear();
  if (!detail::fibers_break(model_)) return;
  breaks_ = detail::find_breaks(model_, state_, std::llround(state_.time / double(params_.dt)));
  if (breaks_.empty()) return;
  undo.keep_model(model_);  // the edits change the model: a later failure puts it back (step_undo.hpp)
  apply_breaks();
}

template <class Real> void World<Real>::apply_breaks() {
  detail::for_each_store(model_.stores, [&](const auto& st, auto) {  // the broken ones, type by type
    using C = typename std::decay_t<decltype(st)>::value_type;
    if constexpr (takes_material<C>()) {
      std::vector<Index> gone;
      for (const FiberBreak& b : breaks_)
        if (std::string_view(b.type) == C::kName) gone.push_back(b.fiber);
      if (!gone.empty()) remove<C>(gone, "break fibers", false);
    }
  });
  // Per built-in type, the constraints a tear takes (user indices, ascending), laid out later.
  auto remove_torn = [&](const std::array<std::vector<Index>, kNumBuiltinTypes>& torn_ones) {
    detail::for_each_store(model_.stores, [&](const auto& st, auto t) {
      using C = typename std::decay_t<decltype(st)>::value_type;
      const std::vector<Index>& r = torn_ones[decltype(t)::value];
      if (!r.empty()) remove<C>(r, "tear", false);
    });
  };
  remove_torn(detail::cells_on_broken_fibers(model_, breaks_));
  bool torn = false;
  if (!model_.surfaces.empty()) {
    detail::TearResult tear = detail::tear_surfaces(model_, state_, breaks_);
    torn = tear.changed();
    copies_ = std::move(tear.copies);
    if (torn) {
      ++model_.edits;  // free bodies, the hierarchy: found again
      remove_torn(tear.remove);
    }
  }
  if (!model_.colors_current) return;
  if (torn) detail::lay_out_after_tear(model_);
  else detail::note_layout(model_);
}

template <class Real>
Index World<Real>::add_surface(std::span<const std::array<Index, 3>> triangles,
                               std::span<const std::array<Index, 2>> cut) {
  check_surface(triangles, cut, std::size_t(num_particles()), "add_surface");
  detail::Surface s{{triangles.begin(), triangles.end()}, {}};
  for (const auto& e : cut) s.cut.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
  std::sort(s.cut.begin(), s.cut.end());
  s.cut.erase(std::unique(s.cut.begin(), s.cut.end()), s.cut.end());
  model_.surfaces.push_back(std::move(s));
  return Index(model_.surfaces.size() - 1);
}

template <class Real> std::size_t World<Real>::num_constraints() const {
  std::size_t n = model_.volume.table.size();
  detail::for_each_type(model_, [&](const detail::TypeStore<Real>& type, std::size_t) { n += type.size(); });
  return n;
}

// ---- colliders ----

template <class Real> void World<Real>::add_plane(const Vec& normal, Real offset, const ContactMaterial<Real>& material) {
  auto& planes = model_.colliders.planes;
  const Real len = check_plane(normal, offset, material, detail::message("add_plane: plane ", planes.size()));
  planes.push_back({normal / len, offset / len, material});
}

template <class Real> void World<Real>::add_sphere(const Vec& center, Real radius, const ContactMaterial<Real>& material) {
  auto& spheres = model_.colliders.spheres;
  check_sphere(center, radius, material, detail::message("add_sphere: sphere ", spheres.size()));
  spheres.push_back({center, radius, material});
}

template <class Real> Index World<Real>::add_contact_body(const ContactBody<Real>& body) {
  auto& bodies = model_.contact.bodies;
  const std::string what = detail::message("add_contact_body: body ", bodies.size());
  check_contact_body<Real>(body, num_particles(), bodies, what);
  check_contact_reach<Real>(body, state_.x, params_.collision_margin, what);
  bodies.push_back(body);
  model_.contact.cooked = false;
  return Index(bodies.size() - 1);
}

// ---- parameters and coloring ----

template <class Real> void World<Real>::set_params(const StepParams<Real>& p) {
  check_params(p);
  if (p.collision_margin != params_.collision_margin)  // the bodies' reach grows with the margin
    for (std::size_t b = 0; b < model_.contact.bodies.size(); ++b)
      check_contact_reach<Real>(model_.contact.bodies[b], state_.x, p.collision_margin,
                                detail::message("set_params: contact body ", b));
  if (!(p.chebyshev == params_.chebyshev)) state_.chebyshev_rho = Real(0);  // a measured ρ holds for its settings
  params_ = p;
}

template <class Real> void World<Real>::set_time(double seconds) {
  if (!std::isfinite(seconds)) throw Error(detail::message("set_time: time must be finite, got ", seconds));
  state_.time = seconds;
}

template <class Real> void World<Real>::set_coloring(const coloring::Options& options) {
  model_.coloring = options;
  model_.colors_current = false;
}

template <class Real> void World<Real>::set_blocking(const BlockOptions& options) {
  if (options.constraints_per_block == 0) throw Error("set_blocking: constraints_per_block must be >= 1");
  model_.blocking = options;
  if (model_.layout == detail::Layout::blocks) model_.colors_current = false;
}

template <class Real>
std::vector<coloring::NamedStats> World<Real>::color_statistics(const coloring::Options& options) const {
  const std::vector<std::uint8_t> fixed = detail::pinned_flags(model_.inverse_mass);
  std::vector<coloring::NamedStats> rows;
  detail::for_each_type(model_, [&](const detail::TypeStore<Real>& type, std::size_t) {
    if (type.empty()) return;  // a type the world does not use is not colored at all
    rows.push_back({type.name(), type.color_statistics(fixed, options)});
  });
  return rows;
}

// ---- validation ----

template <class Real> void World<Real>::validate() const {
  const Index n = num_particles();
  if (state_.v.cols() != n || model_.inverse_mass.size() != n)
    throw Error("validate: positions, velocities and inverse masses disagree on the particle count");
  for (std::size_t s = 0; s < model_.surfaces.size(); ++s) {  // tears rename particles: each must still exist
    check_surface(model_.surfaces[s].triangles, model_.surfaces[s].cut, std::size_t(n),
                  detail::message("validate: surface ", s).c_str());
    if (!std::is_sorted(model_.surfaces[s].cut.begin(), model_.surfaces[s].cut.end()))
      throw Error(detail::message("validate: surface ", s, ": its cut edges are not sorted"));
  }
  const std::vector<std::uint8_t> fixed =
      model_.colors_current ? model_.fixed : detail::pinned_flags(model_.inverse_mass);
  // λ is only ever written where α̃ ≠ 0: while no set is compliant, every λ is 0. (Per constraint it cannot be
  // checked here: λ keeps the last sub-step's layout until the next one resets it.)
  const bool any_compliant = std::ranges::any_of(model_.sets, [](const Stiffness& st) {
    return (st.mode == StiffnessMode::xpbd && st.compliance != 0.0) || st.mode == StiffnessMode::material;
  });
  detail::for_each_type(model_, [&](const detail::TypeStore<Real>& type, std::size_t t) {
    const char* name = type.name();
    type.validate(fixed, n);
    // The particle cuts (a team's parts of each color): per color, kCutParts + 1 non-decreasing counts from 0 to its size.
    if (model_.colors_current && t < model_.particle_cuts.size() && !model_.particle_cuts[t].empty()) {
      const auto& cuts = model_.particle_cuts[t];
      const std::size_t per = detail::kCutParts + 1;
      if (cuts.size() != std::size_t(type.num_colors()) * per)
        throw Error(detail::message("validate: ", name, " store: ", cuts.size(), " particle cuts for ", type.num_colors(), " colors"));
      for (Index c = 0; c < type.num_colors(); ++c) {
        const Index* row = cuts.data() + c * per;
        if (row[0] != 0 || row[per - 1] != type.color_begin(c + 1) - type.color_begin(c) || !std::is_sorted(row, row + per))
          throw Error(detail::message("validate: ", name, " color ", c, ": particle cuts do not rise from 0 to its size"));
      }
    }
    if (!any_compliant && t < state_.lambda.size())
      for (std::size_t k = 0; k < state_.lambda[t].size(); ++k)
        if (state_.lambda[t][k] != Real(0))
          throw Error(detail::message("validate: ", name, " λ ", k, " is ", state_.lambda[t][k],
                                      " though no set is compliant"));
  });
  const auto& v = model_.volume;
  if (!v.order.empty()) {
    std::vector<std::uint8_t> seen(v.table.size(), 0);
    for (Index i : v.order) {
      if (i >= v.table.size() || seen[i]) throw Error("validate: volume order is not a permutation");
      seen[i] = 1;
    }
  }
  if (model_.hierarchy)  // the cooked hierarchy, while it matches the model
    if (model_.hierarchy->edits == model_.edits)
      if (const std::string why = detail::validate_hierarchy(*model_.hierarchy, model_); !why.empty())
        throw Error("validate: " + why);
  // Each ring corner's row (volume.hpp: ring_rows) is the row of that corner's particle in its constraint.
  if (v.table.ring_rows.size() != v.table.ring.size())
    throw Error(detail::message("validate: ", v.table.ring_rows.size(), " volume ring rows for ", v.table.ring.size(),
                                " ring corners"));
  for (const auto& c : v.table.items)
    for (Index row = c.row_begin; row < c.row_end; ++row)
      for (Index k = v.table.ring_offsets[row]; k < v.table.ring_offsets[row + 1]; ++k)
        for (int j = 0; j < 2; ++j) {
          const Index r = v.table.ring_rows[k][j];
          if (r >= c.row_end - c.row_begin || v.table.particles[c.row_begin + r] != v.table.ring[k][j])
            throw Error(detail::message("validate: volume ring corner ", k, " names row ", r,
                                        ", not the row of particle ", v.table.ring[k][j]));
        }
}

// The generic per-type members for every type of the list: taking their addresses instantiates them here, so a new
// type in constraint_types.hpp needs no line in this file. (remove<C> below is listed by hand for the hand-written
// remove_stretch etc. of world.hpp; a new type is removed by remove_constraints<C>.)
template <class Real, class... C> auto members_of_each_type(std::tuple<C...>*) {
  return std::tuple{std::pair{&World<Real>::template add<C>, &World<Real>::template remove_constraints<C>}...};
}

// The members defined in this file (the class itself is instantiated in world.cpp).
#define PBD_EDIT_INSTANTIATE(Real)                                                                   \
  template void World<Real>::check_particle(Index, const char*, std::size_t) const;                \
  template void World<Real>::check_set(Index, const char*, std::size_t) const;                     \
  template Index World<Real>::add_particle(const Vec3<Real>&, Real, const Vec3<Real>&);            \
  template Index World<Real>::add_particles(const Matrix3X<Real>&, const VectorX<Real>&);          \
  template Index World<Real>::add_particles_by_inverse_mass(const Matrix3X<Real>&, const VectorX<Real>&); \
  template void World<Real>::set_mass(Index, Real);                                                \
  template void World<Real>::remove_particle(Index);                                               \
  template Index World<Real>::add_constraint_set(const Stiffness&);                                \
  template Index World<Real>::add_stretch(Index, Index, Index, std::optional<Real>);               \
  template Index World<Real>::add_anchor(Index, Index, std::optional<Vec3<Real>>);                 \
  template Index World<Real>::add_bending(Index, Index, Index, Index, Index, std::optional<Real>);  \
  template Index World<Real>::add_area(Index, Index, Index, Index, std::optional<Real>);            \
  template Index World<Real>::add_tethers(std::span<const Index>, const TetherOptions&);          \
  template Index World<Real>::add_volume(std::span<const std::array<Index, 3>>, Index, const PressureSchedule&, \
                                         std::optional<Real>);                                      \
  template std::size_t World<Real>::num_constraints() const;                                       \
  template Index World<Real>::add_surface(std::span<const std::array<Index, 3>>,                   \
                                          std::span<const std::array<Index, 2>>);                  \
  template void World<Real>::add_plane(const Vec3<Real>&, Real, const ContactMaterial<Real>&);     \
  template void World<Real>::add_sphere(const Vec3<Real>&, Real, const ContactMaterial<Real>&);    \
  template Index World<Real>::add_contact_body(const ContactBody<Real>&);                           \
  template void World<Real>::set_params(const StepParams<Real>&);                                  \
  template void World<Real>::set_coloring(const coloring::Options&);                               \
  template void World<Real>::set_blocking(const BlockOptions&);                                     \
  template void World<Real>::set_time(double);                               \
  template std::vector<coloring::NamedStats> World<Real>::color_statistics(const coloring::Options&) const; \
  template void World<Real>::validate() const;                                                     \
  template void World<Real>::break_fibers(detail::StepUndo<Real>&);                                                       \
  template void World<Real>::apply_breaks();                                                       \
  template void World<Real>::remove<StretchConstraint<Real>>(std::span<const Index>, const char*, bool); \
  template void World<Real>::remove<AnchorConstraint<Real>>(std::span<const Index>, const char*, bool);  \
  template void World<Real>::remove<BendingConstraint<Real>>(std::span<const Index>, const char*, bool); \
  template void World<Real>::remove<AreaConstraint<Real>>(std::span<const Index>, const char*, bool);    \
  template auto members_of_each_type<Real>(BuiltinConstraintTypes<Real>*);
PBD_EDIT_INSTANTIATE(float)
PBD_EDIT_INSTANTIATE(double)
#undef PBD_EDIT_INSTANTIATE

}  // namespace pbd
