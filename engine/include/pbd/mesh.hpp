#pragma once
/// \file mesh.hpp
/// Triangle meshes and the topology the constraints are built from: unique edges, bending pairs, closedness.
#include "pbd/types.hpp"

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pbd {

/// A triangle mesh with welded vertices (one position per index); a closed mesh winds counter-clockwise seen from
/// outside, so its volume is positive.
struct TriangleMesh {
  Matrix3X<double> positions;                   ///< 3×V vertex positions
  std::vector<std::array<Index, 3>> triangles;  ///< vertex indices of each triangle
  /// Number of vertices.
  Index num_vertices() const { return Index(positions.cols()); }
};

/// Every undirected edge once, as (first, second) in the order the triangles first name it.
std::vector<std::array<Index, 2>> mesh_edges(std::span<const std::array<Index, 3>> triangles);

/// One (p1, p2, p3, p4) per interior edge, i.e. an edge on exactly two triangles: p1–p2 the edge, p3 and p4 the
/// corners opposite it (the layout of BendingConstraint). Edges on one triangle or on three or more get none.
std::vector<std::array<Index, 4>> mesh_bending_pairs(std::span<const std::array<Index, 3>> triangles);

/// Why `triangles` cannot bound a volume, or nothing if they can: every directed edge (a, b) must appear exactly
/// once and its reverse (b, a) exactly once (closed, manifold, consistently oriented). Names the first bad edge in
/// triangle order, e.g. "edge (4, 7) belongs to one triangle only: the mesh is open". Also rejects an index ≥
/// `num_vertices` and a triangle naming a vertex twice.
std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices);

}  // namespace pbd
