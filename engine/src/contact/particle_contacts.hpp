#pragma once
// Particle contacts (private): the broad phase and the continuous generation of ParticleContact constraints
// between the particles of contact bodies (contacts.hpp), once per sub-step, after the prediction.
//   1. cook      per particle: body, radius, material (when bodies or particles changed); for self-colliding
//                bodies, the particles each one is joined to by a built-in constraint (when the model changed)
//   2. grid      each particle's swept box: its path x → p − Δ̄ (Δ̄ the mean path of this sub-step: relative paths,
//                all a pair test reads, are the same in the frame that moves with it, where a falling cloth's boxes
//                stay short) grown by its radius and half the margin, entered into every cell it covers (cells of
//                1.5·(2·r_max + margin), stretched along an axis by the paths' mean departure along it; one bucket
//                per cell of the boxes' bounding grid, x fastest, or when that grid is sparse a hash table of about
//                twice as many buckets as entries; filled by a counting sort in particle order, each entry marked
//                with the axes along which its cell is the box's lowest). Sums, boxes and cell ranges are computed
//                in fixed chunks of particles. A box over more than kMaxCells cells (a particle far faster than the
//                rest) is tested against every particle instead
//   3. pairs     bucket by bucket (fixed chunks of buckets), every two entries of one cell whose marks together
//                cover all three axes: that cell is the first the two boxes share (the larger of their lower
//                corners), so each pair is found once; then the two boxes must overlap, and the pair is kept when the
//                relative path (x_i − x_j) → (p_i − p_j) comes within r_i + r_j + margin: continuous, so nothing
//                passes through anything within a sub-step (if it does, the two boxes meet)
//   4. output    sorted by pair (i, j), i < j: the same list for any thread count and any cells
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
  std::vector<Eigen::Vector3d> partial;            // per chunk: its part of a sum over the particles
  std::vector<std::array<std::int32_t, 3>> lo, hi; // per particle with a radius: its swept box's cell range
  struct Mover {                                   // what a pair test reads of a particle, in one place
    Vec3<Real> x, p;                               //   start of the sub-step and predicted, m
    Real radius;                                   //   m
    bool pinned;                                   //   inverse mass 0
    Vec3<Real> lo, hi;                             //   its swept box in the sub-step's moving frame, m
  };
  std::vector<Mover> movers;                       // per particle (those with a radius are filled)
  std::vector<std::uint32_t> cells;                // per active particle: cells its box covers (0: too many)
  std::vector<std::pair<std::array<std::int32_t, 3>, std::array<std::int32_t, 3>>> chunk_bounds;  // per chunk: cells
  std::vector<Index> huge;                         // particles whose boxes cover too many cells, ascending
  struct Entry {
    Index particle;
    Index group;                                   // its body when that does not self-collide, else kNone
    std::uint8_t lower;                            // bit d: the cell is the box's lowest along axis d
    std::array<std::int32_t, 3> cell;
  };
  std::vector<Index> bucket_start;                 // per bucket + 1: where its entries start in `entries`
  std::vector<Entry> entries;                      // (particle, cell), bucket by bucket, particle order within one
  std::vector<Index> fill;                         // the counting sort's cursor per bucket
  std::vector<Index> bucket_cut;                   // per chunk + 1: its first bucket
  std::vector<Index> first_of;                     // per particle + 1: the output's counting sort by first particle
  std::vector<std::vector<ParticleContact<Real>>> chunks;  // per chunk of buckets: its contacts (last: the huge ones)
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
