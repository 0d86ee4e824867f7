#pragma once
// Collider contacts in chunks (private): pbd::generate_collisions (colliders.hpp) over fixed chunks of particles, in
// parallel when asked. Each chunk's contacts go to its own list, and the lists are joined in chunk order, so the result
// is the serial one (particle by particle, planes before spheres) for any thread count.
#include "pbd/colliders.hpp"

#include <vector>

namespace pbd::detail {

/// Per-chunk contact lists, kept between sub-steps so that nothing is reallocated.
template <class Real> using CollisionChunks = std::vector<std::vector<CollisionConstraint<Real>>>;

/// generate_collisions, with its particles in chunks that run in parallel when `parallel` (and there are enough).
template <class Real>
void generate_collisions_chunked(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                 const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin,
                                 ParticleSurfaces<Real> surfaces, bool parallel, CollisionChunks<Real>& chunks,
                                 std::vector<CollisionConstraint<Real>>& out);

}  // namespace pbd::detail
