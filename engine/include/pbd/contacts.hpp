#pragma once
/// \file contacts.hpp
/// Contact bodies: runs of particles that touch colliders with a radius and a material, and touch one another as
/// spheres (particle contacts, constraints/particle_contact.hpp). A world without contact bodies builds no grid
/// and runs no particle-contact pass.
#include "pbd/constraints/contact_material.hpp"
#include "pbd/types.hpp"

#include <vector>

namespace pbd {

/// Particles [first, first + count) as one contact body.
template <class Real> struct ContactBody {
  Index first = 0;                   ///< first particle
  Index count = 0;                   ///< number of particles
  Real radius = 0;                   ///< each particle's radius, m, ≥ 0 (0: points, which touch colliders only)
  ContactMaterial<Real> material{};  ///< friction and restitution of its particles (mixed with the other side's)
  /// Its particles also touch one another where no constraint joins them (cloth self-collision: a radius of at
  /// least half the rest edge leaves no gap a particle could pass through).
  bool self_collision = false;
};

/// Every contact body of a world, and what is cooked from them per particle.
template <class Real> struct ContactBodies {
  static constexpr Index kNone = ~Index(0);     ///< body_of: the particle is in no contact body
  std::vector<ContactBody<Real>> bodies;         ///< in the order added
  std::vector<Index> body_of;                    ///< per particle: its body or kNone (empty when there are none)
  VectorX<Real> radius;                          ///< per particle, m (empty when there are no bodies)
  std::vector<ContactMaterial<Real>> material;   ///< per particle (empty when there are no bodies)
  Real max_radius = 0;                           ///< largest radius, m (0: no particle contacts)
  bool cooked = false;                           ///< body_of, radius and material match the bodies (and particles)
  bool empty() const { return bodies.empty(); }  ///< true when no particle belongs to a contact body
  /// True when particles touch one another (some body has a radius): a grid is built every sub-step.
  bool particle_contacts() const { return max_radius > Real(0); }
};

}  // namespace pbd
