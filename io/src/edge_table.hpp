#pragma once
// The undirected edges of a triangle list in the order the triangles first name them (private to pbd::io):
// mesh_edges, mesh_bending_pairs and add_mesh_constraints read their edges and pairs from it.
#include "pbd/types.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace pbd::detail {

/// Half-edge h = 3t + k of triangle t runs from t[k] to t[(k + 1) % 3]; its opposite corner is t[(k + 2) % 3].
inline Index half_edge_from(std::span<const std::array<Index, 3>> tris, std::size_t h) { return tris[h / 3][h % 3]; }
inline Index half_edge_to(std::span<const std::array<Index, 3>> tris, std::size_t h) { return tris[h / 3][(h + 1) % 3]; }
inline Index half_edge_opposite(std::span<const std::array<Index, 3>> tris, std::size_t h) {
  return tris[h / 3][(h + 2) % 3];
}

/// Per undirected edge, in first-appearance order: its first two half-edges and how many triangles name it.
struct EdgeTable {
  std::vector<std::uint32_t> first;   ///< the half-edge that first names the edge (its direction is the edge's)
  std::vector<std::uint32_t> second;  ///< the next half-edge on it, where count ≥ 2
  std::vector<std::uint8_t> count;    ///< half-edges on the edge, counted up to 3
  std::size_t size() const { return first.size(); }  ///< number of edges
  /// Edge e as (first, second) endpoint, as its first triangle names it.
  std::array<Index, 2> edge(std::span<const std::array<Index, 3>> tris, std::size_t e) const {
    return {half_edge_from(tris, first[e]), half_edge_to(tris, first[e])};
  }
  /// Edge e's bending pair (p1, p2 the edge, p3, p4 the corners opposite its first and second half-edge).
  std::array<Index, 4> pair(std::span<const std::array<Index, 3>> tris, std::size_t e) const {
    return {half_edge_from(tris, first[e]), half_edge_to(tris, first[e]), half_edge_opposite(tris, first[e]),
            half_edge_opposite(tris, second[e])};
  }
};

/// The edge table of `triangles`: half-edges bucketed by smaller endpoint (counting sort, so triangle order is
/// kept), matched by larger endpoint inside each bucket (a hub's bucket is sorted). Linear, no hashing.
EdgeTable edge_table(std::span<const std::array<Index, 3>> triangles);

}  // namespace pbd::detail
