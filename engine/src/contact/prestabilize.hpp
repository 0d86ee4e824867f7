#pragma once
// Pre-stabilization of collider contacts (private; Macklin et al. 2014, "Unified Particle Physics for Real-Time
// Applications", §4.1 ordering and §6 contacts: a penetration present at the start of a sub-step is removed from x
// and p alike). A particle whose start x is already behind a collider's surface (a body placed half inside the
// ground, a collider added or moved into a body, a remainder of the last sub-step's solve) is moved out along the
// contact's normal, x and p by the same vector, before the solve. Without it the solve pushes p out of the surface
// while x stays inside, and the velocity update (p − x)/h keeps the whole push as speed: a body placed 0.1 m deep
// leaves at metres per second. With it the push changes no velocity, only the position.
// Runs after contact generation (generate_contacts, substep.cpp), serially in the contacts' order, so that the
// result is the same for any thread count.
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/types.hpp"

#include <cstdint>
#include <vector>

namespace pbd::detail {

/// Moves each collider contact's particle out to the contact's surface at the start of the sub-step (x and p by the
/// same vector; each contact in turn, against x as the ones before left it), then sets every collider contact's
/// start to its particle's x and corrects the start (x_a − x_b) of the particle contacts of moved particles.
/// `moved` and `marks` are scratch (`marks` all 0 between calls). Returns whether any particle moved.
template <class Real>
bool prestabilize(std::vector<CollisionConstraint<Real>>& collisions,
                  std::vector<ParticleContact<Real>>& particle_contacts, Matrix3X<Real>& x, Matrix3X<Real>& p,
                  std::vector<Index>& moved, std::vector<std::uint8_t>& marks);

}  // namespace pbd::detail
