#include "pbd/mesh.hpp"

#include "message.hpp"

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

std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices) {
  if (triangles.empty()) return std::string("the mesh has no triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] >= num_vertices)
        return detail::message("triangle ", t, ": vertex index ", triangles[t][k], " out of range (", num_vertices,
                               " vertices)");
      if (triangles[t][k] == triangles[t][(k + 1) % 3])
        return detail::message("triangle ", t, " names vertex ", triangles[t][k], " twice");
    }
  std::unordered_map<std::uint64_t, Index> directed;
  directed.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++directed[key(t[k], t[(k + 1) % 3])];
  auto count = [&](Index a, Index b) {
    const auto it = directed.find(key(a, b));
    return it == directed.end() ? Index(0) : it->second;
  };
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      const Index forward = count(a, b), backward = count(b, a);
      if (forward == 1 && backward == 1) continue;
      const std::string edge = detail::message("edge (", a, ", ", b, ")");
      if (forward + backward == 1) return edge + " belongs to one triangle only: the mesh is open";
      if (forward + backward > 2)
        return detail::message(edge, " is shared by ", forward + backward, " triangles: the mesh is not manifold");
      return edge + " is used twice in the same direction: the triangles are not consistently oriented";
    }
  return std::nullopt;
}

}  // namespace pbd
