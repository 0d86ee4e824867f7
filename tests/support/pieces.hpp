#pragma once
// Pieces of a set of elements (triangles, tets): the groups the elements fall into when joined through shared
// particles. The tear tests count them to see a body torn in two.
#include "pbd/types.hpp"

#include <array>
#include <numeric>
#include <set>
#include <vector>

namespace pbd::test {

/// Number of groups the elements (each N particle indices < `particles`) fall into, joined through shared particles.
template <class Elements> std::size_t pieces(const Elements& elements, Index particles) {
  std::vector<Index> parent(particles);
  std::iota(parent.begin(), parent.end(), Index(0));
  auto find = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& e : elements)
    for (std::size_t k = 1; k < e.size(); ++k) parent[find(e[k])] = find(e[0]);
  std::set<Index> roots;
  for (const auto& e : elements) roots.insert(find(e[0]));
  return roots.size();
}

}  // namespace pbd::test
