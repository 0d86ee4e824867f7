#pragma once
/// \file contacts.hpp
/// Contact bodies: runs of particles that touch colliders with a radius and a material, and touch one another as
/// spheres (particle contacts, constraints/particle_contact.hpp). A world without contact bodies builds no grid
/// and runs no particle-contact pass.
#include "pbd/constraints/contact_material.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"
#include "pbd/types.hpp"

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
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
  /// Particles of the run (world indices, ascending) that are points whatever the radius: they touch colliders only,
  /// never other particles. A tet body's interior: it touches other bodies and itself through its surface (io's
  /// scene bodies say so from their surface triangles), and its inner particles stay out of the particle grid.
  std::vector<Index> interior{};
};

/// Throws pbd::Error, its message starting with `what`, unless both frictions are finite and ≥ 0 and the
/// restitution is in [0, 1].
template <class Real> void check_contact_material(const ContactMaterial<Real>& m, const std::string& what) {
  if (!std::isfinite(m.static_friction) || m.static_friction < Real(0))
    throw Error(detail::message(what, ": static friction must be finite and >= 0, got ", m.static_friction));
  if (!std::isfinite(m.kinetic_friction) || m.kinetic_friction < Real(0))
    throw Error(detail::message(what, ": kinetic friction must be finite and >= 0, got ", m.kinetic_friction));
  if (!(m.restitution >= Real(0) && m.restitution <= Real(1)))
    throw Error(detail::message(what, ": restitution must be in [0, 1], got ", m.restitution));
}

/// Throws pbd::Error, its message starting with `what`, unless `body` is a non-empty run of the n particles with a
/// finite radius ≥ 0 and a valid material, sharing no particle with `others`.
template <class Real>
void check_contact_body(const ContactBody<Real>& body, Index n, std::span<const ContactBody<Real>> others,
                        const std::string& what) {
  if (body.count == 0 || body.first >= n || body.count > n - body.first)
    throw Error(detail::message(what, ": particles [", body.first, ", ", std::uint64_t(body.first) + body.count,
                                ") are not a non-empty range of the ", n, " particles"));
  if (!std::isfinite(body.radius) || body.radius < Real(0))
    throw Error(detail::message(what, ": radius must be finite and >= 0, got ", body.radius));
  check_contact_material(body.material, what);
  for (std::size_t k = 0; k < body.interior.size(); ++k) {
    const Index i = body.interior[k];
    if (i < body.first || i - body.first >= body.count || (k > 0 && i <= body.interior[k - 1]))
      throw Error(detail::message(what, ": interior particle ", k, " (", i, ") is not in [", body.first, ", ",
                                  std::uint64_t(body.first) + body.count, ") or not above the one before"));
  }
  for (std::size_t b = 0; b < others.size(); ++b)
    if (body.first < others[b].first + others[b].count && others[b].first < body.first + body.count)
      throw Error(detail::message(what, ": particles [", body.first, ", ", body.first + body.count,
                                  ") overlap those of contact body ", b));
}

/// Every contact body of a world, and what is cooked from them per particle.
template <class Real> struct ContactBodies {
  static constexpr Index kNone = ~Index(0);     ///< body_of: the particle is in no contact body
  std::vector<ContactBody<Real>> bodies;         ///< in the order added
  std::vector<Index> body_of;                    ///< per particle: its body or kNone (empty when there are none)
  VectorX<Real> radius;                          ///< per particle, m (empty when there are no bodies)
  std::vector<ContactMaterial<Real>> material;   ///< per particle (empty when there are no bodies)
  std::vector<Index> active;                     ///< the particles with a radius > 0, ascending
  Real max_radius = 0;                           ///< largest radius, m (0: no particle contacts)
  bool cooked = false;                           ///< body_of, radius, material and active match the bodies (and particles)
  bool empty() const { return bodies.empty(); }  ///< true when no particle belongs to a contact body
  /// True when particles touch one another (some body has a radius): a grid is built every sub-step.
  bool particle_contacts() const { return max_radius > Real(0); }
};

}  // namespace pbd
