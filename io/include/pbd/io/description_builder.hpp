#pragma once
/// \file description_builder.hpp
/// A WorldDescription built item by item through World's own calls: the scene reader and the generators (add_cloth,
/// add_rope, add_grains, add_mesh) fill one without building a World<double>.
#include "pbd/checks.hpp"
#include "pbd/io/world_description.hpp"
#include "pbd/tethers.hpp"

#include <limits>
#include <optional>
#include <span>

namespace pbd {

/// Has World<double>'s add_* / set_params calls with World<double>'s checks (the engine's own, pbd/checks.hpp), error
/// messages and arithmetic: the rest values it stores are bit for bit those World<double> computes for the same
/// calls, and a bad call throws the same pbd::Error and adds nothing. tests/io/description_builder_test.cpp holds the
/// two side by side.
class DescriptionBuilder {
public:
  using Vec = Vec3<double>;           ///< 3-vector
  using Positions = Matrix3X<double>;  ///< 3×N particle data
  /// Mass value meaning "pinned": inverse mass 0.
  static constexpr double kPinned = std::numeric_limits<double>::infinity();

  /// As World::add_particles: masses > 0 or kPinned, all validated first; returns the index of the first particle.
  Index add_particles(const Positions& positions, const VectorX<double>& masses);
  /// As World::set_mass: mass in kg, > 0 (kPinned pins it).
  void set_mass(Index particle, double mass);
  /// As World::add_constraint_set.
  Index add_constraint_set(const Stiffness& stiffness);
  /// As World::add<C>: a constraint of built-in type C (in double, e.g. StretchConstraint<double>) with the rest
  /// values in `given`, the others measured at the particles' positions; returns its index among its type.
  template <class C> Index add(const C& constraint, FieldMask given = kAllFields) {
    std::vector<C>& list = d_.constraints<C>();
    list.push_back(checked_constraint(constraint, given, d_.positions, std::span<const Stiffness>(d_.sets), list.size()));
    return Index(list.size() - 1);
  }
  /// As World::add_stretch: rest distance in m, by default the particles' current distance.
  Index add_stretch(Index a, Index b, Index set, std::optional<double> rest = std::nullopt);
  /// As World::add_anchor: target in m, by default the particle's position.
  Index add_anchor(Index particle, Index set, std::optional<Vec> target = std::nullopt);
  /// As World::add_bending: rest angle in rad, by default the current dihedral angle.
  Index add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<double> rest = std::nullopt);
  /// As World::add_area: rest area in m², by default the current one.
  Index add_area(Index a, Index b, Index c, Index set, std::optional<double> rest = std::nullopt);
  /// As World::add_volume: a closed, consistently oriented mesh; rest in the 6V unit, by default the current one.
  Index add_volume(std::span<const std::array<Index, 3>> triangles, Index set, const PressureSchedule& pressure = {},
                   std::optional<double> rest = std::nullopt);
  /// As World::add_surface: a surface that tears along broken fibers.
  Index add_surface(std::span<const std::array<Index, 3>> triangles) {
    check_surface(triangles, {}, std::size_t(d_.num_particles()), "add_surface");
    d_.surfaces.push_back({{triangles.begin(), triangles.end()}, {}});
    return Index(d_.surfaces.size() - 1);
  }
  /// As World::add_tethers: tethers from `body`'s movable particles to its pinned or anchored ones, in a new set of
  /// XPBD compliance options.compliance; returns how many (0 and no set when the body has no such particle).
  Index add_tethers(std::span<const Index> body, const TetherOptions& options = {});
  /// As World::add_plane: n·x ≥ offset (m), stored with the unit normal; its surface's friction (μs, μk ≥ 0) and
  /// restitution (in [0, 1]).
  void add_plane(const Vec& normal, double offset, const ContactMaterial<double>& material = {});
  /// As World::add_sphere: centre and radius in m (radius > 0), and its surface's material.
  void add_sphere(const Vec& center, double radius, const ContactMaterial<double>& material = {});
  /// As World::add_contact_body: particles [body.first, body.first + body.count), existing and in no other contact
  /// body, with a radius in m (≥ 0) and a material. Returns the body's index.
  Index add_contact_body(const ContactBody<double>& body);
  /// As World::set_params.
  void set_params(const StepParams<double>& params);
  /// As World::set_blocking: how the block solver splits the particles (constraints_per_block ≥ 1).
  void set_blocking(const BlockOptions& options);

  /// Room for this many more constraints of built-in type C (no effect on results).
  template <class C> void reserve_more(std::size_t more) {
    std::vector<C>& list = d_.constraints<C>();
    list.reserve(list.size() + more);
  }

  /// Number of particles.
  Index num_particles() const { return d_.num_particles(); }
  /// Positions, 3×N, in m.
  const Positions& positions() const { return d_.positions; }
  /// Velocities, 3×N, in m/s (writable: particles are added at rest).
  Positions& velocities() { return d_.velocities; }
  /// The stiffness of each constraint set.
  std::span<const Stiffness> constraint_sets() const { return d_.sets; }
  /// What has been built so far.
  const WorldDescription& description() const& { return d_; }
  /// The description built, moved out.
  WorldDescription description() && { return std::move(d_); }

private:
  WorldDescription d_;
};

}  // namespace pbd
