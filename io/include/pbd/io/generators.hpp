#pragma once
/// \file generators.hpp
/// Procedural bodies added to a world: the hanging cloth, the rope and a lattice of loose grains. Each generator takes
/// the world as `Target`:
/// World<float>, World<double> or DescriptionBuilder (a scene's description; it computes as World<double>).
#include "pbd/world.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace pbd {

/// Where a generated body landed in the world.
struct Body {
  Index first_particle = 0;                    ///< index of its first particle
  Index num_particles = 0;                     ///< number of consecutive particles
  std::vector<std::array<Index, 3>> triangles;  ///< its surface triangles (world particle indices), if any
};

/// One edge of a generated body between particles a and b: a stretch constraint in `set`, or a fiber (rest length
/// measured, no plastic strain) when the set has a stress–strain curve (docs/fibers.md). Returns its index among
/// its type.
template <class Target> Index add_edge(Target& world, Index a, Index b, Index set) {
  using Real = typename Target::Positions::Scalar;
  if (world.constraint_sets()[set].mode == StiffnessMode::material)
    return world.add(FiberConstraint<Real>{{a, b}, set, Real(0), Real(0)}, FieldMask(2));
  return world.add_stretch(a, b, set);
}

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
/// in that order): a fiber when the set has a stress–strain curve (add_edge), and then its triangles are a surface
/// that tears along them (World::add_surface). Particle (i, j) is first_particle + j·N + i.
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

/// nx × ny × nz loose particles (grains: no constraints) on a cubic lattice, each moved off its lattice point by a
/// jitter drawn from a fixed integer generator (splitmix64 of `seed`): the same options give the same positions,
/// bit for bit, on every platform and in either precision's cast. Lattice point (i, j, k) is
/// origin + ((i − (nx − 1)/2)·spacing, (j − (ny − 1)/2)·spacing, k·spacing): `origin` is the centre of the bottom
/// layer, before the jitter. Each coordinate is then moved by u·jitter·spacing with u uniform in [−1, 1), three
/// draws per particle in the order x, y, z. Particle (i, j, k) is first_particle + (k·ny + j)·nx + i.
struct GrainsOptions {
  std::array<int, 3> count{1, 1, 1};            ///< nx, ny, nz ≥ 1 particles along x, y, z
  double spacing = 0.1;                         ///< lattice spacing in metres, > 0
  std::array<double, 3> origin{0.0, 0.0, 0.0};  ///< centre of the bottom layer's lattice points, m
  double jitter = 0.1;                          ///< largest move per coordinate as a fraction of spacing, in [0, 0.5)
  std::uint64_t seed = 1;                       ///< seed of the jitter
  double mass = 1.0;                            ///< mass of each particle, kg, > 0
  std::array<double, 3> velocity{0.0, 0.0, 0.0};  ///< initial velocity of every particle, m/s
};

/// Adds the grains (particles only: give them a contact body to make them touch). A jitter under half the spacing
/// keeps every particle inside its own lattice cell's neighbourhood, so no two particles coincide.
template <class Target> Body add_grains(Target& world, const GrainsOptions& options);

/// The jitter generator of add_grains: splitmix64 (Steele, Lea & Flood 2014), advancing `state`.
std::uint64_t splitmix64(std::uint64_t& state);

}  // namespace pbd
