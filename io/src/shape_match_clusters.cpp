#include "pbd/io/shape_match_clusters.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>

namespace pbd {
namespace {

using detail::message;

constexpr const char* kCall = "shape_match_clusters";

// Each vertex's 1-ring (the other vertices of its tets), sorted, once each.
std::vector<std::vector<Index>> one_rings(const TetMesh& mesh) {
  std::vector<std::vector<Index>> ring(std::size_t(mesh.num_vertices()));
  for (const auto& t : mesh.tets)
    for (Index a : t)
      for (Index b : t)
        if (a != b) ring[a].push_back(b);
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  return ring;
}

// The neighbours v's cluster is chosen from: its rings, one after the other, until there are at least 7. `mark`
// (one entry per vertex) says which vertices are taken: stamp v + 1, so it need not be cleared between vertices.
std::vector<Index> candidates(Index v, const std::vector<std::vector<Index>>& ring, std::vector<Index>& mark) {
  const Index stamp = v + 1;
  mark[v] = stamp;
  std::vector<Index> found, frontier{v};
  while (found.size() < 7) {
    std::vector<Index> next;
    for (Index f : frontier)
      for (Index n : ring[f])
        if (mark[n] != stamp) {
          mark[n] = stamp;
          next.push_back(n);
        }
    if (next.empty())
      throw Error(message(kCall, ": vertex ", v, " is joined through the tets to only ", found.size(),
                          " other vertices; a cluster needs 7"));
    found.insert(found.end(), next.begin(), next.end());
    frontier = std::move(next);
  }
  return found;
}

}  // namespace

std::vector<std::array<Index, 8>> shape_match_clusters(const TetMesh& mesh) {
  if (mesh.num_vertices() < 8)
    throw Error(message(kCall, ": a cluster is 8 vertices; the mesh has ", mesh.num_vertices()));
  check_tet_mesh(mesh, kCall);
  const auto ring = one_rings(mesh);
  std::vector<Index> mark(std::size_t(mesh.num_vertices()), 0);
  std::vector<std::array<Index, 8>> clusters(std::size_t(mesh.num_vertices()));
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    std::vector<std::pair<double, Index>> near;
    for (Index n : candidates(v, ring, mark))
      near.emplace_back((mesh.positions.col(n) - mesh.positions.col(v)).squaredNorm(), n);
    std::partial_sort(near.begin(), near.begin() + 7, near.end());  // by distance, then index
    clusters[v][0] = v;
    for (int i = 0; i < 7; ++i) clusters[v][std::size_t(i) + 1] = near[std::size_t(i)].second;
  }
  return clusters;
}

}  // namespace pbd
