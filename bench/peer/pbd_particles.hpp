#pragma once
// What both pbd drivers (pbd_cloth.cpp, pbd_bar.cpp) add first: the file's particles as the peer's models have them,
// every vertex of the same mass and the pinned ones of mass 0. Links pbd (the shared *_common.hpp files do not).
#include "pbd/world.hpp"

#include <array>
#include <vector>

namespace peer_bench {

/// Adds the vertices x (m), each of `mass` kg but those in `pinned` (mass 0), to `world`.
template <class Real>
void add_file_particles(pbd::World<Real>& world, const std::vector<std::array<double, 3>>& x, double mass,
                        const std::vector<unsigned>& pinned) {
  const pbd::Index n = pbd::Index(x.size());
  pbd::Matrix3X<Real> p(3, n);
  pbd::VectorX<Real> w = pbd::VectorX<Real>::Constant(n, Real(1.0 / mass));
  for (pbd::Index i = 0; i < n; ++i) p.col(i) = pbd::Vec3<Real>(Real(x[i][0]), Real(x[i][1]), Real(x[i][2]));
  for (unsigned i : pinned) w[i] = 0;
  world.add_particles_by_inverse_mass(p, w);
}

}  // namespace peer_bench
