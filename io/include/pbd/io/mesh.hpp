#pragma once
/// \file mesh.hpp
/// Triangle meshes and the topology the constraints are built from: unique edges and bending pairs (whether a mesh
/// is closed is the engine's check, pbd/closed_mesh.hpp).
#include "pbd/types.hpp"

#include <Eigen/Geometry>
#include <array>
#include <span>
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

/// The edges and the bending pairs of a mesh (what mesh_edges and mesh_bending_pairs give), found together.
struct MeshTopology {
  std::vector<std::array<Index, 2>> edges;          ///< as mesh_edges
  std::vector<std::array<Index, 4>> bending_pairs;  ///< as mesh_bending_pairs
};

/// mesh_edges and mesh_bending_pairs of `triangles` in one pass over them.
MeshTopology mesh_topology(std::span<const std::array<Index, 3>> triangles);

/// Every undirected edge once, as (first, second) in the order the triangles first name it.
std::vector<std::array<Index, 2>> mesh_edges(std::span<const std::array<Index, 3>> triangles);

/// One (p1, p2, p3, p4) per interior edge, i.e. an edge on exactly two triangles: p1–p2 the edge, p3 and p4 the
/// corners opposite it (the layout of BendingConstraint). Edges on one triangle or on three or more get none.
std::vector<std::array<Index, 4>> mesh_bending_pairs(std::span<const std::array<Index, 3>> triangles);

}  // namespace pbd
