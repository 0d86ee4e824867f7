#pragma once
/// \file mesh_body.hpp
/// A triangle mesh added to a world as a body, with the constraint sets generated from its topology on request. The
/// world is a `Target` as in generators.hpp: World<float>, World<double> or DescriptionBuilder.
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh.hpp"

#include <span>

namespace pbd {

/// Which constraints to generate from a mesh, each into the given constraint set (none when empty).
struct MeshConstraintSets {
  std::optional<Index> stretch;  ///< stretch on every unique edge
  std::optional<Index> bending;  ///< dihedral bending on every interior edge (shared by exactly two triangles)
  std::optional<Index> area;     ///< area on every triangle
  std::optional<Index> volume;   ///< one volume constraint on the whole mesh (must be closed and oriented)
  PressureSchedule pressure;     ///< the volume target's schedule
};

/// Where and how heavy the mesh's particles are.
struct MeshBodyOptions {
  double scale = 1.0;                           ///< uniform scale applied to the mesh's positions, > 0
  std::array<double, 3> origin{0.0, 0.0, 0.0};  ///< then translated by this
  double mass = 1.0;                            ///< total mass in kg, > 0, spread evenly over the vertices
  std::vector<Index> pinned;                    ///< mesh vertex indices to pin
};

/// Adds `triangles` (world particle indices)' constraints of the requested kinds, in the order stretch, bending,
/// area, volume. Throws pbd::Error (from World::add_*) naming the first bad constraint.
template <class Target>
void add_mesh_constraints(Target& world, std::span<const std::array<Index, 3>> triangles,
                          const MeshConstraintSets& sets);

/// Adds the mesh's vertices as particles and its constraints; checks the mesh first (indices, and closedness if a
/// volume is asked for) so that a bad mesh adds nothing. Returns the body with its triangles in world indices.
template <class Target>
Body add_mesh(Target& world, const TriangleMesh& mesh, const MeshBodyOptions& options,
              const MeshConstraintSets& sets);

}  // namespace pbd
