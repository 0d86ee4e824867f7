// Phase 5 of the particle contacts (particle_contacts.hpp): the contact lists of the pair phases joined in the order
// of the pairs (i, j), i < j, each pair once. The list is then the same whatever the grid's cells, the frame or the
// thread count, and Gauss-Seidel meets a pile's contacts in particle order, which converges better than bucket order
// (contact_test's pile).
#include "phases.hpp"

#include <algorithm>

namespace pbd::detail::contact {

// A counting sort by i of the lists, then a sort by j among each i's few; a pair found more than once (through two
// pieces of a box) gave the same contact each time: one is kept.
template <class Real> void order_contacts(Call<Real>& call, std::vector<ParticleContact<Real>>& out) {
  ParticleGrid<Real>& g = call.g;
  const Index n = call.m.num_particles();
  const std::size_t lists = call.lists;
  g.first_of.assign(std::size_t(n) + 1, 0);
  std::size_t found = 0;
  for (std::size_t l = 0; l < lists; ++l) {
    found += g.lists[l].size();
    for (const auto& k : g.lists[l]) ++g.first_of[k.particles[0] + 1];
  }
  for (Index i = 0; i < n; ++i) g.first_of[i + 1] += g.first_of[i];
  const std::size_t before = out.size();
  out.resize(before + found);
  ParticleContact<Real>* to = out.data() + before;
  for (std::size_t l = 0; l < lists; ++l)
    for (const auto& k : g.lists[l]) to[g.first_of[k.particles[0]]++] = k;  // first_of[i] ends where i's contacts end
  Index begin = 0;
  for (Index i = 0; i < n; ++i) {
    const Index end = g.first_of[i];
    if (end - begin > 1)
      std::sort(to + begin, to + end, [](const auto& a, const auto& b) { return a.particles[1] < b.particles[1]; });
    begin = end;
  }
  if (call.repeats) {  // a pair found more than once gave the same contact each time: keep one
    auto last = std::unique(to, to + found, [](const auto& a, const auto& b) { return a.particles == b.particles; });
    out.resize(before + std::size_t(last - to));
  }
}

template void order_contacts(Call<float>&, std::vector<ParticleContact<float>>&);
template void order_contacts(Call<double>&, std::vector<ParticleContact<double>>&);

}  // namespace pbd::detail::contact
