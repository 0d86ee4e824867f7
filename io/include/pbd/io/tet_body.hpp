#pragma once
/// \file tet_body.hpp
/// A tetrahedral mesh added to a world as a volumetric body: its particles with masses lumped from a density, its
/// boundary surface (for frames and contacts) and the tet constraints asked for. The world is a `Target` as in
/// generators.hpp: World<float>, World<double> or DescriptionBuilder.
#include "pbd/io/generators.hpp"
#include "pbd/io/tet_mesh.hpp"

#include <optional>
#include <vector>

namespace pbd {

/// Which constraints to make on every tet, each into the given constraint set (none when empty).
struct TetConstraintSets {
  std::optional<Index> volume;       ///< a tet volume constraint (constraints/tet_volume.hpp)
  std::optional<Index> neo_hookean;  ///< a Neo-Hookean tet (constraints/neo_hookean.hpp); the set's compliance is 1/μ
  double ratio = 0.0;                ///< μ/λ of the Neo-Hookean tets (NeoHookeanMaterial::ratio)
  std::optional<Index> shape_match;  ///< shape matching on every vertex's cluster (shape_match_clusters.hpp)
  double beta = 0.0;                 ///< its mode: 0 rigid, up to 1 linear (constraints/shape_match.hpp)
  /// A constraint on every edge of the tets (add_edge: a fiber when the set has a stress–strain curve, else a
  /// stretch constraint). Fibers tear the tets they run along when they break (traits.hpp: breaks_with_fibers).
  std::optional<Index> stretch;
  /// A tet fiber on every tet (constraints/tet_fiber.hpp), along `direction` in the mesh's frame: with a curve in
  /// the set (its stiffness E in Pa) they stiffen, yield and break, and a tet whose fibers break leaves with them.
  std::optional<Index> fibers;
  std::array<double, 3> direction{1.0, 0.0, 0.0};  ///< the tet fibers' direction a0 (not zero)
};

/// Where the body goes and how heavy it is.
struct TetBodyOptions {
  double scale = 1.0;                           ///< uniform scale applied to the mesh's positions, > 0
  std::array<double, 3> origin{0.0, 0.0, 0.0};  ///< then translated by this
  double density = 1000.0;                      ///< kg/m³, > 0: each tet gives ρV/4 to each of its corners
  std::vector<Index> pinned;                    ///< mesh vertex indices to pin
};

/// The mesh vertices on the face of the mesh's bounding box where coordinate `axis` (0, 1, 2) is smallest (`max`
/// false) or largest: within 1e-9 of the box's size along that axis. A bar clamped at one end pins these.
std::vector<Index> tet_mesh_face_vertices(const TetMesh& mesh, int axis, bool max);

/// Adds the mesh's vertices as particles and a constraint of each requested kind on every tet (volume first, then
/// Neo-Hookean, each in tet order), then a shape-matching cluster per vertex if asked, then one on each edge (edges
/// in increasing order of their two vertices) if asked, then a tet fiber on every tet if asked. Checks first (check_tet_mesh with source "add_tet_body", every vertex on some
/// tet, options, pinned indices), so a bad mesh adds nothing. Returns the body with its boundary triangles
/// (tet_mesh_surface) in world indices.
template <class Target>
Body add_tet_body(Target& world, const TetMesh& mesh, const TetBodyOptions& options, const TetConstraintSets& sets);

}  // namespace pbd
