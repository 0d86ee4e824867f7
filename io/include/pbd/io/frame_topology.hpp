#pragma once
/// \file frame_topology.hpp
/// What a frame draws, body by body: each body's run of particles, its surface triangles and its line segments.
#include "pbd/io/scene.hpp"
#include "pbd/world.hpp"

#include <array>
#include <string>
#include <vector>

namespace pbd {

/// One body of a frame: consecutive particles with the triangles and lines between them (world particle indices).
struct FrameBody {
  std::string name;                             ///< its name: the OBJ object name (e.g. "rope_0")
  Index first_particle = 0;                     ///< world index of its first particle
  Index num_particles = 0;                      ///< number of consecutive particles it has
  std::vector<std::array<Index, 3>> triangles;  ///< surface triangles, each with all three corners in the body
  std::vector<std::array<Index, 2>> lines;      ///< segments of ropes and particle chains, both ends in the body
  /// Per line, the stretch constraint it draws: an index into world.constraints<StretchConstraint<Real>>().
  std::vector<Index> line_stretch;
};

/// What a frame draws: bodies in particle order that together hold every particle of the world once (body k starts
/// where body k − 1 ends), each with its triangles and lines.
struct FrameTopology {
  std::vector<FrameBody> bodies;  ///< the bodies, in particle order
};

/// The bodies of a scene (scene.bodies) with their triangles, and as lines every stretch constraint whose two
/// particles are on no triangle and in the same body (a constraint joining two bodies is not drawn). Throws
/// pbd::Error unless the bodies hold every particle of `world` once, in order, and every triangle lies in its body.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<SceneBody>& bodies);

/// One body named "world" holding every particle, with `triangles` and as lines every stretch constraint whose two
/// particles are both on no triangle (a world built without a scene). Throws pbd::Error naming the triangle whose
/// particle index is out of range.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles);

/// Throws pbd::Error naming `what` unless `topology` fits a world of `num_particles` particles: its bodies hold every
/// particle once, in order, each triangle and line lies in its body, and there is one line_stretch per line.
void check_frame_topology(const FrameTopology& topology, Index num_particles, const std::string& what);

}  // namespace pbd
