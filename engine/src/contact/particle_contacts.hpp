#pragma once
// Particle contacts (private): the broad phase and the continuous generation of ParticleContact constraints
// between the particles of contact bodies (contacts.hpp), once per sub-step, after the prediction.
//   1. cook      per particle: body, radius, material (when bodies or particles changed); for self-colliding
//                bodies, the particles each one is joined to by a built-in constraint (when the model changed)
//   2. grid      a spatial hash of the predicted positions p: cells of 2·r_max + margin + 2·s_max (s_max the
//                largest departure of a path x → p from the mean path of this sub-step, so two particles whose paths
//                meet end in neighbouring cells however fast they moved), hashed into a table of about twice as many buckets as particles, filled
//                by a counting sort in particle order
//   3. pairs     each particle i looks at its own cell (particles j > i) and the 13 cells after it (all), and keeps
//                the pairs whose relative path (x_i − x_j) → (p_i − p_j) comes within r_i + r_j + margin: continuous,
//                so nothing passes through anything within a sub-step
//   4. output    in particle order of i, then j: the same list for any thread count (fixed chunks of i, joined in
//                chunk order)
// A world without contact bodies of non-zero radius runs none of this.
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/detail/model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace pbd::detail {

/// Scratch of the broad phase, kept between sub-steps so that nothing is reallocated.
template <class Real> struct ParticleGrid {
  std::uint64_t joined_edits = ~std::uint64_t(0);  // Model::edits the exclusions below were built at
  std::size_t joined_bodies = 0;                   // contact bodies then
  std::vector<Index> joined_offsets;               // CSR per particle: particles joined to it by a constraint
  std::vector<Index> joined;                       //   (sorted; only particles of self-colliding bodies)
  std::vector<Index> active;                       // particles with a radius, ascending
  std::vector<std::array<std::int32_t, 3>> cell;   // per particle with a radius: the cell of p
  std::vector<Index> bucket_start;                 // per bucket + 1: where its particles start in bucket_items
  std::vector<Index> bucket_items;                 // active particles, bucket by bucket, ascending within one
  std::vector<std::uint32_t> bucket_of;            // per active particle (by position in `active`)
  std::vector<std::vector<ParticleContact<Real>>> chunks;  // per chunk of particles: its contacts
};

/// Brings m.contact's per-particle arrays up to date (after bodies or particles were added).
template <class Real> void cook_contact_bodies(Model<Real>& m);

/// Appends to `out` this sub-step's particle contacts (see above): x the positions at the start of the sub-step,
/// p the predicted ones, v the velocities after forces (for restitution), margin in m. Runs its loops in
/// parallel when `parallel`, with the same result.
template <class Real>
void generate_particle_contacts(const Model<Real>& m, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                const Matrix3X<Real>& v, Real margin, bool parallel, ParticleGrid<Real>& grid,
                                std::vector<ParticleContact<Real>>& out);

}  // namespace pbd::detail
