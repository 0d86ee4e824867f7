#include "pbd/io/mesh.hpp"

#include <cstdint>
#include <unordered_map>

namespace pbd {
namespace {

std::uint64_t key(Index a, Index b) { return (std::uint64_t(a) << 32) | b; }
std::uint64_t undirected(Index a, Index b) { return a < b ? key(a, b) : key(b, a); }

}  // namespace

std::vector<std::array<Index, 2>> mesh_edges(std::span<const std::array<Index, 3>> triangles) {
  std::unordered_map<std::uint64_t, Index> seen;
  seen.reserve(3 * triangles.size());
  std::vector<std::array<Index, 2>> edges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      if (seen.emplace(undirected(a, b), Index(edges.size())).second) edges.push_back({a, b});
    }
  return edges;
}

std::vector<std::array<Index, 4>> mesh_bending_pairs(std::span<const std::array<Index, 3>> triangles) {
  // Per undirected edge, in first-appearance order: its triangles' opposite corners (up to 3 are kept).
  struct Edge {
    Index a, b, count = 0;
    Index opposite[2]{};
  };
  std::unordered_map<std::uint64_t, Index> index;
  std::vector<Edge> edges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3], opp = t[(k + 2) % 3];
      const auto [it, added] = index.emplace(undirected(a, b), Index(edges.size()));
      if (added) edges.push_back({a, b});
      Edge& e = edges[it->second];
      if (e.count < 2) e.opposite[e.count] = opp;
      ++e.count;
    }
  std::vector<std::array<Index, 4>> pairs;
  for (const Edge& e : edges)
    if (e.count == 2) pairs.push_back({e.a, e.b, e.opposite[0], e.opposite[1]});
  return pairs;
}

}  // namespace pbd
