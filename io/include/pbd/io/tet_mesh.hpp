#pragma once
/// \file tet_mesh.hpp
/// Tetrahedral meshes: the volumetric bodies' input (read from Gmsh or TetGen files, made from a closed OBJ surface
/// by TetGen, or generated), their checks and their boundary surface.
#include "pbd/types.hpp"

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace pbd {

/// A tetrahedral mesh with welded vertices. Every tet is positively oriented: det[p1 − p0, p2 − p0, p3 − p0] > 0
/// (p3 on the side of the face (p0, p1, p2) its normal (p1 − p0) × (p2 − p0) points to).
struct TetMesh {
  Matrix3X<double> positions;              ///< 3×V vertex positions
  std::vector<std::array<Index, 4>> tets;  ///< vertex indices of each tet
  /// Number of vertices.
  Index num_vertices() const { return Index(positions.cols()); }
};

/// Signed volume of the tet (p0, p1, p2, p3): det[p1 − p0, p2 − p0, p3 − p0] / 6, positive when positively oriented.
double signed_tet_volume(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2,
                         const Vec3<double>& p3);

/// Throws pbd::Error, its message starting with `source` (a file name or a generator), unless every tet names four
/// distinct vertices in range and is positively oriented and not degenerate: 6V > 1e-9 · (its longest edge)³, so
/// that a sliver whose volume is rounding noise is refused with the inverted ones. Names the first bad tet (its
/// index from 0) and, for an inverted or degenerate one, its signed volume. Also refuses a mesh without tets or with
/// a non-finite position.
void check_tet_mesh(const TetMesh& mesh, const std::string& source);

/// The boundary: every face that belongs to exactly one tet, wound counter-clockwise seen from outside (so a closed
/// surface of positive volume, closed_mesh.hpp), in the order of the tets and, within a tet, faces opposite p3, p2,
/// p1, p0. Vertex indices are the mesh's own (interior vertices are simply not named).
std::vector<std::array<Index, 3>> tet_mesh_surface(const TetMesh& mesh);

/// A box of cells[0] × cells[1] × cells[2] cubes spanning [0, size[0]] × [0, size[1]] × [0, size[2]], each cube cut
/// into 6 tets around its diagonal from its lowest to its highest corner (the Kuhn subdivision: neighbouring cubes'
/// cuts match, so the mesh is conforming). Vertex (i, j, k) is (k·(ny + 1) + j)·(nx + 1) + i with n = cells.
/// Throws pbd::Error unless every cell count is ≥ 1 and every size > 0 and finite.
TetMesh tet_box_mesh(const std::array<int, 3>& cells, const std::array<double, 3>& size);

/// The mesh with its vertices renumbered in recursive coordinate bisection order and its tets sorted by their
/// smallest new vertex (ties: in their order). The vertices of each part (at first, all) are split at the median of
/// the part's bounding box's longest side, lower half first, until a part has at most 32 vertices, which then keep
/// their order. So vertices close in space get close indices at every scale: a block of the block solver, or a
/// thread's share of the particles, is a few ranges of memory rather than particles spread over all of it (two
/// threads writing particles that share a cache line stall each other). A tet keeps its corners' order, so its
/// orientation. Deterministic: a strict order (coordinate, then index) decides every split. new_index (when not
/// null) receives each old vertex's new index. Throws as check_tet_mesh (source "spatially_ordered").
TetMesh spatially_ordered(const TetMesh& mesh, std::vector<Index>* new_index = nullptr);

}  // namespace pbd
