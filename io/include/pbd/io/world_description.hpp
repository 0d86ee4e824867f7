#pragma once
/// \file world_description.hpp
/// A world described without a precision: every particle, constraint (with its rest value already computed),
/// collider, contact body and step parameter in double. build_world<Real>() (build_world.hpp) makes a World<Real> of
/// it that holds exactly Real(value) for each value here, as a World<double> cast to Real would.
#include "pbd/constraints/contact_material.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/contacts.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"
#include "pbd/world.hpp"

#include <array>
#include <cstddef>
#include <tuple>
#include <vector>

namespace pbd {

/// The constraints of every built-in fixed-arity type (constraint_types.hpp), one list per type in the list's order,
/// each constraint in double as the type's own struct: its particles, its set and its rest values (fields()).
using ConstraintLists = EachOf<std::vector, BuiltinConstraintTypes<double>>::type;

/// A volume constraint on one closed mesh.
struct VolumeDescription {
  std::vector<std::array<Index, 3>> triangles;  ///< closed, counter-clockwise seen from outside (particle indices)
  Index set = 0;                                ///< constraint set
  double rest = 0.0;                            ///< rest volume in the 6V unit of constraints/volume.hpp (m³ × 6), > 0
  PressureSchedule pressure;                    ///< the target's factor over time
};

/// A surface that tears (World::add_surface).
struct SurfaceDescription {
  std::vector<std::array<Index, 3>> triangles;  ///< its triangles (particle indices)
  std::vector<std::array<Index, 2>> cut;        ///< edges already cut
};

/// A half-space n·x ≥ offset.
struct PlaneDescription {
  Eigen::Vector3d normal;              ///< unit normal, pointing out of the solid
  double offset = 0.0;                 ///< n·x of any point x on the plane, in m
  ContactMaterial<double> material{};  ///< its surface's friction (μs, μk ≥ 0) and restitution (in [0, 1])
};

/// A solid ball.
struct SphereDescription {
  Eigen::Vector3d center;              ///< centre in m
  double radius = 0.0;                 ///< radius in m, > 0
  ContactMaterial<double> material{};  ///< its surface's friction (μs, μk ≥ 0) and restitution (in [0, 1])
};

/// Everything a World<Real> is built from, in double precision, in the order the world holds it.
struct WorldDescription {
  Matrix3X<double> positions;                  ///< 3×N particle positions in m
  Matrix3X<double> velocities;                 ///< 3×N particle velocities in m/s
  VectorX<double> inverse_masses;              ///< N inverse masses in 1/kg (0 = pinned)
  std::vector<Stiffness> sets;                 ///< stiffness of each constraint set
  ConstraintLists constraint_lists;            ///< built-in fixed-arity constraints, per type, in insertion order
  std::vector<VolumeDescription> volumes;      ///< volume constraints, in insertion order
  std::vector<SurfaceDescription> surfaces;    ///< surfaces that tear, in the order added
  std::vector<PlaneDescription> planes;        ///< plane colliders
  std::vector<SphereDescription> spheres;      ///< sphere colliders
  /// Contact bodies (contacts.hpp: particle runs with a radius in m, a material and self-collision), in the order
  /// added; disjoint.
  std::vector<ContactBody<double>> contact_bodies;
  StepParams<double> params;                   ///< step parameters
  BlockOptions blocking;                       ///< how the block solver splits the particles

  /// Number of particles.
  Index num_particles() const { return Index(positions.cols()); }
  /// The constraints of built-in type C (in double, e.g. StretchConstraint<double>), in insertion order.
  template <class C> std::vector<C>& constraints() { return std::get<std::vector<C>>(constraint_lists); }
  template <class C> const std::vector<C>& constraints() const {  ///< read-only constraints()
    return std::get<std::vector<C>>(constraint_lists);
  }
  /// Number of constraints of all types.
  std::size_t num_constraints() const {
    std::size_t n = volumes.size();
    std::apply([&](const auto&... lists) { ((n += lists.size()), ...); }, constraint_lists);
    return n;
  }
};

}  // namespace pbd
