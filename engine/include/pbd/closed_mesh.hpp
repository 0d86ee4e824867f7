#pragma once
/// \file closed_mesh.hpp
/// Whether triangles bound a volume: the topology check World::add_volume runs (and pbd::io before it adds a mesh).
#include "pbd/types.hpp"

#include <array>
#include <optional>
#include <span>
#include <string>

namespace pbd {

/// Why `triangles` cannot bound a volume, or nothing if they can: every directed edge (a, b) must appear exactly
/// once and its reverse (b, a) exactly once (closed, manifold, consistently oriented). Names the first bad edge in
/// triangle order, e.g. "edge (4, 7) belongs to one triangle only: the mesh is open". Also rejects an index ≥
/// `num_vertices` and a triangle naming a vertex twice.
std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices);

}  // namespace pbd
