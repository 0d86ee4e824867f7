#pragma once
// Particle contacts (private): the broad phase and the continuous generation of ParticleContact constraints
// between the particles of contact bodies (contacts.hpp), once per sub-step, after the prediction.
// generate_particle_contacts runs five phases, each a function of its own file (phases.hpp lists them):
//   1. cook      per particle: body, radius, material (cook_contact_bodies, when bodies or particles changed); for
//                self-colliding bodies, the particles each one is joined to by a built-in constraint (exclusions.cpp:
//                build_exclusions, when the model changed)
//   2. boxes     (boxes.cpp: mean_path, sweep_boxes) each particle's swept box: its path x → p − Δ̄ (Δ̄ a mean path:
//                relative paths, all a pair test reads, are the same in any frame that moves with one, where a
//                falling cloth's boxes stay short) grown by its radius and half the margin. Δ̄ and level 0's cell
//                widths are the last sub-step's (kept here), so level 0's cells are found in this pass; the first
//                sub-step, or one with a new particle count, finds them in passes of their own (mean_path,
//                find_cells). Neither changes the result, only which pairs are tested. The pass stores what a pair
//                test reads (movers) and level 0's cells, not the boxes: the few a later level needs are found again
//                from the movers, the same corners (cells.hpp: box_of)
//   3. grid      (grid.cpp: find_cells, build_grid) a uniform grid whose cells are as wide as the boxes are on average,
//                along each axis. A box that spans at most two cells along every axis ("small") is entered once, by the
//                cell of its lower corner, into the bucket of that cell's row along x (a counting sort into one bucket
//                per row (y, z) of the lower corners' bounding grid, or when those rows are sparse a hash table of
//                about twice as many buckets as boxes), sorted within a bucket by cell and particle (a dense grid is
//                counting-sorted by cell x before the sort by row, so no row needs sorting). A box that spans three or
//                four cells along some axis (a fast particle's) is entered as up to kMaxPieces pieces of two cells, two
//                cells apart, which cover it: a box that overlaps it overlaps a piece, and no two pieces of one box are
//                paired (a pair may be found through two pieces: the output drops the repeat). Larger boxes are
//                not entered (large)
//   4. walk      (walk.cpp: walk_entries, query_large, pair_each_with_each; the test in pair_test.hpp) two small
//                boxes that overlap have lower corners at most one cell apart along each axis, so each entry is paired
//                with the entries of its own row in its cell (after it) and the next, and with those of the rows
//                (y + 1, z), (y − 1, z + 1), (y, z + 1), (y + 1, z + 1) within one cell along x, walked along with
//                its own row: the 13 of the 26 neighbouring cells that come after its own, so each pair once. A larger
//                box is paired with the entries whose lower corners lie in its cells or one cell below them (or with
//                all of them, over kMaxRows rows). The larger boxes then form the next level (3 and 4 again), with
//                cells at least twice as wide, until every box is entered or at most kBruteForce boxes are left, which
//                are paired with one another. A box's candidates are gathered (a row's are consecutive: counted and
//                copied eight at a time without a branch) and tested together, eight at a time with AVX2, four with
//                SSE2, one at a time otherwise, all giving the same bits: a pair is kept when the relative path
//                (x_i − x_j) → (p_i − p_j) comes within r_i + r_j + margin: continuous, so nothing passes through
//                anything within a sub-step. The boxes are not compared first: paths within reach have overlapping
//                boxes. Near candidates joined to the particle by a constraint are masked out together, against its
//                row of joined particles, nearest first: its first two groups of four with every candidate, the rest
//                only when a near candidate is left unmatched (a cloth's near pairs are nearly all its edges); then
//                pairs of one body that does not self-collide or of two pinned particles are dropped. A dense float
//                grid on a CPU with AVX2 is walked by near_avx2.hpp's build of this phase (the same pairs)
//   5. order     (order.cpp: order_contacts) sorted by pair (i, j), i < j, each once: the same list for any thread
//                count, cells or frame
// Why this order: each phase reads only what the ones before it wrote. The exclusions come first because the walk
// masks candidates with them; the boxes' pass writes the movers every later test reads and, from the boxes' sizes,
// the widths of the cells (this sub-step's for level 0 when not known, the next sub-step's always); a level's grid
// must hold all its entries, sorted, before the walk can find a box's neighbours in it, and a level's large boxes
// are paired with its entries before they form the next level; the order is last because the walk's lists are in
// chunk and bucket order, which depends on the cells. Sums, cells, sorts, pairs and queries run in fixed chunks (phases.hpp:
// over_chunks), in parallel when asked, and the chunks' results are joined in chunk order.
// A world without contact bodies of non-zero radius runs none of this.
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/detail/model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace pbd::detail {

/// Scratch of the broad phase, kept between sub-steps so that nothing is reallocated; also the last sub-step's frame
/// and cell widths (phase 2).
template <class Real> struct ParticleGrid {
  using Cell = std::array<std::int32_t, 3>;
  std::uint64_t joined_edits = ~std::uint64_t(0);  // Model::edits the exclusions below were built at
  std::size_t joined_bodies = 0;                   // contact bodies then
  std::vector<Index> joined_offsets;               // CSR per particle: the particles joined to it by a constraint
  std::vector<Index> joined;                       //   (nearest first when built, each row padded to whole
                                                   //   groups of four with kNone; only in self-colliding bodies)
  std::vector<Eigen::Vector3d> partial;            // per chunk: its part of a sum over the particles
  std::vector<Eigen::Vector3d> partial_path;       //   and of the sum of their paths
  Index known = 0;                                 // the particles of the last sub-step (0: none yet), for which
  Vec3<Real> frame = Vec3<Real>::Zero();           //   its mean path, m
  Eigen::Vector3d width = Eigen::Vector3d::Ones(); //   and its boxes' mean size along each axis, m (level 0's cells)
  struct alignas(16) Mover {                      // what a pair test reads of a particle, padded for lane loads
    Real x[4];                                     //   start of the sub-step, m, then its radius, m
    Real p[4];                                     //   predicted, m, then 1 when pinned (inverse mass 0), else 0
  };
  std::vector<Mover> movers;                       // per particle (those with a radius are filled)
  struct Box {                                     // a particle's swept box (not stored: found from its mover)
    Vec3<Real> lo, hi;                             //   in the sub-step's moving frame, m
  };
  struct Slot {                                    // a small box as a grid holds it
    Cell cell;                                     //   the cell of its lower corner
    Index particle;
  };
  struct Level {                                   // one grid (see above)
    std::vector<Index> members;                    //   its particles, ascending
    std::vector<Cell> lo, hi;                      //   per member: the cells of its box's corners
    std::vector<std::uint32_t> key;                //   per member: small, in pieces or large; then per slot: its bucket
    std::vector<Slot> slots;                       //   the grid's entries: small boxes, pieces of larger ones
    std::vector<Index> large;                      //   its particles whose boxes span more than two cells
    std::vector<std::pair<Cell, Cell>> bounds;     //   per chunk: the range of its small members' lower cells
    std::vector<Eigen::Vector3d> extent;           //   per chunk: the sum of its large members' box sizes
    std::vector<Index> bucket_start;               //   per bucket + 1: where its entries start in `entries`
    std::vector<Index> fill;                       //   the counting sort's cursor per bucket
    std::vector<Index> x_start;                    //   dense: per cell along x + 1, the first counting sort's starts
    std::vector<Index> by_x;                       //   dense: the small members by cell along x, then particle
    std::vector<Slot> entries;                     //   the small members, bucket by bucket, by (cell z, y, x, particle)
    std::vector<std::int32_t> cell_x;              //   per entry (+ 8 past the end): its cell along x
    std::vector<Index> particle;                   //   per entry (+ 8 past the end): its particle
    std::vector<Index> cut;                        //   per chunk + 1: its first bucket
  };
  std::vector<Level> levels;
  std::vector<Index> first_of;                     // per particle + 1: the output's counting sort by first particle
  std::vector<std::vector<ParticleContact<Real>>> lists;  // per chunk of each level's work: its contacts
};

/// Items from which the broad phase's loops run in parallel (a loop over fewer is shorter than a fork costs).
constexpr Index kParallelContactsFrom = 4096;

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
