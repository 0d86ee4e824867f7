#pragma once
/// \file closed_mesh.hpp
/// Whether triangles bound a volume: the topology check World::add_volume runs (and pbd::io before it adds a mesh).
#include "pbd/constraints/volume.hpp"
#include "pbd/types.hpp"

#include <array>
#include <optional>
#include <span>
#include <string>

namespace pbd {

/// Why `triangles` cannot bound a volume, or nothing if they can: every directed edge (a, b) must appear exactly
/// once and its reverse (b, a) exactly once (closed, manifold, consistently oriented). Names the first bad edge in
/// triangle order, e.g. "edge (4, 7) belongs to one triangle only: the mesh is open". Also rejects an index ≥
/// `num_vertices` and a triangle naming a vertex twice. The message numbers vertices and triangles from
/// `first_number` (1 for a mesh from an OBJ file, whose vertices count from 1).
std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices,
                                              Index first_number = 0);

/// The checks of a volume constraint over `triangles` of the particles at `x` (closed, manifold and oriented; pressure
/// schedule finite and positive; not flat or inside out unless `rest` is given) and its rest volume in the 6V unit
/// of constraints/volume.hpp (`rest`, or the current one). Throws pbd::Error prefixed by `what`. World::add_volume and
/// pbd::io's scene reader both check volumes through it.
template <class Real>
Real checked_rest_volume(std::span<const std::array<Index, 3>> triangles, const Matrix3X<Real>& x,
                         const PressureSchedule& pressure, std::optional<Real> rest, const std::string& what);

}  // namespace pbd
