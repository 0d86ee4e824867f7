#pragma once
/// \file frame_topology.hpp
/// What a frame draws, body by body: each body's run of particles, its surface triangles, its line segments and its
/// tets.
#include "pbd/io/scene.hpp"
#include "pbd/world.hpp"

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pbd {

/// The rest shape of a drawn tet, copied from its constraints: what a frame measures the tet's deformation against.
struct FrameTetRest {
  double volume = 0.0;  ///< rest volume V0 > 0, m³: its Neo-Hookean constraint's, else its tet volume constraint's
  /// Dm⁻¹ (1/m), the inverse of its rest edge matrix [p1 − p0, p2 − p0, p3 − p0], from its Neo-Hookean constraint;
  /// none for a tet with only a volume constraint (which has no rest shape, only a rest volume).
  std::optional<Eigen::Matrix3d> inverse_rest;
};

/// One body of a frame: consecutive particles with the triangles, lines and tets between them (world particle
/// indices).
struct FrameBody {
  std::string name;                             ///< its name: the OBJ object name (e.g. "rope_0")
  Index first_particle = 0;                     ///< world index of its first particle
  Index num_particles = 0;                      ///< number of consecutive particles it has
  std::vector<std::array<Index, 3>> triangles;  ///< surface triangles, each with all three corners in the body
  std::vector<std::array<Index, 2>> lines;      ///< segments of ropes and particle chains, both ends in the body
  /// Per line, the stretch constraint it draws: an index into world.constraints<StretchConstraint<Real>>().
  std::vector<Index> line_stretch;
  std::vector<std::array<Index, 2>> fiber_lines;  ///< fibers (constraints/fiber.hpp) drawn as segments, like lines
  /// Per fiber line, the fiber it draws: an index into world.constraints<FiberConstraint<Real>>().
  std::vector<Index> line_fiber;
  std::vector<std::array<Index, 4>> tets;  ///< tets (corners p0..p3 of their constraint), all four in the body
  std::vector<FrameTetRest> tet_rest;      ///< per tet, its rest shape
  /// Per tet, the tet fiber on its four corners (an index into world.constraints<TetFiberConstraint<Real>>()), or
  /// kNoTetFiber; empty when the world has no tet fibers.
  std::vector<Index> tet_fiber;
  static constexpr Index kNoTetFiber = ~Index(0);  ///< a tet without a tet fiber
};

/// What a frame draws: bodies in particle order that together hold every particle of the world once (body k starts
/// where body k − 1 ends), each with its triangles, lines and tets.
struct FrameTopology {
  std::vector<FrameBody> bodies;  ///< the bodies, in particle order
};

/// The bodies of a scene (scene.bodies) with their triangles, as lines every stretch constraint whose two particles
/// are on no triangle and in the same body (a constraint joining two bodies is not drawn), as fiber lines every such
/// fiber (so a topology made after fibers broke draws only the ones left), and as tets every tet
/// constraint's four particles when they are in the same body. Throws pbd::Error unless the bodies hold every
/// particle of `world` once, in order, and every triangle lies in its body.
///
/// Tets come from tet constraints the way lines come from stretch constraints: first each Neo-Hookean constraint's
/// corners (with its rest volume and Dm⁻¹), then each tet volume constraint's (its rest volume, no Dm⁻¹) whose four
/// particles no tet before it has. So a tet is drawn once however many constraints it has (the same four particles in
/// any order), in the order of its first constraint, with the corner order of that constraint.
///
/// A body whose triangles are a surface that tears (SceneBody::surface) draws them as they are now; once a tear has
/// added particles (past every body), the frame is one body "world" holding every particle and every triangle.
/// A body with tets draws as its triangles the boundary of the tets it has now (tet_mesh_surface): the same as its
/// own until fibers along its edges tear some tets away (constraints/traits.hpp: breaks_with_fibers). Its lines and
/// fiber lines with both ends on its tets (a tet body's edges) are drawn as the tets, not as lines.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<SceneBody>& bodies);

/// One body named "world" holding every particle, with `triangles`, as lines every stretch constraint whose two
/// particles are both on no triangle, and the tets of every tet constraint (as above): a world built without a
/// scene. Throws pbd::Error naming the triangle whose particle index is out of range.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles);

/// Throws pbd::Error naming `what` unless `topology` fits a world of `num_particles` particles: its bodies hold every
/// particle once, in order, each triangle, line and tet lies in its body, and there is one line_stretch per line, one
/// line_fiber per fiber line, one tet_rest per tet and one tet_fiber per tet or none.
void check_frame_topology(const FrameTopology& topology, Index num_particles, const std::string& what);

}  // namespace pbd
