#pragma once
// The colored solvers' schedule (private): every coloring goes through graph_coloring. Persistent constraints are
// colored per type (full, or only the appended ones into tail colors), volume constraints as items spanning their
// mesh, and each sub-step's collisions; the cooked per-color data (Jacobi counts, stretch sets, particle cuts)
// follows.
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/detail/model.hpp"
#include "scratch.hpp"

namespace pbd::detail {

/// Pinned flags (inverse mass 0) of every particle: pinned particles are never written, so they never conflict.
template <class Real> std::vector<std::uint8_t> pinned_flags(const VectorX<Real>& inverse_mass);

/// Colors (or partitions and lays out, for Layout::blocks) every store of `m` anew (built-in, user-defined,
/// volume), then the cooked data; sets colors_current.
template <class Real> void color_everything(Model<Real>& m);

/// Brings the stores up to date for `layout` after constraints or particles were added, or cooks everything anew
/// when they are not current, were laid out for the other layout, or the increment would cost too much. Colors:
/// only the new constraints are colored, into tail colors. Blocks: a store with new constraints is laid out again
/// on the same partition (only its boundary constraints are colored); many new particles partition anew.
template <class Real> void update_colors(Model<Real>& m, Layout layout);

/// After a store's layout changed without recoloring (a removal): the Jacobi counts, the stretch colors' sets and
/// the colors' particle cuts.
template <class Real> void note_layout(Model<Real>& m);

/// Colors this sub-step's collisions (each touches one particle: the k-th collision of a particle gets color k) and
/// lays them out color by color.
template <class Real>
void color_collisions(Store<CollisionConstraint<Real>>& collisions, FirstFitScratch<CollisionConstraint<Real>>& w);

/// Colors this sub-step's particle contacts (first fit in generation order; pinned particles, flagged in `fixed`,
/// never conflict) and lays them out color by color.
template <class Real>
void color_particle_contacts(Store<ParticleContact<Real>>& contacts, const std::vector<std::uint8_t>& fixed,
                             FirstFitScratch<ParticleContact<Real>>& w);

}  // namespace pbd::detail
