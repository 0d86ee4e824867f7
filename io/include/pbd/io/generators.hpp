#pragma once
/// \file generators.hpp
/// Procedural bodies added to a world: the hanging cloth and the rope. Each generator takes the world as `Target`:
/// World<float>, World<double> or DescriptionBuilder (a scene's description; it computes as World<double>).
#include "pbd/world.hpp"

#include <array>
#include <optional>
#include <vector>

namespace pbd {

/// Where a generated body landed in the world.
struct Body {
  Index first_particle = 0;                    ///< index of its first particle
  Index num_particles = 0;                     ///< number of consecutive particles
  std::vector<std::array<Index, 3>> triangles;  ///< its surface triangles (world particle indices), if any
};

/// Which cloth particles are pinned (inverse mass 0).
enum class ClothPin { none, corners, edge };

/// An N×N particle grid in the plane z = origin.z, spanning [origin.x, origin.x + size] × [origin.y, origin.y + size],
/// each quad split into two triangles along the same diagonal.
struct ClothOptions {
  int resolution = 30;                        ///< N ≥ 2 particles per side
  double size = 1.0;                          ///< side length in metres, > 0
  double mass = 1.0;                          ///< total mass in kg, > 0, spread evenly
  std::array<double, 3> origin{0.0, 0.0, 1.0};  ///< corner of particle 0
  ClothPin pin = ClothPin::corners;           ///< corners: the two corners of the edge y = origin.y + size
};

/// Adds a cloth; with `stretch_set`, a stretch constraint on every unique triangle edge (rows, columns, diagonals,
/// in that order). Particle (i, j) is first_particle + j·N + i.
template <class Target> Body add_cloth(Target& world, const ClothOptions& options, std::optional<Index> stretch_set);

/// M particles on a straight line from `origin` along `direction`, the first one pinned.
struct RopeOptions {
  int particles = 20;                             ///< M ≥ 2
  double length = 1.0;                            ///< rest length in metres, > 0
  double mass = 1.0;                              ///< mass of each particle but the last, kg, > 0
  double end_mass = 1.0;                          ///< mass of the last particle, kg, > 0 (e.g. 1000× for the hard case)
  std::array<double, 3> origin{0.0, 0.0, 1.0};    ///< position of the pinned first particle
  std::array<double, 3> direction{1.0, 0.0, 0.0};  ///< direction of the rope, non-zero
};

/// Adds a rope; with `stretch_set`, a stretch constraint between consecutive particles.
template <class Target> Body add_rope(Target& world, const RopeOptions& options, std::optional<Index> stretch_set);

}  // namespace pbd
