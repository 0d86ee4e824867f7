#pragma once
// Tearing a surface along broken fibers (private; World::add_surface). After a step's breaks (fibers.hpp), each
// surface's edges whose fiber broke are cut. Around each end particle v of a newly cut edge, the triangles holding v
// are joined across each of their shared edges (v, u) that is not cut; when that leaves them in several groups, v
// stays with the group of its lowest triangle and each other group gets a copy of v (same position and velocity;
// v's mass split between the groups by their triangle counts, so the momentum is kept), which takes v's place in
// the group's triangles and in every constraint that lies on the group (a constraint lies on the triangles holding
// v whose corners are all among its particles, or for a two-particle one, that hold both: an edge). A constraint
// lying on two groups (a bending hinge on the cut) is removed; one on no triangle (an anchor) stays with v. The
// particles are visited in increasing order, the surfaces in order: the result depends only on which fibers broke,
// not on the thread count nor on the order of the breaks. Last, a triangle at a cut's end that has two or more
// edges with no fiber (or stretch constraint) left, a flap that nothing holds, leaves the surface with the
// constraints of three or more particles on it (its area, a bending through it).
#include "pbd/detail/model.hpp"
#include "pbd/fiber_state.hpp"

#include <array>
#include <span>
#include <vector>

namespace pbd::detail {

/// What a tear asks of the world: constraints to remove (per built-in type, by user index, ascending).
struct TearResult {
  std::vector<TornParticle> copies;                        ///< each particle added, and the one it copies
  std::array<std::vector<Index>, kNumBuiltinTypes> remove;  ///< constraints that lay across a tear
  bool changed() const {  ///< particles were added or constraints are to go
    if (!copies.empty()) return true;
    for (const auto& r : remove)
      if (!r.empty()) return true;
    return false;
  }
};

/// Cuts each surface of `m` along the fibers of `breaks` and splits the particles the cuts separate (file comment);
/// adds the copies to `s` (x, v) and `m` (inverse masses), renames them in the constraints. The caller removes
/// result.remove and brings the layout up to date.
template <class Real> TearResult tear_surfaces(Model<Real>& m, State<Real>& s, std::span<const FiberBreak> breaks);

/// After tear_surfaces renamed particles in constraints: a colors layout is kept (every color stays proper) and its
/// per-particle tables follow (tail colors, Jacobi counts, particle cuts); a block layout is made anew next step.
template <class Real> void lay_out_after_tear(Model<Real>& m);

}  // namespace pbd::detail
