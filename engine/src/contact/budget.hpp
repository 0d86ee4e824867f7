#pragma once
// The particle contacts' budget (private to contact/): a sub-step may find at most kMaxContactsPerParticle pairs per
// particle with a radius (contacts.hpp says why that is enough for any pile). A radius or margin far beyond the
// particles' spacing makes the pairs grow with the square of the particles, which would fill the memory; instead the
// broad phase stops with a pbd::Error naming the body. The pairs are counted as found, repeats included, so the
// decision is the same for any thread count: each list adds its pairs to a shared count every kCountEvery (a
// partial count, never above the whole), and the whole is checked once every list is done.
#include "pbd/contacts.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace pbd::detail::contact {

constexpr std::size_t kCountEvery = 4096;  // pairs a list finds between two additions to the shared count

// The most pairs a sub-step may find among `active` particles with a radius.
inline std::size_t contact_limit(std::size_t active) { return kMaxContactsPerParticle * (active + 1); }

// Throws: `found` pairs (at least) are more than `limit`; names the body that has the most of those in `lists`.
template <class Real>
[[noreturn]] void fail_too_many_contacts(const ContactBodies<Real>& c, std::span<const std::vector<ParticleContact<Real>>> lists,
                                         std::size_t found, std::size_t limit, Real margin) {
  std::vector<std::size_t> per_body(c.bodies.size(), 0);
  for (const auto& list : lists)
    for (const auto& k : list) ++per_body[c.body_of[k.particles[0]]];
  const std::size_t b = std::size_t(std::max_element(per_body.begin(), per_body.end()) - per_body.begin());
  throw Error(message("step: particle contacts: ", found, " pairs found in one sub-step, more than the limit of ", limit,
                      " (", kMaxContactsPerParticle, " per particle with a radius); most are of contact body ", b,
                      " (radius ", c.bodies[b].radius, " m, collision_margin ", margin,
                      " m), whose particles each touch many others: use a radius near half their spacing and a "
                      "margin no larger than it; the step was not taken"));
}

}  // namespace pbd::detail::contact
