#pragma once
/// \file shape_match_clusters.hpp
/// The clusters of shape matching (pbd/constraints/shape_match.hpp) on a tet mesh: one per vertex, the vertex and
/// its 7 nearest neighbours.
#include "pbd/io/tet_mesh.hpp"
#include "pbd/types.hpp"

#include <array>
#include <vector>

namespace pbd {

/// One cluster per vertex v, in vertex order: v, then its 7 nearest other vertices by rest distance (nearest first,
/// ties by the smaller index), chosen among its neighbours: the vertices that share a tet with v (its 1-ring), or
/// when those are fewer than 7, the 1- and 2-rings together (and further rings while still fewer). Neighbours
/// through the tets rather than plain nearest points, so that a cluster never spans a gap between two parts of a
/// body that are close but not joined (a slit, the two arms of a bent bar). A pure function of the mesh.
/// Throws pbd::Error ("shape_match_clusters: ...") when the mesh has fewer than 8 vertices, fails check_tet_mesh,
/// or a vertex is joined through the tets to fewer than 7 others (a small separate part, or a vertex in no tet).
std::vector<std::array<Index, 8>> shape_match_clusters(const TetMesh& mesh);

}  // namespace pbd
