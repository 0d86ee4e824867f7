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
#include <cstddef>
#include <cstdint>
#include <limits>
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

/// Largest contact radius and collision margin, m (the largest length a scene key takes): their squares and sums stay
/// finite in float, and a longer reach is no contact a simulation in metres needs.
inline constexpr double kMaxContactLength = 1e6;

/// Contact pairs a sub-step may find per particle with a radius, at most (the run stops with a pbd::Error beyond it).
/// Counting each pair at its smaller particle: spheres that do not overlap put at most (3 + margin / radius)³
/// partners of its radius or larger within its reach (a ball of its radius fits inside each, and all of those fit
/// in a ball three radii and a margin wide), which is 64 with a margin as large as the radius. This allows four times
/// that, for spheres pressed into one another and paths swept in one sub-step; a pile at rest has about six.
inline constexpr std::size_t kMaxContactsPerParticle = 256;

/// Mean number of reach spheres (each particle's contact radius plus half the margin) that cover a point of the
/// body's box, at most: check_contact_reach. Non-overlapping spheres cover each point at most once; a cloth whose
/// radius is half its rest edge, or a soft ball whose particles overlap their neighbours, stays well under it.
inline constexpr double kMaxContactCover = 8;

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
  if (!std::isfinite(body.radius) || body.radius < Real(0) || double(body.radius) > kMaxContactLength)
    throw Error(detail::message(what, ": radius must be finite and >= 0 and at most ", kMaxContactLength, " m, got ",
                                body.radius));
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

/// Throws pbd::Error, its message starting with `what`, when the particles of `body` that have a radius (not its
/// interior) would touch more than a bounded number of others: the spheres of radius + margin / 2 around them
/// (their reach) must cover each point of the body's bounding box (grown by the reach) at most kMaxContactCover
/// times on average. A body of grains or a cloth with a radius far beyond its spacing fails; one particle never does.
/// Linear in the body's particles; World and pbd::io's DescriptionBuilder run it when a body is added and when the
/// margin is set (against the positions then).
template <class Real>
void check_contact_reach(const ContactBody<Real>& body, const Matrix3X<Real>& x, Real margin, const std::string& what) {
  if (!(body.radius > Real(0))) return;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double active = 0;
  std::size_t k = 0;  // the next interior particle
  for (Index i = body.first; i < body.first + body.count; ++i) {
    if (k < body.interior.size() && body.interior[k] == i) {
      ++k;
      continue;
    }
    const Eigen::Vector3d xi = x.col(i).template cast<double>();
    lo = lo.cwiseMin(xi);
    hi = hi.cwiseMax(xi);
    active += 1;
  }
  const double reach = double(body.radius) + 0.5 * double(margin);
  const double spheres = active * (4.0 / 3.0) * 3.14159265358979323846 * reach * reach * reach;
  const Eigen::Vector3d box = (hi - lo).array() + 2.0 * reach;
  if (active < 2 || !(spheres > kMaxContactCover * box.prod())) return;
  throw Error(detail::message(what, ": radius ", body.radius, " m and collision_margin ", margin, " m make its ",
                              active, " particles' contact spheres cover their box ", spheres / box.prod(),
                              " times over (at most ", kMaxContactCover,
                              "): each would touch many others; use a radius near half the particle spacing"));
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
