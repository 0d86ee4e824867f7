#pragma once
// The contact generators' scratch (private): the collider contacts' per-chunk lists and the particle contacts' broad
// phase, kept between sub-steps so that nothing is reallocated. The world's per-step scratch (solve/scratch.hpp)
// holds it through a pointer to this type, which it only declares: a sub-step (substep.cpp) alone calls the generators
// and makes it, so solve/ need not see contact/.
#include "colliders.hpp"
#include "particle_contacts.hpp"

#include <cstdint>
#include <vector>

namespace pbd::detail {

template <class Real> struct ContactScratch {
  CollisionChunks<Real> collision_chunks;  // the collider contacts' per-chunk lists (colliders.hpp)
  ParticleGrid<Real> grid;                 // the particle contacts' broad phase (particle_contacts.hpp)
  std::vector<Index> moved;                // the particles pre-stabilization moved (prestabilize.hpp)
  std::vector<std::uint8_t> moved_marks;   // and a mark per particle, 0 between sub-steps
};

}  // namespace pbd::detail
