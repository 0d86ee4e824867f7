#include "prestabilize.hpp"

namespace pbd::detail {

template <class Real>
bool prestabilize(std::vector<CollisionConstraint<Real>>& collisions,
                  std::vector<ParticleContact<Real>>& particle_contacts, Matrix3X<Real>& x, Matrix3X<Real>& p,
                  std::vector<Index>& moved, std::vector<std::uint8_t>& marks) {
  // The collisions come particle by particle (colliders.hpp): a particle's contacts are consecutive.
  moved.clear();
  for (const CollisionConstraint<Real>& c : collisions) {
    const Index i = c.particles[0];
    const Real depth = c.offset - c.normal.dot(x.col(i));
    if (!(depth > Real(0))) continue;
    const Vec3<Real> shift = depth * c.normal;
    x.col(i) += shift;
    p.col(i) += shift;
    if (moved.empty() || moved.back() != i) moved.push_back(i);
  }
  if (moved.empty()) return false;
  for (CollisionConstraint<Real>& c : collisions) c.start = x.col(c.particles[0]);
  if (!particle_contacts.empty()) {
    // Marks on the moved particles, a byte per particle, cleared again below: O(contacts), no search.
    if (marks.size() < std::size_t(x.cols())) marks.resize(std::size_t(x.cols()), 0);
    for (const Index i : moved) marks[std::size_t(i)] = 1;
    for (ParticleContact<Real>& c : particle_contacts)
      if (marks[std::size_t(c.particles[0])] | marks[std::size_t(c.particles[1])])
        c.start = x.col(c.particles[0]) - x.col(c.particles[1]);
    for (const Index i : moved) marks[std::size_t(i)] = 0;
  }
  return true;
}

template bool prestabilize(std::vector<CollisionConstraint<float>>&, std::vector<ParticleContact<float>>&,
                           Matrix3X<float>&, Matrix3X<float>&, std::vector<Index>&,
                           std::vector<std::uint8_t>&);
template bool prestabilize(std::vector<CollisionConstraint<double>>&, std::vector<ParticleContact<double>>&,
                           Matrix3X<double>&, Matrix3X<double>&, std::vector<Index>&,
                           std::vector<std::uint8_t>&);

}  // namespace pbd::detail
